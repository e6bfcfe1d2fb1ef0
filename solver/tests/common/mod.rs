//! Builders shared by the integration tests.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]
#![allow(dead_code)]

use impact_solver::contact::registry::{SolverChoice, SolverKind};
use impact_solver::contact::solver::SolveLimits;
use impact_solver::contact::ContactPair;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings, RunState};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, perturb_interior, BoxSpec, Mesh};
use impact_solver::model::Model;
use impact_solver::problem::Problem;
use nalgebra::{Matrix3, Vector3};

pub const STEEL: IsotropicElastic = IsotropicElastic {
    density: 7800.0,
    youngs_modulus: 200e9,
    poisson_ratio: 0.3,
};

pub fn spec(size: [f64; 3], divisions: [usize; 3]) -> BoxSpec {
    BoxSpec {
        origin: [0.0; 3],
        size,
        divisions,
        mirror: Vec::new(),
    }
}

/// A box mesh, with interior nodes moved by up to `perturb` of the cell size.
pub fn box_body(size: [f64; 3], divisions: [usize; 3], perturb: f64, seed: u64) -> Mesh {
    let s = spec(size, divisions);
    let mut mesh = box_mesh(&s);
    if perturb > 0.0 {
        perturb_interior(&mut mesh, &s, perturb, seed);
    }
    mesh
}

pub fn problem(mesh: Mesh, material: MaterialModel) -> Problem {
    Problem::new(Model::new(vec![("body".into(), mesh, material)]).unwrap())
}

/// Nodes on the boundary of the box `[0, size]`.
pub fn box_boundary_nodes(model: &Model, size: [f64; 3]) -> Vec<u32> {
    let tol = 1e-9;
    (0..model.node_count() as u32)
        .filter(|&n| {
            let x = model.reference[n as usize];
            (0..3).any(|a| x[a].abs() < tol || (x[a] - size[a]).abs() < tol)
        })
        .collect()
}

pub fn max_abs(m: &Matrix3<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

pub fn voigt_to_matrix(v: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2])
}

pub fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

/// Largest |sigma_ij| over all elements at displacement `u`.
pub fn max_element_stress(model: &Model, u: &[Vector3<f64>]) -> f64 {
    model
        .element_fields(u)
        .cauchy
        .iter()
        .map(|s| max_abs(&voigt_to_matrix(s)))
        .fold(0.0, f64::max)
}

/// A steel column 0.5 x 0.05 x 0.05 m whose end `x = 0` is pushed along x at 1 m/s.
pub fn pushed_column() -> Problem {
    let mut p = problem(
        box_body([0.5, 0.05, 0.05], [20, 2, 2], 0.0, 0),
        MaterialModel::LinearElastic(STEEL),
    );
    drive_end_face(&mut p, "push", [true, false, false], 1.0);
    p
}

/// Drives the nodes of the face `x = 0` at a constant `speed` (m/s) along the directions
/// `dofs`, as the constraint `name`.
pub fn drive_end_face(p: &mut Problem, name: &str, dofs: [bool; 3], speed: f64) {
    use impact_solver::model::{Constraint, Motion, TimeFunction};
    let end: Vec<u32> = (0..p.model.node_count() as u32)
        .filter(|&n| p.model.reference[n as usize].x < 1e-12)
        .collect();
    p.constraints.push(Constraint {
        name: name.into(),
        nodes: end,
        motion: Motion::Velocity(dofs, TimeFunction::Constant(speed)),
    });
}

/// Largest `|K + W - W_0| / W_0` over a history (kinetic and stored energy against the stored
/// energy `W_0` of the start): the drift of an undamped elastic body, independent of the
/// solver's energy bookkeeping.
pub fn kinetic_plus_stored_drift(
    history: &impact_solver::output::HistoryTable,
    stored: f64,
) -> f64 {
    let kinetic = history.column("kinetic").expect("a kinetic column");
    let strain = history
        .column("stored_energy")
        .expect("a stored_energy column");
    kinetic
        .iter()
        .zip(&strain)
        .map(|(k, w)| (k + w - stored).abs())
        .fold(0.0, f64::max)
        / stored
}

