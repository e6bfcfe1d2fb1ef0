//! Scene files: the example parses and builds; bad input gives its specific message.

use impact_solver::scene::{build_problem, Scene};
use impact_solver::SolverError;

const EXAMPLE: &str = include_str!("../../cases/examples/confined-column.yaml");

#[test]
fn the_example_scene_builds() {
    let scene = Scene::from_yaml(EXAMPLE, "example.yaml").unwrap();
    let problem = build_problem(&scene).unwrap();
    assert_eq!(problem.model.element_count(), 6 * 100 * 2 * 2);
    assert_eq!(problem.constraints.len(), 5);
    assert_eq!(problem.probes[0].nodes.len(), 9);
}

fn error_of(text: &str) -> String {
    match Scene::from_yaml(text, "bad.yaml").and_then(|s| build_problem(&s).map(|_| ())) {
        Err(e @ SolverError::InvalidScene { .. }) => e.to_string(),
        other => panic!("expected an InvalidScene error, got {other:?}"),
    }
}

#[test]
fn an_unknown_key_is_named_with_its_line() {
    let text = EXAMPLE.replace("    material:\n", "    materail_typo: 1\n    material:\n");
    let msg = error_of(&text);
    assert!(
        msg.contains("bad.yaml") && msg.contains("materail_typo") && msg.contains("line"),
        "{msg}"
    );
}

#[test]
fn malformed_yaml_is_reported_with_its_line() {
    let msg = error_of("name: [unclosed\nbodies: []\n");
    assert!(msg.contains("line"), "{msg}");
}

#[test]
fn a_negative_density_is_refused() {
    let msg = error_of(&EXAMPLE.replace("density: 2300", "density: -2300"));
    assert!(msg.contains("density must be positive"), "{msg}");
}

#[test]
fn a_selector_that_picks_nothing_is_refused() {
    let msg = error_of(&EXAMPLE.replace(
        "point: [0.5, 0, 0], normal: [1, 0, 0]",
        "point: [7.5, 0, 0], normal: [1, 0, 0]",
    ));
    assert!(
        msg.contains("picks no node") && msg.contains("probe `mid`"),
        "{msg}"
    );
}

#[test]
fn an_unknown_body_is_refused() {
    let msg = error_of(&EXAMPLE.replacen("body: column", "body: colum", 1));
    assert!(msg.contains("no body named `colum`"), "{msg}");
}

#[test]
fn a_missing_mesh_file_is_refused() {
    let text = EXAMPLE.replace(
        "box: { origin: [0, 0, 0], size: [1.0, 0.05, 0.05], divisions: [100, 2, 2] }",
        "gmsh: does/not/exist.msh",
    );
    let scene = Scene::from_yaml(&text, "bad.yaml").unwrap();
    let err = build_problem(&scene).unwrap_err();
    assert!(matches!(err, SolverError::MeshRead { .. }), "{err}");
    assert!(err.to_string().contains("does/not/exist.msh"));
}
