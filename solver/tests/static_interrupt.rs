//! Static analyses that stop on a signal, refuse load step counts that are no loading, and name
//! a loaded body that nothing holds (fuzz findings H2 and U4).

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use impact_solver::analysis::{execute, ExecuteOptions};
use impact_solver::scene::{build_problem, Analysis, Scene};
use impact_solver::statics::{solve_static, solve_static_until, MAX_LOAD_STEPS};
use impact_solver::SolverError;

/// The clamp of [`bar`]'s end x = 0.
const CLAMP: &str = "{ name: clamp, body: bar, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { fixed: [x, y, z] } }";

/// A 1 m elastic bar of two cells with the boundary conditions `supports` (YAML flow maps), its
/// tip pulled down by 1 kN per node: a linear problem (no history), `analysis` as given.
fn bar(supports: &[&str], analysis: &str) -> Scene {
    let conditions: String = supports.iter().map(|c| format!("  - {c}\n")).collect();
    let conditions = if conditions.is_empty() {
        String::new()
    } else {
        format!("boundary_conditions:\n{conditions}")
    };
    let text = format!(
        "name: bar
bodies:
  - name: bar
    mesh: {{ box: {{ origin: [0, 0, 0], size: [1.0, 0.1, 0.1], divisions: [2, 1, 1] }} }}
    material: {{ linear_elastic: {{ density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 }} }}
{conditions}loads:
  - {{ name: tip, body: bar, nodes: {{ plane: {{ point: [1.0, 0, 0], normal: [1, 0, 0] }} }}, force_per_node: [0, 0, -1.0e3] }}
analysis: {analysis}
"
    );
    Scene::from_yaml(&text, "bar.yaml").unwrap()
}

/// The options of an analysis of stem `bar` writing into `out`, its stop flag already raised
/// (as a signal raises it), without fields.
fn raised_stop(out: Option<&std::path::Path>) -> ExecuteOptions<'_> {
    ExecuteOptions {
        out,
        stem: "bar",
        final_state: true,
        fields: false,
        time_limit_s: None,
        stop: Some(Arc::new(AtomicBool::new(true))),
        ranks: None,
        log: &impact_solver::analysis::log_to_stderr,
    }
}

fn static_settings(scene: &Scene) -> impact_solver::statics::StaticSettings {
    let Analysis::Static(settings) = &scene.analysis else {
        unreachable!()
    };
    settings.clone()
}

/// A linear static analysis of the largest allowed number of load steps (ten million, minutes
/// of work) with the stop flag already raised stops after its first step, at load factor
/// 1e-7, well within a second.
#[test]
fn a_raised_stop_flag_ends_a_linear_static_analysis_after_one_step() {
    let scene = bar(
        &[CLAMP],
        &format!("{{ static: {{ load_steps: {MAX_LOAD_STEPS} }} }}"),
    );
    let problem = build_problem(&scene).unwrap();
    let stop = AtomicBool::new(true);
    let start = Instant::now();
    let outcome = solve_static_until(&problem, &static_settings(&scene), &mut |_| {}, Some(&stop));
    let elapsed = start.elapsed();
    match outcome {
        Err(SolverError::Interrupted { step, time }) => {
            assert_eq!(step, 1);
            assert!((time - 1.0 / MAX_LOAD_STEPS as f64).abs() < 1e-18, "{time}");
        }
        other => panic!(
            "expected an interruption, got {:?}",
            other.map(|s| s.iterations.len())
        ),
    }
    assert!(elapsed < Duration::from_secs(2), "{elapsed:?}");
}

/// The preload of a release analysis stops on the flag too (it ran all its load steps before,
/// fuzz finding H2), and reports its load factor as progress.
#[test]
fn a_raised_stop_flag_ends_the_preload_of_a_release() {
    let scene = bar(
        &[CLAMP],
        &format!(
            "{{ release: {{ preload: {{ load_steps: {MAX_LOAD_STEPS} }}, explicit: {{ end_time: 1.0e-3 }} }} }}"
        ),
    );
    let mut problem = build_problem(&scene).unwrap();
    let options = raised_stop(None);
    let mut reported = Vec::new();
    let start = Instant::now();
    let outcome = execute(&mut problem, &scene.analysis, &options, &mut |f| {
        reported.push(f)
    });
    let elapsed = start.elapsed();
    match outcome {
        Err(SolverError::Interrupted { step, .. }) => assert_eq!(step, 1),
        Err(e) => panic!("expected an interruption, got {e}"),
        Ok(_) => panic!("expected an interruption, the release ran to its end"),
    }
    assert_eq!(reported, [1.0 / MAX_LOAD_STEPS as f64]);
    assert!(elapsed < Duration::from_secs(2), "{elapsed:?}");
}

