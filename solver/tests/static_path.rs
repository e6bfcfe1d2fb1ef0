//! The static path of microplane concrete (`statics::path`): Newton's method from the committed
//! history, checked against the material-point driver, an independent code path (stress control
//! of one point, no elements, no assembly, no tangent matrix).

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use impact_solver::material::microplane::experiments::{uniaxial_tension, QUASI_STATIC_RATE};
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;
use impact_solver::model::TimeFunction;
use impact_solver::scene::{build_problem, Analysis, Component, MotionSpec, Scene};
use impact_solver::statics::{solve_static, solve_static_until, StaticSolution};
use impact_solver::SolverError;

fn shipped_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/materials/thesis-concrete.yaml")
}

/// A 5 cm cube of the thesis concrete (six tetrahedra) on rollers (x on the face x = 0, y on
/// y = 0, z on z = 0), its face x = 5 cm pulled to an axial strain `strain` in `steps` load
/// steps: uniaxial stress, the same strain in every element.
fn pulled_cube(strain: f64, steps: usize) -> (impact_solver::problem::Problem, Analysis) {
    let text = format!(
        "name: cube
bodies:
  - name: cube
    mesh: {{ box: {{ origin: [0, 0, 0], size: [0.05, 0.05, 0.05], divisions: [1, 1, 1] }} }}
    material: {{ microplane: {{ file: {file}, rate_effect: false }} }}
boundary_conditions:
  - {{ name: roller_x, body: cube, nodes: {{ box: {{ min: [0, 0, 0], max: [0, 0.05, 0.05] }} }}, motion: {{ fixed: [x] }} }}
  - {{ name: roller_y, body: cube, nodes: {{ box: {{ min: [0, 0, 0], max: [0.05, 0, 0.05] }} }}, motion: {{ fixed: [y] }} }}
  - {{ name: roller_z, body: cube, nodes: {{ box: {{ min: [0, 0, 0], max: [0.05, 0.05, 0] }} }}, motion: {{ fixed: [z] }} }}
  - name: pull
    body: cube
    nodes: {{ box: {{ min: [0.05, 0, 0], max: [0.05, 0.05, 0.05] }} }}
    motion: {{ displacement: {{ components: [x], value: {{ constant_rate: {{ rate: {rate}, lead_in: 0 }} }} }} }}
analysis:
  static: {{ load_steps: {steps}, tolerance: 1.0e-9, max_iterations: 20 }}
",
        file = shipped_file().display(),
        rate = strain * 0.05,
    );
    let scene = Scene::from_yaml(&text, "cube.yaml").unwrap();
    (build_problem(&scene).unwrap(), scene.analysis)
}

fn solve(strain: f64, steps: usize) -> StaticSolution {
    let (problem, analysis) = pulled_cube(strain, steps);
    let Analysis::Static(settings) = analysis else {
        unreachable!()
    };
    solve_static(&problem, &settings).unwrap()
}

fn model() -> MicroplaneConcrete {
    MicroplaneConcrete::new(read_microplane_file(&shipped_file()).unwrap()).unwrap()
}

/// Up to past the tensile peak, the cube's axial stress (reaction over the face area) equals the
/// material point's uniaxial tension curve at the same strain, and the peaks agree (measured:
/// peaks 9e-5 apart, curves within 1.5e-4 of the peak; the driver's stress control stops at a
/// lateral residual, and the cube's strain is Green-Lagrange).
#[test]
fn a_pulled_cube_follows_the_material_point_through_the_tensile_peak() {
    // The driver's increments are 2e-6: the same load steps here, to 2.4e-4 (the peak is near
    // 1.3e-4 for this concrete).
    let solution = solve(2.4e-4, 120);
    assert!(solution.stopped.is_none(), "{:?}", solution.stopped);
    let history = solution.history.as_ref().unwrap();
    let reaction = history.column("pull_reaction_x").unwrap();
    let area = 0.05 * 0.05;
    let (curve, result) = uniaxial_tension(&model(), 0.05, QUASI_STATIC_RATE).unwrap();
    let (strains, stresses) = (curve.axial_strain(), curve.axial_stress());
    let mut worst: f64 = 0.0;
    for (k, r) in reaction.iter().enumerate().skip(1) {
        let strain = 2.4e-4 * k as f64 / 120.0;
        // The driver's path: its first increment is 1e-8, then 2e-6 steps.
        let at = strains
            .iter()
            .position(|&e| (e - strain).abs() < 2e-8)
            .unwrap_or_else(|| panic!("the driver has no point at strain {strain:e}"));
        worst = worst.max((r / area - stresses[at]).abs() / result.peak_stress);
    }
    let peak = reaction.iter().fold(0.0_f64, |a, &r| a.max(r)) / area;
    assert!(
        (peak / result.peak_stress - 1.0).abs() < 1e-3,
        "peak {peak} against the material point's {}",
        result.peak_stress
    );
    assert!(
        worst < 1e-3,
        "largest difference {worst} of the peak stress"
    );
}

