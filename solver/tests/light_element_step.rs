//! The stable step of an element lighter than its material's density (issue 21).
//!
//! A remeshing gives each new element its parent's current density, and the concrete the nail
//! tears open at the cavity wall is dilated to about a hundredth of `rho_0`. The step estimate
//! `l / c` with the nominal wave speed is then ten times too long for that element, and a step
//! between the two throws its nodes. These tests hold [`Model::critical_time_step`] and
//! [`Model::current_critical_time_step`] against the element's own highest frequency,
//! computed here from the linear-elastic stiffness `V B^T D B` and the lumped mass (an
//! independent model of the element), and against a run.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::kinematics::shape_gradients;
use impact_solver::material::MaterialModel;
use impact_solver::mesh::Mesh;
use impact_solver::model::{CarriedState, Model};
use impact_solver::problem::Problem;
use nalgebra::{DMatrix, Matrix3, SymmetricEigen, Vector3};

/// A tetrahedron of a few millimetres, not regular.
fn nodes() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(2.0e-3, 0.1e-3, 0.0),
        Vector3::new(0.4e-3, 1.7e-3, 0.2e-3),
        Vector3::new(0.5e-3, 0.6e-3, 1.5e-3),
    ]
}

/// The element's model, steel, remeshed (carried `F_0 = I`) with mass `ratio rho_0 V`.
fn light_tet(ratio: f64) -> Model {
    let mesh = Mesh {
        nodes: nodes(),
        tets: vec![[0, 1, 2, 3]],
        node_sets: Default::default(),
    };
    let mut model = Model::new(vec![(
        "tet".to_string(),
        mesh,
        MaterialModel::LinearElastic(STEEL),
    )])
    .unwrap();
    let m = ratio * STEEL.density * model.volume(0);
    model.carried = Some(
        CarriedState::new(
            vec![Matrix3::identity()],
            vec![Vector3::zeros(); 4],
            vec![m],
        )
        .unwrap(),
    );
    model.mass = vec![0.25 * m; 4].into();
    model
}

/// `2 / omega_max` of the element with lumped mass `m / 4` per node: the exact limit of the
/// central-difference scheme for it (Belytschko, Liu & Moran 2000, (6.3.5)).
fn exact_limit(mass: f64) -> f64 {
    let (g, v) = shape_gradients(&nodes().try_into().unwrap()).unwrap();
    // Engineering strain (xx, yy, zz, xy, yz, zx) of the 12 nodal displacements.
    let mut b = DMatrix::<f64>::zeros(6, 12);
    for (a, grad) in g.iter().enumerate() {
        let c = 3 * a;
        b[(0, c)] = grad.x;
        b[(1, c + 1)] = grad.y;
        b[(2, c + 2)] = grad.z;
        b[(3, c)] = grad.y;
        b[(3, c + 1)] = grad.x;
        b[(4, c + 1)] = grad.z;
        b[(4, c + 2)] = grad.y;
        b[(5, c)] = grad.z;
        b[(5, c + 2)] = grad.x;
    }
    let (e, nu) = (STEEL.youngs_modulus, STEEL.poisson_ratio);
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let mut d = DMatrix::<f64>::zeros(6, 6);
    for i in 0..3 {
        for j in 0..3 {
            d[(i, j)] = lambda;
        }
        d[(i, i)] += 2.0 * mu;
        d[(i + 3, i + 3)] = mu;
    }
    let k = b.transpose() * d * b * v;
    // M^-1/2 K M^-1/2 with M = m / 4 on every degree of freedom.
    let scaled = k / (0.25 * mass);
    let omega_max = SymmetricEigen::new(scaled).eigenvalues.max().sqrt();
    2.0 / omega_max
}

