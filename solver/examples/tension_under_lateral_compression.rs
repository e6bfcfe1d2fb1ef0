//! Issue 17 diagnostic: the tensile peak of one material point of the calibrated concrete
//! (h = 50 mm, quasi-static) under a lateral compression, beside Kupfer's tension-compression
//! envelope. The lateral stress `sigma_yy = -k f_t` is applied first (with `sigma_xx = sigma_zz
//! = 0`), then held while `E_xx` grows by 8e-4 (`sigma_zz = 0`, no shear:
//! `experiments::tension_under_lateral_stress`). A second set drives `E_yy = -r E_xx` instead.
//! Concrete's tensile strength falls under lateral compression (Kupfer & Gerstle 1973:
//! `sigma_1 = f_t (1 + 0.8 sigma_2 / f_c)`); the shipped thesis concrete's rises, that of
//! `thesis-concrete-tensile-relaxation.yaml` falls (docs/MICROPLANE.md, "Tension under lateral
//! compression").
//!
//! `cargo run --release -p impact-solver --example tension_under_lateral_compression [-- MATERIAL_FILE]`

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{Control, MaterialPoint, PathPoint};
use impact_solver::material::microplane::experiments::{tension_under_lateral_stress, Curve};
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;

/// Tensile and compressive strength of the thesis concrete (thesis 10.3, the calibration's
/// targets), the scales of the envelope.
const FT: f64 = 2.70e6;
const FC: f64 = 45.0e6;

/// Seconds per increment: the strain rate stays quasi-static (rate factor 1).
const DT: f64 = 2.0;

/// Controls with `sigma_zz = 0` and no shear strain.
fn controls(xx: Control, yy: Control) -> [Control; 6] {
    [
        xx,
        yy,
        Control::Stress(0.0),
        Control::Strain(0.0),
        Control::Strain(0.0),
        Control::Strain(0.0),
    ]
}

/// The point of largest `sigma_xx` on a path, and `">="` when the path has not passed it
/// (`Curve::peak_passed`: the stress still within 1e-3 of it where the path ends).
fn peak(curve: &Curve) -> (PathPoint, &'static str) {
    (*curve.peak(), if curve.peak_passed() { "" } else { ">=" })
}

fn main() {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/materials/thesis-concrete.yaml".into());
    let parameters = read_microplane_file(std::path::Path::new(&file)).unwrap();
    let model = MicroplaneConcrete::new(parameters).unwrap();
    println!(
        "{file}: f_t {:.2} MPa, f_c {:.1} MPa, h = 50 mm",
        FT * 1e-6,
        FC * 1e-6
    );
    println!("lateral stress  tensile peak  Kupfer-Gerstle  E_xx at the peak");
    for k in [0.0, 0.5, 1.0, 2.0, 5.0] {
        let lateral = -k * FT;
        let curve = tension_under_lateral_stress(&model, 0.05, lateral, 8e-4, 400).unwrap();
        let (top, bound) = peak(&curve);
        println!(
            "{:>6.1} f_t   {bound:>2}{:>6.2} f_t     {:>6.2} f_t      {:.2e}",
            -k,
            top.stress[0] / FT,
            1.0 + 0.8 * lateral / FC,
            top.strain[0]
        );
        if let Some(last) = curve.error.and(curve.points.last()) {
            // The cracked point cannot hold the lateral stress any longer (its relaxation is
            // isotropic): the peak above was reached before.
            println!(
                "        (lateral stress lost at E_xx {:.2e})",
                last.strain[0]
            );
        }
    }
    println!("E_yy = -r E_xx  tensile peak  sigma_yy there");
    for r in [0.0, 0.18, 0.4, 0.63, 1.0] {
        let mut point = MaterialPoint::new(&model, 0.05).unwrap();
        let (points, error) = point.run((1..=400).map(|i| {
            let e = 8e-4 * f64::from(i) / 400.0;
            (controls(Control::Strain(e), Control::Strain(-r * e)), DT)
        }));
        assert!(error.is_none(), "{error:?}");
        let (top, bound) = peak(&Curve { points, error });
        println!(
            "r = {r:<4}      {bound:>2}{:>6.2} f_t     {:>6.2} f_t",
            top.stress[0] / FT,
            top.stress[1] / FT
        );
    }
}
