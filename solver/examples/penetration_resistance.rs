//! Issue 21 diagnostic: how much stress the calibrated concrete keeps on the strain paths of the
//! material ahead of a penetrator's nose, at the nail's element size (0.25 mm) and strain rate
//! (200 m/s over 2 mm, 1e5 /s). Two paths of one material point:
//!
//! * uniaxial strain (`E_11` down to -0.2, the other strains held), the path of a plate impact
//!   and, roughly, of the material the nose pushes ahead of it;
//! * shear at held compression (all normal strains -c, then the shear `E_12` up to 0.5): a
//!   frictional material keeps a shear stress that grows with its pressure (Mohr-Coulomb,
//!   `tau = tau0 + lambda p`, lambda about 0.7 for comminuted concrete: Forrestal et al. 1994's
//!   cavity expansion), which is what resists a nose in a cavity.
//!
//! Prints the axial and lateral stress, the mean stress (pressure positive) and the shear stress
//! along each path (second Piola-Kirchhoff, tension positive).
//!
//! What it showed (2026-11-27): the thesis concrete (`thesis-concrete.yaml`) in uniaxial strain
//! reaches 388 MPa axial at 2 % and 939 MPa at 5 % (the volumetric law stiffens). Sheared to
//! `E_12 = 0.5` at held normal strains of 0, -0.005 and -0.02 it keeps 29, 62 and 154 MPa at
//! h = 0.25 mm, where the crack band stretches the laws' strain scales by h_ref / h = 200, and
//! nothing at h_ref = 50 mm under pressures of 0.1 to 0.97 GPa: every shear law of the thesis
//! softens to zero whatever the pressure. The elements by the nail's nose (0.3 to 1.5 mm) were
//! stress-free or nearly hydrostatic in the run, a fluid. The crack-friction refit
//! (`thesis-concrete-crack-friction.yaml`, docs/MICROPLANE.md "Crack friction") keeps 0.63 times the
//! pressure on the same paths at both sizes (70 / 169 / 592 MPa at 0.25 mm, 38 / 145 / 567 MPa at
//! 50 mm): the Coulomb limit of friction 0.73 homogenised over the 21 planes.
//!
//! `cargo run --release -p impact-solver --example penetration_resistance [-- MATERIAL_FILE]`
//! (the thesis concrete and its crack-friction refit when no file is given)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;

fn main() {
    let files: Vec<String> = match std::env::args().nth(1) {
        Some(file) => vec![file],
        None => vec![
            "cases/materials/thesis-concrete.yaml".into(),
            "cases/materials/thesis-concrete-crack-friction.yaml".into(),
        ],
    };
    for file in files {
        let model =
            MicroplaneConcrete::new(read_microplane_file(std::path::Path::new(&file)).unwrap())
                .unwrap();
        for h in [2.5e-4, model.parameters.h_ref] {
            paths(&file, &model, h);
        }
    }
}

/// The two paths of the module doc for a point of size `h` at the nail's strain rate.
fn paths(file: &str, model: &MicroplaneConcrete, h: f64) {
    let rate = 1e5;
    println!("\n{file}: h = {h} m, strain rate {rate:e} /s");

    println!("uniaxial strain: E11, S11 (MPa), S22 (MPa), pressure (MPa)");
    let mut pt = MaterialPoint::new(model, h).unwrap();
    let steps = 4000;
    for i in 1..=steps {
        let e = -0.2 * i as f64 / steps as f64;
        let de = 0.2 / steps as f64;
        let q = pt.strain_step([e, 0.0, 0.0, 0.0, 0.0, 0.0], de / rate);
        if i % 400 == 0 || i == 40 {
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
        println!("shear at held normal strains -{c}: E12, S12 (MPa), pressure (MPa)");
        let mut pt = MaterialPoint::new(model, h).unwrap();
        let n = 200;
        for i in 1..=n {
            let e = -c * i as f64 / n as f64;
            pt.strain_step([e, e, e, 0.0, 0.0, 0.0], c.max(1e-6) / n as f64 / rate);
        }
        let steps = 5000;
        for i in 1..=steps {
            let g = 0.5 * i as f64 / steps as f64;
            let q = pt.strain_step([-c, -c, -c, 0.0, 0.0, g], 0.5 / steps as f64 / rate);
            if i % 1000 == 0 || i == 50 || i == 250 {
                let p = -(q.stress[0] + q.stress[1] + q.stress[2]) / 3.0;
                println!("{:9.4} {:10.2} {:10.1}", g, q.stress[5] / 1e6, p / 1e6);
            }
        }
    }
}
