//! Diagnostic for an element that collapses (issue 20, `beam/drop-8ms-h25`): runs a scene and
//! prints, at every field frame from a given time on, one element's volume ratio `J = det F`,
//! the two volumetric strains the microplane model can read (`tr E / 3`, thesis (5.11), and the
//! dilatational `(J^(2/3) - 1) / 2`, `material/microplane/volumetric.rs`), its principal
//! stretches, and its pressure and von Mises stress.
//!
//! ```text
//! cargo run --release -p impact-solver --example element_history -- \
//!     cases/beam/drop-8ms-h25.yaml 3.15e-3 5.0e-5 16161 0.5e-3
//! ```
//! The arguments: a scene file or a case file's `scene`, the end time and the frame interval (s),
//! the element (its index in the model, as a run's error names it) and the first time printed.
//! The scene's own end time and intervals are replaced; nothing is written to disk. A run that
//! stops (an inverted element) prints its error after the frames it reached.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::kinematics::matrix_from_voigt;
use impact_solver::material::microplane::volumetric::{
    dilatational_strain, volume_ratio_squared_minus_one,
};
use impact_solver::material::microplane::{principal_values, sym};
use impact_solver::output::observer::RunObserver;
use impact_solver::output::vtu::{FieldData, FieldFrame};
use impact_solver::remesh::von_mises;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, Scene};

/// Prints one element's deformation and stress at every field frame.
struct ElementHistory {
    element: usize,
    from: f64,
}

impl RunObserver for ElementHistory {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> impact_solver::error::Result<Option<PathBuf>> {
        if frame.time < self.from {
            return Ok(None);
        }
        let (Some(FieldData::SymmetricTensor(strain)), Some(FieldData::SymmetricTensor(sigma))) = (
            frame.cell_field("green_lagrange_strain"),
            frame.cell_field("cauchy_stress"),
        ) else {
            return Ok(None);
        };
        // The frame's fields are in Voigt order [xx, yy, zz, xy, yz, xz]; the microplane
        // model's functions read its own order [11, 22, 33, 23, 13, 12].
        let e = sym(&matrix_from_voigt(&strain[self.element]));
        let s = &sigma[self.element];
        // The principal stretches from the principal Green-Lagrange strains (largest first).
        let stretches = principal_values(&e).map(|l| (1.0 + 2.0 * l).max(0.0).sqrt());
        let j = (1.0 + volume_ratio_squared_minus_one(&e)).max(0.0).sqrt();
        let dilatational = dilatational_strain(&e).unwrap_or(f64::NAN);
        let pressure = -(s[0] + s[1] + s[2]) / 3.0;
        println!(
            "{:8.4} ms  J {j:.4}  trE/3 {:+.4}  e_V(J) {dilatational:+.4}  stretches {:.3} {:.3} \
             {:.3}  p {:+8.2} MPa  q {:7.2} MPa",
            frame.time * 1e3,
            (e[0] + e[1] + e[2]) / 3.0,
            stretches[2],
            stretches[1],
            stretches[0],
            pressure / 1e6,
            von_mises(s) / 1e6,
        );
        Ok(None)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 5 {
        eprintln!(
            "usage: element_history <scene or case.yaml> <end time s> <frame interval s> \
             <element> [from s]"
        );
        std::process::exit(2);
    }
    let scene = Scene::from_yaml_file_entry(Path::new(&args[1]), "scene").unwrap();
    let end: f64 = args[2].parse().unwrap();
    let every: f64 = args[3].parse().unwrap();
    let element: usize = args[4].parse().unwrap();
    let from: f64 = args.get(5).map_or(0.0, |s| s.parse().unwrap());
    let Analysis::Explicit(ExplicitAnalysis {
        settings: scene_settings,
        ..
    }) = &scene.analysis
    else {
        panic!("an explicit analysis is needed")
    };
    // The frames this diagnostic reads, and no snapshots.
    let settings = ExplicitSettings {
        end_time: end,
        field_interval: Some(every),
        snapshot_interval: None,
        ..scene_settings.clone()
    };
    let problem = build_problem(&scene).unwrap();
    println!("element {element} of `{}`", args[1]);
    let mut history = ElementHistory { element, from };
    let mut solver = ExplicitSolver::new(&problem, settings, OutputSettings::default()).unwrap();
    if let Err(e) = solver.run_with(&mut [&mut history]) {
        println!("run stopped: {e}");
    }
}
