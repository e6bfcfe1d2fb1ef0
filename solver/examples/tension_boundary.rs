//! The microplane concrete with a tensile boundary on every plane (`tension_boundary.rs`) at one
//! material point (h = 50 mm, quasi-static), against the calibration's targets and Kupfer's
//! tension-compression envelope: uniaxial tension (peak, strain there, fracture energy on the
//! crack band's path), uniaxial and equal-biaxial compression, tension under a held lateral
//! compression, and a crack opened to `w_cr` in x and then compressed in y.
//!
//! `cargo run --release -p impact-solver --example tension_boundary -- MATERIAL_FILE F0_MPA EPS_F THETA`

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{Control, MaterialPoint};
use impact_solver::material::microplane::experiments::{
    bonded_tension, equal_biaxial_compression, tension_under_lateral_stress, uniaxial_compression,
};
use impact_solver::material::microplane::{MicroplaneConcrete, TensionBoundary};
use impact_solver::material::read_microplane_file;

const FT: f64 = 2.70e6;
const FC: f64 = 45.0e6;
const H: f64 = 0.05;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| "cases/materials/thesis-concrete.yaml".into());
    let number = |i: usize, default: f64| args.get(i).map_or(default, |a| a.parse().unwrap());
    let mut parameters = read_microplane_file(std::path::Path::new(&file)).unwrap();
    parameters.tension_boundary = Some(TensionBoundary {
        strength: number(2, 2.7) * 1e6,
        softening_strain: number(3, 6e-4),
        strain_weight: number(4, 0.0),
    });
    let model = MicroplaneConcrete::new(parameters).unwrap();
    let (_, t) = bonded_tension(&model, H, 1e-6).unwrap();
    println!(
        "tension: peak {:.3} MPa at {:.2e}, GF {:.1} N/m (bonded, h 50 mm)",
        t.peak_stress * 1e-6,
        t.peak_strain,
        t.fracture_energy
    );
    for h in [0.025, 0.1] {
        let (_, t) = bonded_tension(&model, h, 1e-6).unwrap();
        println!(
            "  h {:.0} mm: peak {:.3} MPa, GF {:.1} N/m",
            h * 1e3,
            t.peak_stress * 1e-6,
            t.fracture_energy
        );
    }
    match uniaxial_compression(&model, H, 1e-6, 6e-3, 600) {
        Ok((_, c)) => println!(
            "compression: peak {:.1} MPa at {:.2e}, largest Poisson ratio after it {:.2}",
            c.peak_stress * 1e-6,
            c.peak_strain,
            c.largest_poisson_after_peak
        ),
        Err(e) => println!("compression: {e}"),
    }
    match equal_biaxial_compression(&model, H, 6e-3, 600) {
        Ok((_, peak)) => println!("equal biaxial: {:.1} MPa", peak * 1e-6),
        Err(e) => println!("equal biaxial: {e}"),
    }
    let uniaxial = t.peak_stress;
    println!("lateral   peak/uniaxial  Kupfer-Gerstle");
    for k in [0.5, 1.0, 2.0, 5.0] {
        let lateral = -k * FT;
        match tension_under_lateral_stress(&model, H, lateral, 8e-4, 400) {
            Ok(curve) => println!(
                "{:>5.1} f_t  {:>6.3}{}        {:.3}",
                -k,
                curve.peak().stress[0] / uniaxial,
                if curve.peak_passed() { "  " } else { ">=" },
                1.0 + 0.8 * lateral / FC
            ),
            Err(e) => println!("{:>5.1} f_t  {e}", -k),
        }
    }
    // A crack opened in x to w_cr = 0.2 mm (eps 4e-3 at 50 mm) at sigma_yy = sigma_zz = 0, then
    // y compressed with x held: the lateral strength of the cracked point against that of a
    // virgin point on the same y path.
    let crushing = |open: bool| {
        let mut point = MaterialPoint::new(&model, H).unwrap();
        let dt = 1.0;
        let mut exx = 0.0;
        if open {
            for i in 1..=400 {
                exx = 4e-3 * i as f64 / 400.0;
                let c = [
                    Control::Strain(exx),
                    Control::Stress(0.0),
                    Control::Stress(0.0),
                    Control::Strain(0.0),
                    Control::Strain(0.0),
                    Control::Strain(0.0),
                ];
                if point.mixed_step_subdivided(&c, dt).is_err() {
                    println!("  (opening stopped at {exx:.2e})");
                    break;
                }
            }
        }
        let start = point.strain[1];
        let mut peak: f64 = 0.0;
        for i in 1..=600 {
            let c = [
                Control::Strain(exx),
                Control::Strain(start - 6e-3 * i as f64 / 600.0),
                Control::Stress(0.0),
                Control::Strain(0.0),
                Control::Strain(0.0),
                Control::Strain(0.0),
            ];
            match point.mixed_step_subdivided(&c, dt) {
                Ok(p) => peak = peak.max(-p.stress[1]),
                Err(_) => break,
            }
        }
        peak
    };
    let (virgin, cracked) = (crushing(false), crushing(true));
    println!(
        "compression along a crack: {:.1} MPa against {:.1} uncracked ({:.2})",
        cracked * 1e-6,
        virgin * 1e-6,
        cracked / virgin
    );
    let _ = FC;
}
