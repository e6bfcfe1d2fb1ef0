//! The elastic refinement reference solved by conjugate gradients gives the stiffness sparse LU
//! gives: the iterative solver's tolerance does not change the answer.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use impact_references::elastic_refinement::{solve_elastic, ElasticStiffnessSpec};
use impact_solver::scene::{Component, Scene};
use impact_solver::statics::LinearSolver;

/// The scene of a case file (its `scene:` entry), relative paths resolved against the file.
fn case_scene(case: &Path) -> Scene {
    Scene::from_yaml_file_entry(case, "scene").unwrap()
}

/// The static three-point bending beam's metric `elastic_stiffness` at its 50 mm cells.
#[test]
fn conjugate_gradients_give_the_lu_stiffness() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/beam/static-3pt.yaml");
    let scene = case_scene(&case);
    let spec = ElasticStiffnessSpec {
        condition: "load_plate".into(),
        component: Component::Y,
        divisions: [60, 12, 6],
        displacement: -1.0e-4,
    };
    let lu = solve_elastic(&scene, &spec, LinearSolver::Lu).unwrap();
    let cg = solve_elastic(&scene, &spec, LinearSolver::conjugate_gradient()).unwrap();
    let relative = (cg.stiffness - lu.stiffness).abs() / lu.stiffness.abs();
    assert!(
        relative < 1e-6,
        "LU {} N/m, conjugate gradients {} N/m: {relative:e} relative",
        lu.stiffness,
        cg.stiffness
    );
    assert_eq!(lu.linear_iterations, 0);
    assert!(cg.linear_iterations > 0);
    // The value the case's comment quotes for these cells (384.3 MN/m).
    assert!(
        (cg.stiffness / 384.3e6 - 1.0).abs() < 1e-3,
        "{} N/m",
        cg.stiffness
    );
}
