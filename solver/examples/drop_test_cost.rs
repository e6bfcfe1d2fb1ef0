//! Wall time of the whole 2 m/s drop test (`cases/beam/drop-2ms.yaml`, 903 steps to 4 ms) with
//! three beams, run alternately so that the ratios come from one sitting (issue 20):
//!
//! - `microplane`: the case as it is;
//! - `linear laws`: the same microplane model with its strain scales `e1`, `e2`, `e3` multiplied
//!   by 1e6, so that every plane law stays linear to `f32` precision and every update takes the
//!   elastic path (`MicroplaneConcrete::elastic_limit`): the element's polar decomposition and
//!   strain, the volumetric law, the rate factor and the stress rotation are all still there, the
//!   63 plane components are not. It is the floor of the microplane element's cost, what the
//!   model costs with no plane work at all (its physics is not the case's: nothing cracks);
//! - `elastic`: linear elasticity at the model's initial constants.
//!
//! No files are written; each run prints its wall time and its internal-force phase, and the
//! medians and their ratios close the output.
//!
//! `cargo run --release -p impact-solver --example drop_test_cost [ROUNDS]` (3 rounds by
//! default, about 25 s each on two threads)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::material::MaterialModel;
use impact_solver::scene::{
    build_problem, Analysis, ExplicitAnalysis, MaterialSpec, MicroplaneSpec, Scene,
};

/// Factor on the strain scales of the `linear laws` variant: `2^(-25/m)` of the scales stays
/// above any strain of the run.
const LINEAR_SCALE: f64 = 1e6;

/// The drop-test scene with the beam's material replaced as `variant` says.
fn drop_scene(variant: &str) -> Scene {
    let case = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/beam/drop-2ms.yaml");
    let mut scene = Scene::from_yaml_file_entry(&case, "scene").unwrap();
    let beam = scene.bodies.iter_mut().find(|b| b.name == "beam").unwrap();
    let model = beam.material.model(&beam.name).unwrap();
    match (variant, model) {
        ("elastic", model) => beam.material = MaterialSpec::LinearElastic(model.constants()),
        ("linear laws", MaterialModel::Microplane(mut p)) => {
            p.e1 *= LINEAR_SCALE;
            p.e2 *= LINEAR_SCALE;
            p.e3 *= LINEAR_SCALE;
            beam.material = MaterialSpec::Microplane(Box::new(MicroplaneSpec {
                file: None,
                parameters: Some(p),
                rate_effect: true,
                volumetric_strain: None,
                crack_friction: None,
                strength_field: None,
                crack_band: None,
            }));
        }
        _ => {}
    }
    scene
}

/// Wall time and internal-force time (s) of one whole run, and the elastic path's share of the
/// element updates.
fn run(scene: &Scene) -> (f64, f64, Option<f64>) {
    let Analysis::Explicit(ExplicitAnalysis { settings, .. }) = &scene.analysis else {
        panic!("the drop test is an explicit analysis")
    };
    let problem = build_problem(scene).unwrap();
    let output = OutputSettings {
        dir: None,
        stem: "drop-test-cost".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::new(&problem, settings.clone(), output).unwrap();
    let summary = solver.run_with(&mut []).unwrap();
    let share = problem
        .model
        .fast_update_share(solver.history(), summary.steps);
    (
        summary.wall_seconds,
        summary.phase_seconds.internal_forces,
        share,
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .map_or(3, |s| s.parse().expect("ROUNDS is a count"));
    let variants = ["microplane", "linear laws", "elastic"];
    let scenes: Vec<Scene> = variants.iter().map(|v| drop_scene(v)).collect();
    let mut wall = vec![Vec::new(); variants.len()];
    let mut internal = vec![Vec::new(); variants.len()];
    for round in 1..=rounds {
        for (i, scene) in scenes.iter().enumerate() {
            let (w, f, share) = run(scene);
            let share = share.map_or("-".to_string(), |s| format!("{:.1} %", 100.0 * s));
            println!(
                "round {round} {:12} wall {w:6.2} s, internal forces {f:6.2} s, elastic path \
                 {share}",
                variants[i]
            );
            wall[i].push(w);
            internal[i].push(f);
        }
    }
    let elastic = (median(wall[2].clone()), median(internal[2].clone()));
    println!("medians of {rounds} rounds, and their ratios to the elastic beam:");
    for (i, name) in variants.iter().enumerate() {
        let (w, f) = (median(wall[i].clone()), median(internal[i].clone()));
        println!(
            "  {name:12} wall {w:6.2} s ({:4.1}x), internal forces {f:6.2} s ({:4.1}x)",
            w / elastic.0,
            f / elastic.1
        );
    }
}
