//! Microplane concrete in scene files: `material: { microplane: { file: ... } }` relative to the
//! scene, or `material: { microplane: { parameters: {...} } }` inline; the crack indicator
//! setting; and the errors, each naming the file, the body and the fix.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use impact_solver::material::{read_microplane_file, MaterialModel, MicroplaneMaterial};
use impact_solver::scene::{build_problem, Scene};
use impact_solver::SolverError;

fn shipped_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/materials/thesis-concrete.yaml")
}

/// A fresh directory per test.
fn temp_dir(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "impact-microplane-scene-{name}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A scene with one 5 cm concrete cube of `material` (YAML, indented for the `material:` key)
/// and `extra` top-level keys.
fn scene(material: &str, extra: &str) -> String {
    format!(
        "name: cube
bodies:
  - name: cube
    mesh:
      box: {{ origin: [0, 0, 0], size: [0.05, 0.05, 0.05], divisions: [1, 1, 1] }}
    material:
{material}
{extra}
analysis:
  explicit: {{ end_time: 1.0e-5 }}
"
    )
}

fn build(text: &str) -> Result<impact_solver::problem::Problem, SolverError> {
    Scene::from_yaml(text, "cube.yaml").and_then(|s| build_problem(&s))
}

fn error_of(text: &str) -> String {
    match build(text) {
        Err(e @ SolverError::InvalidScene { .. }) => e.to_string(),
        Err(e) => panic!("expected an InvalidScene error, got {e}"),
        Ok(_) => panic!("expected an error"),
    }
}

#[test]
fn a_parameter_file_is_found_relative_to_the_scene_file() {
    let dir = temp_dir("relative");
    std::fs::create_dir_all(dir.join("materials")).unwrap();
    let with_record = format!(
        "{}\ncalibration:\n  note: fitted elsewhere\n  residuals: {{ ft: 0.01 }}\n",
        std::fs::read_to_string(shipped_file())
            .unwrap()
            .split("\ncalibration:")
            .next()
            .unwrap()
    );
    std::fs::write(dir.join("materials/concrete.yaml"), with_record).unwrap();
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    let path = dir.join("scenes/cube.yaml");
    std::fs::write(
        &path,
        scene("      microplane: { file: ../materials/concrete.yaml }", ""),
    )
    .unwrap();
    let problem = build_problem(&Scene::from_yaml_file(&path).unwrap()).unwrap();
    let expected = read_microplane_file(&shipped_file()).unwrap();
    assert_eq!(
        problem.model.bodies[0].material.model(),
        Some(MaterialModel::Microplane(expected))
    );
    let microplane = microplane_of(&problem, 0);
    assert_eq!(microplane.bands.len(), 6);
    assert!(microplane
        .bands
        .iter()
        .all(|b| (b.size - 0.05).abs() < 1e-12));
    // The stable step comes from the elastic constants of the parameters.
    let c = expected.elastic().dilatational_wave_speed();
    let (dt, e) = problem.model.critical_time_step();
    assert_eq!(dt, problem.model.min_altitude(e) / c);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The shipped file's `parameters:` block (up to the next top-level key), indented to sit under `material: { microplane: ... }`.
fn inline_parameters() -> String {
    std::fs::read_to_string(shipped_file())
        .unwrap()
        .lines()
        .skip_while(|l| !l.starts_with("parameters:"))
        .enumerate()
        .take_while(|(i, l)| *i == 0 || !l.starts_with(|c: char| c.is_ascii_alphabetic()))
        .map(|(_, l)| format!("        {l}\n"))
        .collect()
}

#[test]
fn inline_parameters_build_the_same_model() {
    let text = scene(&format!("      microplane:\n{}", inline_parameters()), "");
    let problem = build(&text).unwrap();
    let expected = read_microplane_file(&shipped_file()).unwrap();
    assert_eq!(
        problem.model.bodies[0].material.model(),
        Some(MaterialModel::Microplane(expected))
    );
}

#[test]
fn microplane_material_errors_name_the_body_the_file_and_the_fix() {
    let file = shipped_file().display().to_string();
    // Both sources, or none.
    let msg = error_of(&scene(
        &format!(
            "      microplane:\n        file: {file}\n{}",
            inline_parameters()
        ),
        "",
    ));
    assert!(
        msg.contains("body `cube`") && msg.contains("exactly one"),
        "{msg}"
    );
    let msg = error_of(&scene("      microplane: {}", ""));
    assert!(msg.contains("neither"), "{msg}");
    // A misspelt key of the spec, with its line.
    let msg = error_of(&scene("      microplane: { files: x.yaml }", ""));
    assert!(
        msg.contains("cube.yaml") && msg.contains("files") && msg.contains("line"),
        "{msg}"
    );
    // A missing file.
    let msg = error_of(&scene("      microplane: { file: no/such/file.yaml }", ""));
    assert!(
        msg.contains("body `cube` material.microplane.file")
            && msg.contains("no/such/file.yaml")
            && msg.contains("cannot read"),
        "{msg}"
    );
    // A file with an unknown parameter names the file and the key.
    let dir = temp_dir("typo");
    let typo = dir.join("typo.yaml");
    std::fs::write(
        &typo,
        std::fs::read_to_string(shipped_file())
            .unwrap()
            .replace("  beta:", "  betta:"),
    )
    .unwrap();
    let msg = error_of(&scene(
        &format!("      microplane: {{ file: {} }}", typo.display()),
        "",
    ));
    assert!(
        msg.contains("typo.yaml") && msg.contains("betta") && msg.contains("body `cube`"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    // A cube too large for the crack band.
    let msg = error_of(
        &scene(&format!("      microplane: {{ file: {file} }}"), "")
            .replace("size: [0.05, 0.05, 0.05]", "size: [0.9, 0.9, 0.9]"),
    );
    assert!(
        msg.contains("body `cube` element 0") && msg.contains("900.0 mm"),
        "{msg}"
    );
}

#[test]
fn the_crack_indicator_setting_is_read_and_checked() {
    let material =
        "      linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 }";
    let problem = build(&scene(
        material,
        "crack_indicator: { crack_width: 1.0e-4, length: 0.05 }",
    ))
    .unwrap();
    assert_eq!(problem.model.crack_indicator.crack_width, 1e-4);
    assert_eq!(problem.model.crack_indicator.length, Some(0.05));
    let defaults = build(&scene(material, "")).unwrap();
    assert_eq!(defaults.model.crack_indicator.crack_width, 2e-4);
    assert_eq!(defaults.model.crack_indicator.length, None);
    let msg = error_of(&scene(material, "crack_indicator: { crack_width: -1 }"));
    assert!(
        msg.contains("crack_indicator") && msg.contains("crack_width"),
        "{msg}"
    );
    let msg = error_of(&scene(material, "crack_indicator: { width: 1 }"));
    assert!(msg.contains("width") && msg.contains("line"), "{msg}");
}

/// `rate_effect: false` gives the body the file's parameters at static rates: the rate law is
/// dropped (rate factor 1 however fast the element is strained), nothing else changes.
#[test]
fn rate_effect_false_gives_static_rates() {
    let file = shipped_file().display().to_string();
    let with_rate = build(&scene(&format!("      microplane: {{ file: {file} }}"), "")).unwrap();
    let text = scene(
        &format!("      microplane: {{ file: {file}, rate_effect: false }}"),
        "",
    );
    let problem = build(&text).unwrap();
    let mut expected = read_microplane_file(&shipped_file()).unwrap();
    assert!(
        expected.rate_effect.is_some(),
        "the shipped file has a rate law"
    );
    assert_ne!(
        problem.model.bodies[0].material.model(),
        with_rate.model.bodies[0].material.model()
    );
    expected.rate_effect = None;
    assert_eq!(
        problem.model.bodies[0].material.model(),
        Some(MaterialModel::Microplane(expected))
    );
    let model = &microplane_of(&problem, 0).model;
    assert_eq!(model.rate_factor(1e3), 1.0);
}

/// The prepared microplane material of body `b`.
fn microplane_of(problem: &impact_solver::problem::Problem, b: usize) -> &MicroplaneMaterial {
    let material: &dyn std::any::Any = &*problem.model.bodies[b].material;
    material
        .downcast_ref::<MicroplaneMaterial>()
        .expect("a body of microplane concrete")
}
