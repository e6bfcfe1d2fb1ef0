//! The stable step on elongated and flattened box cells (issue O1 of the fuzz findings).
//!
//! A bar of ten Kuhn-split cells pushed at one end (the scene of O1) with cells of aspect ratio
//! 1 to 10, long (`r x 1 x 1`, "needle") and flat (`1 x r x r`, "plate"). For each, the run at
//! the default safety of 0.9 must keep its energy balance, and the largest stable step found by
//! bisection must not be below the estimate `Model::critical_time_step`. The bisected limit is
//! held against an independent reference, `2 / sqrt(lambda_max(M^-1 K))` of the assembled
//! linear-elastic stiffness with the pushed dofs held (a dense eigen solve), and the old
//! estimate, smallest altitude over wave speed, is shown to lie above the limit of flat cells:
//! the mechanism of O1.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::model::Problem;
use impact_solver::scene::{build_problem, Scene};
use nalgebra::{DMatrix, Matrix3};

const DENSITY: f64 = 2300.0;
const YOUNGS_MODULUS: f64 = 30.0e9;
const POISSON_RATIO: f64 = 0.2;

/// The push scene of O1 with ten cells of `cell` (m) along x, one across.
fn push_bar(cell: [f64; 3]) -> Problem {
    let text = format!(
        "name: bar
bodies:
  - name: bar
    mesh: {{ box: {{ origin: [0, 0, 0], size: [{}, {}, {}], divisions: [10, 1, 1] }} }}
    material: {{ linear_elastic: {{ density: {DENSITY}, youngs_modulus: {YOUNGS_MODULUS}, poisson_ratio: {POISSON_RATIO} }} }}
boundary_conditions:
  - {{ name: push, body: bar, nodes: {{ plane: {{ point: [0, 0, 0], normal: [1, 0, 0] }} }}, motion: {{ velocity: {{ components: [x], value: {{ constant: 1.0 }} }} }} }}
analysis:
  explicit: {{ end_time: 1.0e-3 }}
",
        10.0 * cell[0],
        cell[1],
        cell[2]
    );
    let scene = Scene::from_yaml(&text, "push-bar.yaml").unwrap();
    build_problem(&scene).unwrap()
}

/// Relative energy-balance error after `steps` steps of `settings`' step, or infinity where a
/// step fails (an inverted element) or the error is not finite.
fn energy_error(problem: &Problem, settings: ExplicitSettings, steps: usize) -> f64 {
    let mut solver = ExplicitSolver::new(problem, settings, OutputSettings::default()).unwrap();
    for _ in 0..steps {
        if solver.step().is_err() {
            return f64::INFINITY;
        }
    }
    let error = solver.energies.relative_error().abs();
    if error.is_finite() {
        error
    } else {
        f64::INFINITY
    }
}

/// Stable: the energy balance error stays below half the energy over `STEPS` steps of `dt`. A
/// mode above the limit grows by about `e^(2 sqrt(eps))` a step at `omega dt = 2 (1 + eps)`, so
/// 2000 steps find the limit to about `eps = 1e-5`. (A tighter bound on the error would call
/// stable steps just below the limit unstable: the discrete energy of a mode near
/// `omega dt = 2` departs from the exact one by `1 / (1 - (omega dt / 2)^2)`.)
fn stable_at(problem: &Problem, dt: f64) -> bool {
    const STEPS: usize = 2000;
    let mut settings = ExplicitSettings::new(1.0);
    settings.time_step = Some(dt);
    settings.allow_unstable_time_step = true;
    energy_error(problem, settings, STEPS) < 0.5
}