/// The path is a function of the input: the same history whatever the number of threads.
#[test]
fn the_static_path_does_not_depend_on_the_thread_count() {
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| solve(1.6e-4, 20))
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.history, two.history);
    assert_eq!(one.material_history, two.material_history);
}

/// A path records one history row per converged load step (and the start) and returns the
/// committed material history.
#[test]
fn the_static_path_records_every_load_step() {
    let solution = solve(5e-5, 2);
    let history = solution.history.as_ref().unwrap();
    // The start and the two load steps, at load factors 0, 1/2 and 1 (end_time 1).
    assert_eq!(history.column("time").unwrap(), [0.0, 0.5, 1.0]);
    assert_eq!(history.column("step").unwrap(), [0.0, 1.0, 2.0]);
    // The committed history is the loaded one, not the virgin state.
    let (problem, _) = pulled_cube(5e-5, 2);
    let committed = solution.material_history.as_ref().unwrap();
    assert_ne!(committed, &problem.model.initial_history());
}

/// A stop flag raised during the second load step (by the progress callback, as a signal
/// would) ends the path at the end of that step with `Interrupted`, naming the step and its
/// time; without it the same path runs to the end.
#[test]
fn a_raised_stop_flag_ends_the_path_at_the_end_of_the_step() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let (problem, analysis) = pulled_cube(5e-5, 4);
    let Analysis::Static(settings) = analysis else {
        unreachable!()
    };
    let stop = AtomicBool::new(false);
    let mut steps = 0;
    let outcome = solve_static_until(
        &problem,
        &settings,
        &mut |_| {
            steps += 1;
            if steps == 2 {
                stop.store(true, Ordering::Relaxed);
            }
        },
        Some(&stop),
    );
    match outcome {
        Err(SolverError::Interrupted { step, time }) => {
            assert_eq!(step, 2);
            assert!((time - 0.5).abs() < 1e-12, "{time}");
        }
        other => panic!(
            "expected an interruption, got {:?}",
            other.map(|s| s.stopped)
        ),
    }
    let calm = AtomicBool::new(false);
    assert!(solve_static_until(&problem, &settings, &mut |_| {}, Some(&calm)).is_ok());
}