/// A cantilever `length x depth x depth` on 20 x 2 x 2 cells of `material`, clamped at `x = 0`
/// and loaded at `x = length` by a constant `tip_force` (N) per node along z; with its tip nodes.
pub fn tip_loaded_cantilever<M: Into<impact_solver::model::MaterialSource>>(
    material: M,
    length: f64,
    depth: f64,
    tip_force: f64,
) -> (Problem, Vec<u32>) {
    use impact_solver::model::{Constraint, Motion, NodalLoad, TimeFunction};
    let mesh = box_body([length, depth, depth], [20, 2, 2], 0.0, 0);
    let mut p = Problem::new(Model::new(vec![("body".to_string(), mesh, material)]).unwrap());
    let at = |x: f64| -> Vec<u32> {
        (0..p.model.node_count() as u32)
            .filter(|&n| (p.model.reference[n as usize].x - x).abs() < 1e-12)
            .collect()
    };
    let (clamp, tip) = (at(0.0), at(length));
    p.constraints.push(Constraint {
        name: "clamp".into(),
        nodes: clamp,
        motion: Motion::Fixed([true; 3]),
    });
    p.loads.push(NodalLoad {
        name: "tip".into(),
        nodes: tip.clone(),
        force_per_node: Vector3::new(0.0, 0.0, tip_force),
        function: TimeFunction::Constant(1.0),
    });
    (p, tip)
}

/// The microplane parameters of the thesis' concrete (`cases/materials/thesis-concrete.yaml`).
pub fn thesis_concrete() -> impact_solver::material::microplane::MicroplaneParameters {
    shipped_concrete("thesis-concrete")
}

/// The microplane parameters of the shipped material `cases/materials/<name>.yaml`.
pub fn shipped_concrete(name: &str) -> impact_solver::material::microplane::MicroplaneParameters {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../cases/materials/{name}.yaml"));
    impact_solver::material::read_microplane_file(&path).unwrap()
}

