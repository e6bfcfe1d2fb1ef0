//! The microplane concrete with a tensile boundary on every plane (`tension_boundary.rs`) at one
//! material point (h = 50 mm, quasi-static), against the calibration's targets and Kupfer's
//! tension-compression envelope: uniaxial tension (peak, strain there, fracture energy on the
//! crack band's path), uniaxial and equal-biaxial compression, tension under a held lateral
//! compression, and a crack opened to `w_cr` in x on the crack band's path and then compressed
//! in y with the other strains held (`crack_compression.rs`); and, along the crack band's path at
//! 25, 50 and 100 mm, the strains at which the planes crack. `FRICTION` sets `crack_friction`,
//! the shear boundary's Coulomb coefficient on the compressed planes (0 or absent: none).
//!
//! `cargo run --release -p impact-solver --example tension_boundary -- MATERIAL_FILE F0_MPA EPS_F THETA [FRICTION [ONSET [mc2010]]]`

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::crack_compression::{
    compression_along_crack, kupfer_gerstle, lateral_tension_ratio,
};
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::experiments::{
    bonded_tension, equal_biaxial_compression, tension_rate_sweep, uniaxial_compression,
    QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{
    state, BoundaryShape, MicroplaneConcrete, TensionBoundary,
};
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
        onset_strain: number(6, 0.0),
        shape: match args.get(7).map(String::as_str) {
            Some("mc2010") => BoundaryShape::Mc2010,
            _ => BoundaryShape::Exponential,
        },
    });
    let friction = number(5, 0.0);
    if friction > 0.0 {
        parameters.crack_friction = Some(friction);
    }
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
    for h in [0.025, 0.05, 0.1] {
        cracking_along_the_band(&model, h);
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
    // The rate effect: the uniaxial tensile peak at 1 and 10 /s over the quasi-static one,
    // against the rate factor at the peak (the boundary's f0 is scaled by it).
    if let Ok(sweep) = tension_rate_sweep(&model, H, &[QUASI_STATIC_RATE, 1.0, 10.0]) {
        let (_, slow, f_slow) = sweep[0];
        for (rate, r, f) in &sweep[1..] {
            println!(
                "rate {rate:>4} /s: peak {:.3} MPa, {:.3} of the quasi-static, rate factor {:.3}",
                r.peak_stress * 1e-6,
                r.peak_stress / slow.peak_stress,
                f / f_slow
            );
        }
    }
    let uniaxial = t.peak_stress;
    println!("lateral   peak/uniaxial  Kupfer-Gerstle");
    for k in [0.5, 1.0, 2.0, 5.0] {
        let lateral = -k * FT;
        match lateral_tension_ratio(&model, H, lateral, uniaxial, 8e-4) {
            Ok((ratio, passed)) => println!(
                "{:>5.1} f_t  {:>6.3}{}        {:.3}",
                -k,
                ratio,
                if passed { "  " } else { ">=" },
                kupfer_gerstle(lateral, FC)
            ),
            Err(e) => println!("{:>5.1} f_t  {e}", -k),
        }
    }
    // A crack opened in x to w_cr = 0.2 mm on the crack band's path, then y compressed with x
    // held: the lateral strength of the cracked point against that of a virgin point.
    match compression_along_crack(&model, H, 2e-4, 6e-3) {
        Ok(c) => println!(
            "compression along a crack (opened to {:.2e}): {:.1} MPa against {:.1} uncracked ({:.2})",
            c.opening_strain,
            c.cracked * 1e-6,
            c.virgin * 1e-6,
            c.ratio()
        ),
        Err(e) => println!("compression along a crack: {e}"),
    }
}

/// The planes' cracking along the crack band's path at size `h`: the path replayed on a point
/// whose planes' crack strains are read at every increment; printed where the weighted share of
/// cracked planes (a largest crack strain above zero, `crack_strain.rs`) first passes 25, 50, 75
/// and 95 %, with the strain and the stress over the peak there.
fn cracking_along_the_band(model: &MicroplaneConcrete, h: f64) {
    let (curve, t) = bonded_tension(model, h, 1e-6).unwrap();
    let mut point = MaterialPoint::new(model, h).unwrap();
    let planes = model.planes();
    let total: f64 = planes.iter().map(|p| p.weight).sum();
    let mut marks = vec![0.25, 0.5, 0.75, 0.95];
    let mut line = format!("  cracked planes at h {:.0} mm:", h * 1e3);
    let mut time = 0.0;
    for p in &curve.points {
        point.strain_step(p.strain, (p.time - time).max(1e-12));
        time = p.time;
        let cracked: f64 = planes
            .iter()
            .enumerate()
            .filter(|(i, _)| {
                let at = state::HEADER + i * state::PER_PLANE + state::D_POSITIVE;
                point.state.values[at] > 0.0
            })
            .map(|(_, plane)| plane.weight)
            .sum::<f64>()
            / total;
        while let Some(&mark) = marks.first().filter(|&&m| cracked >= m) {
            line += &format!(
                " {:.0} % at {:.2e} ({:.2} of peak)",
                mark * 100.0,
                p.strain[0],
                p.stress[0] / t.peak_stress
            );
            marks.remove(0);
        }
    }
    println!("{line}");
}