/// An elastic bar of three 5 cm cells on rollers, its end face moved by opening control: the
/// opening between the nodes at x = 5 and 10 cm is prescribed. Uniform strain: the end moves by
/// three openings and the reaction is `E A eps` (uniaxial stress), to round-off.
#[test]
fn opening_control_moves_the_loaded_face_by_what_the_opening_needs() {
    let text = |probe_to: &str| {
        format!(
            "name: bar
bodies:
  - name: bar
    mesh: {{ box: {{ origin: [0, 0, 0], size: [0.15, 0.05, 0.05], divisions: [3, 1, 1] }} }}
    material: {{ linear_elastic: {{ density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 }} }}
boundary_conditions:
  - {{ name: roller_x, body: bar, nodes: {{ box: {{ min: [0, 0, 0], max: [0, 0.05, 0.05] }} }}, motion: {{ fixed: [x] }} }}
  - {{ name: roller_y, body: bar, nodes: {{ box: {{ min: [0, 0, 0], max: [0.15, 0, 0.05] }} }}, motion: {{ fixed: [y] }} }}
  - {{ name: roller_z, body: bar, nodes: {{ box: {{ min: [0, 0, 0], max: [0.15, 0.05, 0] }} }}, motion: {{ fixed: [z] }} }}
  - name: pull
    body: bar
    nodes: {{ box: {{ min: [0.15, 0, 0], max: [0.15, 0.05, 0.05] }} }}
    motion: {{ displacement: {{ components: [x], value: {{ constant: 0.0 }} }} }}
probes:
  - {{ name: x05, body: bar, nodes: {{ box: {{ min: [0.05, 0, 0], max: [0.05, 0.05, 0.05] }} }}, quantity: displacement }}
  - {{ name: x10, body: bar, nodes: {{ box: {{ min: [0.1, 0, 0], max: [0.1, 0.05, 0.05] }} }}, quantity: displacement }}
analysis:
  static:
    load_steps: 2
    tolerance: 1.0e-10
    opening_control: {{ condition: pull, from: x05, to: {probe_to}, component: x, opening: {{ constant_rate: {{ rate: 1.0e-6, lead_in: 0 }} }} }}
"
        )
    };
    let scene = Scene::from_yaml(&text("x10"), "bar.yaml").unwrap();
    let problem = build_problem(&scene).unwrap();
    let Analysis::Static(settings) = &scene.analysis else {
        unreachable!()
    };
    let solution = solve_static(&problem, settings).unwrap();
    let history = solution.history.as_ref().unwrap();
    let last = |c: &str| *history.column(c).unwrap().last().unwrap();
    let strain = 1.0e-6 / 0.05;
    assert!((last("control_opening") - 1.0e-6).abs() < 1e-18);
    assert!((last("control_displacement") / (3.0 * 1.0e-6) - 1.0).abs() < 1e-9);
    // Against the same bar with the end displacement prescribed, solved without the control: the
    // same equilibrium to round-off. Against Hooke's law to the order of the strain (2e-5: the
    // material is linear in the Green-Lagrange strain of the co-rotated frame).
    let reaction = last("pull_reaction_x");
    let mut prescribed = scene.clone();
    prescribed.boundary_conditions[3].motion = MotionSpec::Displacement {
        components: vec![Component::X],
        value: TimeFunction::Constant(last("control_displacement")),
    };
    let Analysis::Static(mut plain) = prescribed.analysis.clone() else {
        unreachable!()
    };
    plain.opening_control = None;
    let problem = build_problem(&prescribed).unwrap();
    let direct = solve_static(&problem, &plain).unwrap();
    let index = problem
        .constraints
        .iter()
        .position(|c| c.name == "pull")
        .unwrap();
    let expected = direct.constraint_reaction(&problem, index).x;
    assert!(
        (reaction / expected - 1.0).abs() < 1e-9,
        "{reaction} against {expected}"
    );
    let stress = reaction / (0.05 * 0.05);
    assert!(
        (stress / (30.0e9 * strain) - 1.0).abs() < 1e-4,
        "{stress} against {}",
        30.0e9 * strain
    );
    // A probe that does not exist is named, with those that do.
    let scene = Scene::from_yaml(&text("x15"), "bar.yaml").unwrap();
    let problem = build_problem(&scene).unwrap();
    let Analysis::Static(settings) = &scene.analysis else {
        unreachable!()
    };
    let message = solve_static(&problem, settings).unwrap_err().to_string();
    assert!(
        message.contains("opening_control.to")
            && message.contains("x15")
            && message.contains("x05"),
        "{message}"
    );
}

/// Conjugate gradients need a symmetric tangent; a path's forward-difference tangents are not,
/// so a path asked to use them is refused before it starts, naming the way out.
#[test]
fn a_path_refuses_conjugate_gradients() {
    let (problem, analysis) = pulled_cube(1e-5, 1);
    let Analysis::Static(mut settings) = analysis else {
        unreachable!()
    };
    settings.linear_solver = impact_solver::statics::LinearSolver::conjugate_gradient();
    let message = solve_static(&problem, &settings).unwrap_err().to_string();
    assert!(message.contains("linear_solver: lu"), "{message}");
}

/// The catalogue's opening-controlled prism, `cases/fracture/band-in-prism-h50-long-opening-control.yaml`
/// (350 mm of 50 mm cells, two across, the band's opening driven to 0.3 mm), in `steps` load steps.
fn catalogue_prism(steps: usize) -> (impact_solver::problem::Problem, Analysis) {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/fracture/band-in-prism-h50-long-opening-control.yaml");
    let mut scene = Scene::from_yaml_file_entry(&file, "scene").unwrap();
    let Analysis::Static(settings) = &mut scene.analysis else {
        panic!("the prism's analysis is static")
    };
    settings.load_steps = steps;
    (build_problem(&scene).unwrap(), scene.analysis)
}