/// Frobenius norm of a symmetric tensor `[11, 22, 33, 23, 13, 12]` with tensor shears (each
/// counted twice).
pub fn sym_norm(s: &[f64; 6]) -> f64 {
    (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// Simple shear of the box `[0, size]^3` of `p` at `rate` (1/s): every boundary node follows
/// `v = rate y e_x` (an affine velocity constraint named `shear`), and a probe `top` records the
/// mean displacement of the top face `y = size[1]`.
#[allow(dead_code)]
pub fn shear_the_box(p: &mut Problem, size: [f64; 3], rate: f64) {
    use impact_solver::model::{Constraint, Motion, Probe, ProbeQuantity};
    let boundary = box_boundary_nodes(&p.model, size);
    let top: Vec<u32> = boundary
        .iter()
        .copied()
        .filter(|&n| p.model.reference[n as usize].y > size[1] - 1e-9)
        .collect();
    let mut gradient = Matrix3::zeros();
    gradient[(0, 1)] = rate;
    p.constraints.push(Constraint {
        name: "shear".into(),
        nodes: boundary,
        motion: Motion::AffineVelocity {
            translation: Vector3::zeros(),
            gradient,
            center: Vector3::zeros(),
        },
    });
    p.probes.push(Probe {
        name: "top".into(),
        nodes: top,
        quantity: ProbeQuantity::Displacement,
    });
}

/// A random walk of `steps` strain increments of up to `reach` per component from zero, with a
/// drift `drift` per step on every component (negative: towards compression), each step's rate
/// drawn from 1e-5 to 1e2 /s on a log scale: `(strain, rate)` per step.
pub fn strain_walk(
    rng: &mut impact_solver::rng::SplitMix64,
    steps: usize,
    reach: f64,
    drift: [f64; 6],
) -> Vec<([f64; 6], f64)> {
    let mut strain = [0.0; 6];
    (0..steps)
        .map(|_| {
            for (e, d) in strain.iter_mut().zip(drift) {
                *e += d + rng.uniform(-reach, reach) / (steps as f64).sqrt();
            }
            (strain, 10f64.powf(rng.uniform(-5.0, 2.0)))
        })
        .collect()
}

/// Runs `path` through the microplane models `a` and `b` from the virgin state with the crack
/// band of size `h`, asserting equal stresses and histories, bit for bit, at every step; returns
/// the final history.
pub fn assert_same_updates(
    a: &impact_solver::material::microplane::MicroplaneConcrete,
    b: &impact_solver::material::microplane::MicroplaneConcrete,
    path: &[([f64; 6], f64)],
    h: f64,
    label: &str,
) -> Vec<f32> {
    let band = a.crack_band(h).unwrap();
    let mut state_a = a.initial_state().values;
    let mut state_b = state_a.clone();
    let bits = |s: &[f64; 6]| s.map(f64::to_bits);
    let history_bits = |h: &[f32]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (step, (strain, rate)) in path.iter().enumerate() {
        let (sa, _) = a.update(&mut state_a, strain, *rate, &band);
        let (sb, _) = b.update(&mut state_b, strain, *rate, &band);
        assert_eq!(
            bits(&sa),
            bits(&sb),
            "{label} step {step}: {sa:?} vs {sb:?}"
        );
        assert_eq!(
            history_bits(&state_a),
            history_bits(&state_b),
            "{label} step {step}: histories differ"
        );
    }
    state_a
}

/// The bits of a run's material history (values, then stresses, body by body), for bitwise
/// comparisons of runs.
pub fn material_history_bits(history: &impact_solver::model::MaterialHistory) -> Vec<u64> {
    history
        .bodies
        .iter()
        .flatten()
        .flat_map(|b| {
            b.values
                .iter()
                .map(|x| x.to_bits() as u64)
                .chain(b.cauchy.iter().flatten().map(|x| x.to_bits()))
        })
        .collect()
}

/// `kind` run to a residual of 1e-12, at most 5000 iterations.
pub fn tight_solver(kind: SolverKind) -> SolverChoice {
    SolverChoice {
        kind,
        limits: SolveLimits {
            tolerance: 1e-12,
            max_iterations: 5000,
            time_limit: None,
        },
    }
}

/// A two-pass contact pair between bodies 0 and 1 solved by `solver`: barycentric tolerance
/// 1e-9, default normals, nothing recorded, a penetration closed at once.
pub fn contact_pair(name: &str, friction: f64, solver: SolverChoice) -> ContactPair {
    ContactPair {
        name: name.into(),
        bodies: [0, 1],
        friction,
        beta_0: 0.0,
        solver,
        record_every: None,
        record_ccd_every: None,
        detection_tolerance: 1e-9,
        two_pass: true,
        normals: Default::default(),
        skip_symmetry_faces: false,
        penetration_release_speed: f64::INFINITY,
    }
}

/// Runs `steps` explicit steps of `problem` under `settings`, from `state` or from the start,
/// and returns the state reached.
pub fn run_steps(
    problem: &Problem,
    settings: ExplicitSettings,
    state: Option<RunState>,
    steps: usize,
) -> RunState {
    let mut solver = match state {
        Some(s) => ExplicitSolver::resume(problem, settings, OutputSettings::default(), s),
        None => ExplicitSolver::new(problem, settings, OutputSettings::default()),
    }
    .unwrap();
    for _ in 0..steps {
        solver.step().unwrap();
    }
    solver.state()
}

/// The elements of body `body` whose current centroid lies within `radius` of `center`, grown
/// by one layer.
pub fn current_region_near(
    problem: &Problem,
    state: &RunState,
    body: usize,
    center: Vector3<f64>,
    radius: f64,
) -> Vec<usize> {
    let m = &problem.model;
    let x: Vec<Vector3<f64>> = m
        .reference
        .iter()
        .zip(&state.u)
        .map(|(x, u)| x + u)
        .collect();
    let elements = m.bodies[body].elements.clone();
    let seed: Vec<usize> = impact_solver::mesh::ops::centroids(&x, &m.tets)
        .iter()
        .enumerate()
        .filter(|(e, c)| elements.contains(e) && (*c - center).norm() < radius)
        .map(|(e, _)| e)
        .collect();
    assert!(!seed.is_empty());
    impact_solver::mesh::ops::grow_region(&m.tets, &seed, 1)
        .into_iter()
        .filter(|e| elements.contains(e))
        .collect()
}