/// The estimate `l / c` is not a bound for a lone tetrahedron with lumped mass (FORMULATION 2:
/// the run's safety factor covers it); what matters is that its margin against the element's
/// exact limit does not change when the element is light, where the nominal one's grows.
#[test]
fn a_light_element_keeps_the_margin_of_its_step_to_its_exact_limit() {
    let c = STEEL.dilatational_wave_speed();
    let margin = |ratio: f64| {
        let model = light_tet(ratio);
        let mass = ratio * STEEL.density * model.volume(0);
        let exact = exact_limit(mass);
        let (reference, _) = model.critical_time_step();
        let (current, _) = model.current_critical_time_step(&[Vector3::zeros(); 4]);
        // The element is in its reference configuration: both estimates agree.
        assert!(
            (current / reference - 1.0).abs() < 1e-12,
            "{current} {reference}"
        );
        let nominal = model.min_altitude(0) / c;
        (reference / exact, nominal / exact)
    };
    let (at_nominal_density, _) = margin(1.0);
    // Within the run's safety factor of 0.6 (contact; FORMULATION 2).
    assert!(0.6 * at_nominal_density < 1.0, "{at_nominal_density}");
    for ratio in [0.2, 0.01] {
        let (estimate, nominal) = margin(ratio);
        assert!(
            (estimate / at_nominal_density - 1.0).abs() < 1e-12,
            "{ratio}: {estimate}"
        );
        // The nominal step's margin grows as 1 / sqrt(ratio): ten times at a hundredth.
        let growth = nominal / at_nominal_density;
        assert!(
            (growth * ratio.sqrt() - 1.0).abs() < 1e-12,
            "{ratio}: {growth}"
        );
    }
}

#[test]
fn a_dilated_element_takes_the_current_density_into_its_step() {
    // Never remeshed: its mass is rho_0 V. Stretched to eight times its volume, its density is
    // an eighth of rho_0 and its step shrinks by sqrt(8) more than its altitude alone says.
    let model = light_tet(1.0);
    let mut plain = model;
    plain.carried = None;
    let u: Vec<Vector3<f64>> = nodes().iter().map(|x| x * 1.0).collect();
    let (current, _) = plain.current_critical_time_step(&u);
    let c = STEEL.dilatational_wave_speed();
    let altitude = 2.0 * plain.min_altitude(0);
    assert!(
        (current / (altitude / c / 8f64.sqrt()) - 1.0).abs() < 1e-12,
        "{current:e}"
    );
    // Compressed to an eighth, its density is eight times rho_0; its step stays the nominal
    // one at its current altitude (compacted material is taken to stiffen, not to slow).
    let u: Vec<Vector3<f64>> = nodes().iter().map(|x| -0.5 * x).collect();
    let (current, _) = plain.current_critical_time_step(&u);
    let altitude = 0.5 * plain.min_altitude(0);
    assert!(
        (current / (altitude / c) - 1.0).abs() < 1e-12,
        "{current:e}"
    );
}

/// Runs the element with its nodes kicked apart for `steps` steps of `dt` and returns the
/// largest nodal speed over the run.
fn largest_speed(problem: &Problem, dt: f64, steps: usize) -> f64 {
    let mut settings = ExplicitSettings::new(1.0);
    settings.time_step = Some(dt);
    settings.allow_unstable_time_step = true;
    let mut solver = ExplicitSolver::new(problem, settings, OutputSettings::default()).unwrap();
    let mut largest: f64 = 0.0;
    for _ in 0..steps {
        if solver.step().is_err() {
            return f64::INFINITY;
        }
        let state = solver.state();
        for v in &state.v_full {
            largest = largest.max(v.norm());
        }
    }
    largest
}

#[test]
fn a_light_element_run_at_its_step_stays_bounded_and_at_the_nominal_step_blows_up() {
    let model = light_tet(0.01);
    let nominal = model.min_altitude(0) / STEEL.dilatational_wave_speed();
    let (estimate, _) = model.critical_time_step();
    let mut problem = Problem::new(model);
    problem.initial_velocity = vec![
        Vector3::new(-1.0, -0.5, 0.2),
        Vector3::new(1.0, 0.0, -0.3),
        Vector3::new(0.0, 1.0, 0.4),
        Vector3::new(0.0, -0.5, -0.3),
    ]
    .into();
    // Kicked at about 1 m/s, the element vibrates at about that speed. The steps are the
    // contact runs' safety, 0.6, times each estimate.
    let at_estimate = largest_speed(&problem, 0.6 * estimate, 400);
    assert!(
        at_estimate < 3.0,
        "{at_estimate} m/s at 0.6 of the estimate"
    );
    let at_nominal = largest_speed(&problem, 0.6 * nominal, 400);
    assert!(
        at_nominal > 1e6,
        "{at_nominal} m/s at 0.6 of the nominal step"
    );
}