/// The catalogue prism's band shrunk to one cell across (`divisions: [7, 1, 1]`, six
/// tetrahedra in the band, `max_cuts: 3`), its pulled face held sideways (`gripped`) or only
/// along the pull, in `steps` load steps.
fn shrunk_prism(steps: usize, gripped: bool) -> (impact_solver::problem::Problem, Analysis) {
    let grip = if gripped {
        "  - { name: pulled_end_grip, body: prism, nodes: { box: { min: [0.35, 0, 0], max: [0.35, 0.1, 0.1] } }, motion: { fixed: [y, z] } }\n"
    } else {
        ""
    };
    let text = format!(
        "name: prism
bodies:
  - name: prism
    mesh: {{ box: {{ origin: [0, 0, 0], size: [0.35, 0.1, 0.1], divisions: [7, 1, 1] }} }}
    material: {{ linear_elastic: {{ density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.18 }} }}
    regions:
      - name: band
        centroid_box: {{ min: [0.15, 0, 0], max: [0.2, 0.1, 0.1] }}
        material: {{ microplane: {{ file: {file}, rate_effect: false }} }}
boundary_conditions:
  - {{ name: fixed_end, body: prism, nodes: {{ box: {{ min: [0, 0, 0], max: [0, 0.1, 0.1] }} }}, motion: {{ fixed: [x] }} }}
  - {{ name: pin, body: prism, nodes: {{ box: {{ min: [0, 0, 0], max: [0, 0, 0] }} }}, motion: {{ fixed: [y, z] }} }}
  - {{ name: pin_z, body: prism, nodes: {{ box: {{ min: [0, 0.1, 0], max: [0, 0.1, 0] }} }}, motion: {{ fixed: [z] }} }}
  - {{ name: pulled_end, body: prism, nodes: {{ box: {{ min: [0.35, 0, 0], max: [0.35, 0.1, 0.1] }} }}, motion: {{ displacement: {{ components: [x], value: {{ constant: 0.0 }} }} }} }}
{grip}probes:
  - {{ name: band_left, body: prism, nodes: {{ box: {{ min: [0.15, 0, 0], max: [0.15, 0.1, 0.1] }} }}, quantity: displacement }}
  - {{ name: band_right, body: prism, nodes: {{ box: {{ min: [0.2, 0, 0], max: [0.2, 0.1, 0.1] }} }}, quantity: displacement }}
analysis:
  static:
    load_steps: {steps}
    tolerance: 1.0e-6
    max_iterations: 15
    max_cuts: 3
    opening_control: {{ condition: pulled_end, from: band_left, to: band_right, component: x, opening: {{ constant_rate: {{ rate: 3.0e-4, lead_in: 0 }} }} }}
",
        file = shipped_file().display(),
    );
    let scene = Scene::from_yaml(&text, "prism.yaml").unwrap();
    (build_problem(&scene).unwrap(), scene.analysis)
}

/// The load factor at which a prism's path ends, and why.
fn path_end(
    (problem, analysis): (impact_solver::problem::Problem, Analysis),
) -> (f64, Option<String>) {
    let Analysis::Static(settings) = analysis else {
        unreachable!()
    };
    let solution = solve_static(&problem, &settings).unwrap();
    let time = solution.history.as_ref().unwrap().column("time").unwrap();
    (*time.last().unwrap(), solution.stopped)
}

/// Under control of its band's opening the catalogue prism has no limit point: its path ends at
/// load factor 1 whatever the load steps. Two mechanisms stopped it early before. With a
/// tolerance relative to the present reaction alone, a band softened through (0.03 N left of a
/// 26 kN peak) asked for a residual below the round-off of the forces. With a forward-difference
/// step of 1e-7 h, the tangent straddled the loading-unloading kinks of planes near their turning
/// points and Newton stalled (1 000 and 10 000 steps stopped the shrunk prism at 0.18 and 0.022).
#[test]
fn an_opening_controlled_path_ends_where_it_ends_whatever_the_load_steps() {
    let paths = [150, 1000, 10_000].map(|steps| (steps, path_history(catalogue_prism(steps))));
    let (_, (_, w_fine, r_fine, _)) = &paths[2];
    for (steps, (time, opening, reaction, stopped)) in &paths {
        let end = *time.last().unwrap();
        assert!(
            (end - 1.0).abs() < 1e-12 && stopped.is_none(),
            "{steps} load steps ended at {end}: {stopped:?}"
        );
        let work_ratio = work(opening, reaction) / work(w_fine, r_fine);
        assert!(
            (work_ratio - 1.0).abs() < 0.01,
            "{steps} load steps dissipate {work_ratio} of 10 000 steps' work"
        );
    }
}

