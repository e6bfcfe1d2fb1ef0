//! Issue 21 diagnostic: how much stress the calibrated concrete keeps on the strain paths of the
//! material ahead of a penetrator's nose, at the nail's element size (0.25 mm) and strain rate
//! (200 m/s over 2 mm, 1e5 /s). Two paths of one material point:
//!
//! * uniaxial strain (`E_11` down to -0.2, the other strains held), the path of a plate impact
//!   and, roughly, of the material the nose pushes ahead of it;
//! * shear at held compression (all normal strains -c, then the shear `E_12` up to 0.3): a
//!   frictional material keeps a shear stress that grows with its pressure (Mohr-Coulomb,
//!   `tau = tau0 + lambda p`, lambda about 0.7 for comminuted concrete: Forrestal et al. 1994's
//!   cavity expansion), which is what resists a nose in a cavity.
//!
//! Prints the axial and lateral stress, the mean stress (pressure positive) and the shear stress
//! along each path (second Piola-Kirchhoff, tension positive).
//!
//! What it showed (2026-11-27, `cases/materials/thesis-concrete.yaml`): the point carries what a
//! nose needs. Uniaxial strain reaches 388 MPa axial at 2 % and 939 MPa at 5 % (the volumetric
//! law stiffens); shear at held normal strains of 0, -0.005 and -0.02 levels off at 36, 66 and
//! 156 MPa without softening to zero (the crack band stretches the laws' strain scales by
//! h_ref / h = 200 at 0.25 mm, and the rate raises them), with pressures of 265 to
//! 1180 MPa. Forrestal's cavity expansion asks about 470 MPa on the nose for this concrete
//! (S fc with S = 10.4), 1.5 kN on the quarter nail. The nail run meanwhile feels 185 N on its
//! quarter on average over its first 35 us (the momentum it lost; less than the inertial term
//! rho A V^2 = 290 N alone) and 41 MPa of mean pressure within 3 mm of the tip, so
//! its low resistance is not the law at a point: the material by the nose does not reach those
//! strains confined.
//!
//! `cargo run --release -p impact-solver --example penetration_resistance [-- MATERIAL_FILE]`

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;

fn main() {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/materials/thesis-concrete.yaml".into());
    let model = MicroplaneConcrete::new(read_microplane_file(std::path::Path::new(&file)).unwrap())
        .unwrap();
    let (h, rate) = (2.5e-4, 1e5);
    println!("{file}: h = {h} m, strain rate {rate:e} /s");

    println!("\nuniaxial strain: E11, S11 (MPa), S22 (MPa), pressure (MPa)");
    let mut pt = MaterialPoint::new(&model, h).unwrap();
    let steps = 4000;
    for i in 1..=steps {
        let e = -0.2 * i as f64 / steps as f64;
        let de = 0.2 / steps as f64;
        let q = pt.strain_step([e, 0.0, 0.0, 0.0, 0.0, 0.0], de / rate);
        if i % 200 == 0 || i == 10 || i == 40 {
            let p = -(q.stress[0] + q.stress[1] + q.stress[2]) / 3.0;
            println!(
                "{:9.4} {:10.1} {:10.1} {:10.1}",
                e,
                q.stress[0] / 1e6,
                q.stress[1] / 1e6,
                p / 1e6
            );
        }
    }

    for c in [0.0, 0.005, 0.02] {
        println!("\nshear at held normal strains -{c}: E12, S12 (MPa), pressure (MPa)");
        let mut pt = MaterialPoint::new(&model, h).unwrap();
        let n = 200;
        for i in 1..=n {
            let e = -c * i as f64 / n as f64;
            pt.strain_step([e, e, e, 0.0, 0.0, 0.0], c.max(1e-6) / n as f64 / rate);
        }
        let steps = 3000;
        for i in 1..=steps {
            let g = 0.3 * i as f64 / steps as f64;
            let q = pt.strain_step([-c, -c, -c, 0.0, 0.0, g], 0.3 / steps as f64 / rate);
            if i % 150 == 0 || i == 5 || i == 20 {
                let p = -(q.stress[0] + q.stress[1] + q.stress[2]) / 3.0;
                println!("{:9.4} {:10.2} {:10.1}", g, q.stress[5] / 1e6, p / 1e6);
            }
        }
    }
}