/// Zero load steps, or more than ten million, are refused naming the key and the range: by the
/// solver, and by the scene reader before it.
#[test]
fn load_steps_outside_the_range_are_refused() {
    let scene = bar(&[CLAMP], "{ static: { load_steps: 1 } }");
    let problem = build_problem(&scene).unwrap();
    for steps in [0, MAX_LOAD_STEPS + 1] {
        let mut settings = static_settings(&scene);
        settings.load_steps = steps;
        let message = solve_static(&problem, &settings).unwrap_err().to_string();
        assert!(
            message.contains("load_steps") && message.contains("10000000"),
            "{message}"
        );
        let text = format!(
            "name: bar\nbodies:\n  - name: bar\n    mesh: {{ box: {{ origin: [0, 0, 0], size: [1, \
             0.1, 0.1], divisions: [1, 1, 1] }} }}\n    material: {{ linear_elastic: {{ density: \
             2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 }} }}\nanalysis: {{ static: {{ \
             load_steps: {steps} }} }}\n"
        );
        let message = Scene::from_yaml(&text, "bar.yaml").unwrap_err().to_string();
        assert!(
            message.contains("bar.yaml") && message.contains("analysis.static.load_steps"),
            "{message}"
        );
    }
}

/// A loaded bar with no support has no static equilibrium: the error names the body and says
/// that it can move as a rigid body, for sparse LU (which factorised the singular stiffness and
/// then reported non-convergence, fuzz finding U4) and for conjugate gradients alike. The same
/// bar clamped solves, to the tip deflection of a cantilever within the stiffness of two
/// tetrahedral cells (positive, and below Euler-Bernoulli's `F L^3 / (3 E I)`).
#[test]
fn a_loaded_body_without_support_is_named() {
    for solver in ["", ", linear_solver: { conjugate_gradient: {} }"] {
        let scene = bar(&[], &format!("{{ static: {{ load_steps: 1{solver} }} }}"));
        let problem = build_problem(&scene).unwrap();
        let message = solve_static(&problem, &static_settings(&scene))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("`bar`")
                && message.contains("rigid body")
                && message.contains("no boundary condition"),
            "{message}"
        );
    }
    let scene = bar(&[CLAMP], "{ static: { load_steps: 1 } }");
    let problem = build_problem(&scene).unwrap();
    let solution = solve_static(&problem, &static_settings(&scene)).unwrap();
    let tip = solution
        .u
        .iter()
        .zip(&problem.model.reference)
        .filter(|(_, x)| x.x > 1.0 - 1e-9)
        .map(|(u, _)| u.z)
        .fold(0.0_f64, f64::min);
    // Four tip nodes at 1 kN: F = 4 kN, I = 0.1^4 / 12.
    let euler_bernoulli = 4.0e3 * 1.0 / (3.0 * 30.0e9 * 0.1_f64.powi(4) / 12.0);
    assert!(
        tip < 0.0 && -tip < euler_bernoulli,
        "{tip} against {euler_bernoulli}"
    );
}

/// A support that holds only translations (one node fixed in x, y and z) leaves the bar free to
/// rotate about that node: refused, counting the three free rotations.
#[test]
fn a_body_held_at_one_node_is_named_with_its_free_rotations() {
    let pin = "{ name: pin, body: bar, nodes: { box: { min: [0, 0, 0], max: [0, 0, 0] } }, motion: { fixed: [x, y, z] } }";
    let scene = bar(&[pin], "{ static: { load_steps: 1 } }");
    let problem = build_problem(&scene).unwrap();
    let message = solve_static(&problem, &static_settings(&scene))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("`bar`") && message.contains("leave 3 of its 6 rigid-body motions"),
        "{message}"
    );
}

/// A static path (a microplane bar, whose history makes the analysis a path) stopped by a
/// signal writes the history rows it converged before it reports the interruption: the row of
/// the unloaded state and that of its first load step, as an interrupted explicit run keeps
/// what it wrote.
#[test]
fn an_interrupted_static_path_writes_its_history() {
    let material = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/materials/thesis-concrete.yaml");
    let text = format!(
        "name: bar
bodies:
  - name: bar
    mesh: {{ box: {{ origin: [0, 0, 0], size: [0.05, 0.05, 0.05], divisions: [1, 1, 1] }} }}
    material: {{ microplane: {{ file: {}, rate_effect: false }} }}
boundary_conditions:
  - {{ name: clamp, body: bar, nodes: {{ box: {{ min: [0, 0, 0], max: [0, 0.05, 0.05] }} }}, motion: {{ fixed: [x, y, z] }} }}
  - name: pull
    body: bar
    nodes: {{ box: {{ min: [0.05, 0, 0], max: [0.05, 0.05, 0.05] }} }}
    motion: {{ displacement: {{ components: [x], value: {{ constant_rate: {{ rate: 5.0e-6, lead_in: 0 }} }} }} }}
analysis: {{ static: {{ load_steps: 50 }} }}
",
        material.display()
    );
    let scene = Scene::from_yaml(&text, "bar.yaml").unwrap();
    let mut problem = build_problem(&scene).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let options = raised_stop(Some(dir.path()));
    match execute(&mut problem, &scene.analysis, &options, &mut |_| {}) {
        Err(SolverError::Interrupted { step, .. }) => assert_eq!(step, 1),
        Err(e) => panic!("expected an interruption, got {e}"),
        Ok(_) => panic!("expected an interruption, the path ran to its end"),
    }
    let csv = std::fs::read_to_string(dir.path().join("bar_history.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    // The header, the unloaded state (step 0) and the first load step.
    assert_eq!(rows.len(), 3, "{csv}");
}