/// A piece that a crack cuts free, with nothing holding it sideways, has a rigid motion that no
/// force resists: it is set by round-off. The shrunk prism's far end, held only along the pull,
/// slid 387 m sideways by the end of its 150-step path, which reported success; the path now
/// stops where a body moves farther than its own size, and says why.
#[test]
fn a_piece_cut_free_stops_the_path_and_names_its_body() {
    let (end, stopped) = path_end(shrunk_prism(150, false));
    let why = stopped.expect("the path stops");
    assert!(end < 1.0, "ended at {end}");
    assert!(
        why.contains("lost support")
            && why.contains("`prism`")
            && why.contains("boundary condition"),
        "{why}"
    );
}

/// The history of a prism's path: its load factors, band openings and pulled-face reactions.
fn path_history(
    (problem, analysis): (impact_solver::problem::Problem, Analysis),
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Option<String>) {
    let Analysis::Static(settings) = analysis else {
        unreachable!()
    };
    let solution = solve_static(&problem, &settings).unwrap();
    let history = solution.history.as_ref().unwrap();
    let column = |name: &str| history.column(name).unwrap().to_vec();
    (
        column("time"),
        column("control_opening"),
        column("pulled_end_reaction_x"),
        solution.stopped,
    )
}

/// The work of the reaction over the opening, `sum (R_i + R_i+1) / 2 (w_i+1 - w_i)` (J).
fn work(opening: &[f64], reaction: &[f64]) -> f64 {
    (1..opening.len())
        .map(|i| 0.5 * (reaction[i] + reaction[i - 1]) * (opening[i] - opening[i - 1]))
        .sum()
}

/// The reaction at `opening`, interpolated linearly along the path.
fn reaction_at(opening: &[f64], reaction: &[f64], at: f64) -> f64 {
    let i = opening.iter().position(|&w| w >= at).unwrap();
    let t = (at - opening[i - 1]) / (opening[i] - opening[i - 1]);
    reaction[i - 1] + t * (reaction[i] - reaction[i - 1])
}

/// With one cell across (six tetrahedra in the band) the band's tetrahedra do not deform alike
/// (their largest plane strains differ by 2 % before the peak and 10 % at it), and the branch
/// that Newton's iteration follows from the committed state depends on the load steps. On the
/// branch of 150 and of 1 000 steps it folds just past the peak (load factors 0.0417 and
/// 0.0423, where these paths stopped): Newton's iteration cycled (period 2 or 3) between the
/// sides of plane kinks, and along the segment between two of its iterates the residual had a
/// nonzero least value (25 N, 1.4e-3 of the force scale), so no state near balanced the step.
/// The step relaxed there (`statics::relaxation`) finds the balanced state across the fold, and
/// the paths of 150, 1 000 and 10 000 steps end at 1 on the same softening curve.
#[test]
fn a_band_one_cell_across_ends_where_it_ends_whatever_the_load_steps() {
    let paths = [150, 1000, 10_000].map(|steps| (steps, path_history(shrunk_prism(steps, true))));
    let (_, (_, w_fine, r_fine, _)) = &paths[2];
    for (steps, (time, opening, reaction, stopped)) in &paths {
        let end = *time.last().unwrap();
        assert!(
            (end - 1.0).abs() < 1e-12,
            "{steps} load steps ended at {end}: {stopped:?}"
        );
        let work_ratio = work(opening, reaction) / work(w_fine, r_fine);
        assert!(
            (work_ratio - 1.0).abs() < 0.01,
            "{steps} load steps dissipate {work_ratio} of 10 000 steps' work"
        );
        for at in [3e-5, 1e-4] {
            let ratio = reaction_at(opening, reaction, at) / reaction_at(w_fine, r_fine, at);
            assert!(
                (ratio - 1.0).abs() < 0.01,
                "{steps} load steps: the reaction at opening {at} is {ratio} of 10 000 steps'"
            );
        }
    }
}
