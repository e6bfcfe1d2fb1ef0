//! A run made by hand for the measures' unit tests: a small bar whose every number is known
//! (its mass, its elastic constants, the nodes' places), a history table of given columns, and
//! final fields set by the test. No solver runs, so each expected value is a hand calculation on
//! the numbers written here.

use impact_solver::analysis::Execution;
use impact_solver::dynamics::RunSummary;
use impact_solver::output::HistoryTable;
use impact_solver::problem::Problem;
use impact_solver::scene::{build_problem, Scene};
use impact_solver::Vector3;

/// Density of the bar (kg/m^3).
pub const DENSITY: f64 = 2000.0;
/// Young's modulus of the bar (Pa).
pub const YOUNG: f64 = 1.0e10;
/// Poisson's ratio of the bar: 1/4 makes both Lame constants `0.4 E`.
pub const POISSON: f64 = 0.25;
/// The bar's volume (m^3): 2 x 1 x 1 m.
pub const VOLUME: f64 = 2.0;

/// The bar `bar`, 2 x 1 x 1 m from the origin in 2 x 1 x 1 cells (12 nodes, 12 elements),
/// linear elastic, under gravity `-10` m/s^2 along y, with its end `x = 0` fixed (`end`) and a
/// reaction probe on the nodes of the line `x = 2, y = 0` (`tip`).
pub fn bar() -> Problem {
    bar_of(
        &format!(
            "{{ linear_elastic: {{ density: {DENSITY}, youngs_modulus: {YOUNG}, poisson_ratio: {POISSON} }} }}"
        ),
        1.0,
    )
}

/// The bar of [`bar`] made of the thesis's microplane concrete, a material whose stress has no
/// closed form, at a tenth of the size (the microplane laws refuse elements over 118 mm).
pub fn concrete_bar() -> Problem {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases/materials/thesis-concrete.yaml");
    bar_of(
        &format!("{{ microplane: {{ file: {} }} }}", file.display()),
        0.1,
    )
}

/// The bar of [`bar`] made of `material` (a scene's material, in YAML flow style), its lengths
/// scaled by `s`.
fn bar_of(material: &str, s: f64) -> Problem {
    let l = 2.0 * s;
    let scene = Scene::from_yaml(
        &format!(
            "name: bar
bodies:
  - name: bar
    mesh: {{ box: {{ origin: [0, 0, 0], size: [{l}, {s}, {s}], divisions: [2, 1, 1] }} }}
    material: {material}
gravity: [0, -10, 0]
boundary_conditions:
  - {{ name: end, body: bar, nodes: {{ box: {{ min: [0, 0, 0], max: [0, {s}, {s}] }} }}, motion: {{ fixed: [x, y, z] }} }}
probes:
  - {{ name: tip, body: bar, nodes: {{ box: {{ min: [{l}, 0, 0], max: [{l}, 0, {s}] }} }}, quantity: reaction }}
analysis:
  explicit: {{ end_time: 1.0e-3 }}
"
        ),
        "bar.yaml",
    )
    .expect("the bar's scene reads");
    build_problem(&scene).expect("the bar builds")
}

/// A history table of the named columns, all of one length.
pub fn history(columns: &[(&str, &[f64])]) -> HistoryTable {
    let mut table = HistoryTable::new(columns.iter().map(|(n, _)| n.to_string()).collect());
    for i in 0..columns.first().map_or(0, |(_, c)| c.len()) {
        table.push(columns.iter().map(|(_, c)| c[i]).collect());
    }
    table
}

/// A static run of `problem` with displacement `u(X)` at every node and the given history:
/// no velocities, no summary.
pub fn run(
    problem: &Problem,
    u: impl Fn(&Vector3<f64>) -> Vector3<f64>,
    history: Option<HistoryTable>,
) -> Execution {
    Execution {
        plan: "by hand".into(),
        u: problem.model.reference.iter().map(u).collect(),
        v: None,
        history,
        summary: None,
        static_solution: None,
        written: Vec::new(),
        contact_problems: Vec::new(),
        material_history: None,
        remeshings: Vec::new(),
    }
}

/// `run` turned into an explicit run that ended at `time` with velocity `v(X)` at every node
/// and `energy_error` as its largest relative energy balance error.
pub fn explicit(
    mut run: Execution,
    problem: &Problem,
    v: impl Fn(&Vector3<f64>) -> Vector3<f64>,
    time: f64,
    energy_error: f64,
) -> Execution {
    run.v = Some(problem.model.reference.iter().map(v).collect());
    run.summary = Some(RunSummary {
        steps: 1,
        time,
        time_step: time,
        critical_time_step: time,
        critical_element: 0,
        wall_seconds: 0.0,
        contact_seconds: 0.0,
        phase_seconds: Default::default(),
        contact_totals: Default::default(),
        energies: Default::default(),
        max_relative_energy_error: energy_error,
        mesh_stability_flags: 0,
        history: HistoryTable::new(Vec::new()),
        snapshots: Vec::new(),
        written: Vec::new(),
        stopped_when_at: None,
    });
    run
}

/// At rest: the zero field.
pub fn rest(_: &Vector3<f64>) -> Vector3<f64> {
    Vector3::zeros()
}

/// The value of `measure` on the run `run` of [`bar`], which must evaluate.
pub fn value(measure: super::Measure, run: &Execution) -> f64 {
    measure.evaluate(&bar(), run).unwrap()
}