/// The exact limit `2 / sqrt(lambda_max(M^-1 K))` of the linear-elastic model with the `x`
/// dofs of the `x = 0` face held: `K = sum_e V (lambda g_a g_b^T + mu g_b g_a^T +
/// mu (g_a . g_b) I)` assembled here from the model's shape gradients, `M` its lumped masses.
fn exact_limit(problem: &Problem) -> f64 {
    let model = &problem.model;
    let (e, nu) = (YOUNGS_MODULUS, POISSON_RATIO);
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let n = model.node_count();
    let mut k = DMatrix::<f64>::zeros(3 * n, 3 * n);
    for (tet, (g, v)) in model
        .tets
        .iter()
        .zip(model.grad_n.iter().zip(&model.volume))
    {
        for a in 0..4 {
            for b in 0..4 {
                let block = (g[a] * g[b].transpose()) * lambda
                    + (g[b] * g[a].transpose()) * mu
                    + Matrix3::identity() * (mu * g[a].dot(&g[b]));
                let (ia, ib) = (3 * tet[a] as usize, 3 * tet[b] as usize);
                for i in 0..3 {
                    for j in 0..3 {
                        k[(ia + i, ib + j)] += v * block[(i, j)];
                    }
                }
            }
        }
    }
    let free: Vec<usize> = (0..3 * n)
        .filter(|&d| !(d % 3 == 0 && model.reference[d / 3].x.abs() < 1e-12))
        .collect();
    let m = &model.mass;
    let a = DMatrix::from_fn(free.len(), free.len(), |i, j| {
        let (p, q) = (free[i], free[j]);
        k[(p, q)] / (m[p / 3] * m[q / 3]).sqrt()
    });
    2.0 / a.symmetric_eigenvalues().max().sqrt()
}

#[test]
#[ignore = "the default estimate is still the smallest altitude, 0.87 of the limit on flat cells: \
            open until the estimate is a bound (docs/stable-time-step.md)"]
fn the_default_step_is_stable_and_the_estimate_below_the_limit_on_cells_up_to_10_to_1() {
    let h = 0.01;
    let c_d = {
        let (e, nu) = (YOUNGS_MODULUS, POISSON_RATIO);
        (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / DENSITY).sqrt()
    };
    for shape in ["needle", "plate"] {
        for ratio in [1.0, 2.0, 3.0, 5.0, 7.0, 10.0] {
            let cell = match shape {
                "needle" => [ratio * h, h, h],
                _ => [h, ratio * h, ratio * h],
            };
            let problem = push_bar(cell);
            let (estimate, _) = problem.model.critical_time_step();
            let case = format!("{shape} cells {ratio}:1");

            // (a) The default step, 0.9 of the estimate, over 5000 steps.
            let mut settings = ExplicitSettings::new(1.0);
            assert_eq!(settings.safety, 0.9);
            settings.time_step = None;
            let error = energy_error(&problem, settings, 5000);
            // The balance error of a stable run here is the scheme's own, about 4e-3 over
            // 5000 steps at 0.9 of the estimate on cubic cells, 4e-4 at 0.5; an unstable one
            // grows past 1 (O1: the solver's check stops a run at 0.05).
            assert!(error < 1e-2, "{case}: energy error {error:e} at safety 0.9");

            // (b) The largest stable step, bisected between the estimate (stable) and twice
            // it (unstable: the estimate is at least half the limit, module docs of
            // `stable_step`).
            assert!(
                stable_at(&problem, estimate),
                "{case}: unstable at the estimate"
            );
            let (mut lo, mut hi) = (1.0, 2.0);
            assert!(
                !stable_at(&problem, hi * estimate),
                "{case}: stable at twice"
            );
            while hi - lo > 1e-3 {
                let mid = 0.5 * (lo + hi);
                if stable_at(&problem, mid * estimate) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let measured = lo * estimate;
            let exact = exact_limit(&problem);
            let old = (0..problem.model.element_count())
                .map(|e| problem.model.min_altitude[e] / c_d)
                .fold(f64::INFINITY, f64::min);
            println!(
                "{case}: measured limit / estimate {lo:.4}, exact / estimate {:.4}, \
                 measured / exact {:.4}, exact / old altitude estimate {:.4}",
                exact / estimate,
                measured / exact,
                exact / old
            );
            // The bisection finds the eigenvalue limit: a step of 2000 can grow a mode only
            // a little above it (`stable_at`), and the bracket is 1e-3 of the estimate.
            assert!(
                (measured / exact - 1.0).abs() < 2e-3,
                "{case}: measured {measured:e} s, exact {exact:e} s"
            );
            // The estimate is conservative: at most the limit.
            assert!(estimate <= exact, "{case}: {estimate:e} > {exact:e}");
            // The old estimate is not, on flat cells: O1's mechanism (0.87 of it at 5:1).
            if shape == "plate" && ratio >= 5.0 {
                assert!(exact < 0.9 * old, "{case}: exact {exact:e}, old {old:e}");
            }
        }
    }
}
