//! The conic solver on small problems with known solutions, and on the cases it must report.

use std::time::Duration;

use clarabel::solver::SolverStatus;
use nalgebra::{DMatrix, DVector};

use super::*;
use crate::contact::problem::{natural_map_error, SparseMatrix};

fn problem(w: &DMatrix<f64>, q: &[f64], mu: &[f64]) -> ContactProblem {
    let n = w.nrows();
    let triplets: Vec<_> = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter(|&(i, j)| w[(i, j)] != 0.0)
        .map(|(i, j)| (i, j, w[(i, j)]))
        .collect();
    ContactProblem {
        w: SparseMatrix::from_triplets(n, &triplets).unwrap(),
        q: q.to_vec(),
        mu: mu.to_vec(),
        frames: None,
        compliance: 1.0,
        source: "unit test".into(),
    }
}

/// An SPD 6x6 matrix coupling two contacts in every component.
fn coupled_w() -> DMatrix<f64> {
    let l = DMatrix::from_row_slice(
        6,
        6,
        &[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, //
            0.2, 0.9, 0.0, 0.0, 0.0, 0.0, //
            -0.1, 0.3, 1.1, 0.0, 0.0, 0.0, //
            0.4, -0.2, 0.1, 1.2, 0.0, 0.0, //
            0.1, 0.2, -0.3, 0.2, 0.8, 0.0, //
            -0.2, 0.1, 0.2, -0.1, 0.3, 1.0, //
        ],
    );
    &l * l.transpose()
}

fn solve(p: &ContactProblem, mode: ConicMode) -> SolverReport {
    ConicSolver::new(mode)
        .solve(p, &SolveLimits::default())
        .expect("solves")
}

/// At the default 1e-8 Clarabel's multipliers are off by about 2e-8 relative; checks of the
/// formulation against exact solutions at 1e-8 ask Clarabel for 1e-10.
fn solve_tight(p: &ContactProblem, mode: ConicMode) -> SolverReport {
    let limits = SolveLimits {
        tolerance: 1e-10,
        ..Default::default()
    };
    ConicSolver::new(mode).solve(p, &limits).expect("solves")
}

fn assert_close(r: &[f64], exact: &[f64], tol: f64) {
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
    for (k, (a, b)) in r.iter().zip(exact).enumerate() {
        assert!(
            (a - b).abs() <= tol * scale,
            "component {k}: {a} vs {b}\n{r:?}"
        );
    }
}

#[test]
fn frictionless_single_contact_is_the_normal_projection() {
    let w = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, 0.1, 0.3, 1.0, 0.0, 0.1, 0.0, 1.5]);
    let p = problem(&w, &[-3.0, 1.0, -0.5], &[0.0]);
    for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
        let report = solve_tight(&p, mode);
        assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
        assert_close(&report.r, &[1.5, 0.0, 0.0], 1e-8);
        assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
        assert!(report.iterations > 0);
    }
}

#[test]
fn frictionless_two_contacts_match_the_linear_solve_on_the_active_set() {
    let w = coupled_w();
    let n = [0, 3];
    let w_nn = DMatrix::from_fn(2, 2, |i, j| w[(n[i], n[j])]);
    // Both active: r_N = W_NN^-1 (-q_N).
    let r_n = DVector::from_vec(vec![1.0, 2.0]);
    let q_n = -(&w_nn * &r_n);
    let q = [q_n[0], 0.7, -0.2, q_n[1], 0.1, 0.4];
    let p = problem(&w, &q, &[0.0, 0.0]);
    let report = solve_tight(&p, ConicMode::Coulomb);
    assert_eq!(report.status, SolveStatus::Converged);
    assert_close(&report.r, &[1.0, 0.0, 0.0, 2.0, 0.0, 0.0], 1e-8);
    assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
    // Contact 1 separates: r = (1.5, 0), u_N,1 = 0.7 > 0.
    let q = [
        -w[(0, 0)] * 1.5,
        0.7,
        -0.2,
        -w[(3, 0)] * 1.5 + 0.7,
        0.1,
        0.4,
    ];
    let p = problem(&w, &q, &[0.0, 0.0]);
    let report = solve_tight(&p, ConicMode::Relaxed);
    assert_eq!(report.status, SolveStatus::Converged);
    assert_close(&report.r, &[1.5, 0.0, 0.0, 0.0, 0.0, 0.0], 1e-8);
    assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
    assert!((p.velocity(&report.r)[3] - 0.7).abs() < 1e-7);
}

#[test]
fn stick_leaves_the_tangential_force_free() {
    let w = coupled_w();
    let exact = [1.0, 0.7, -0.4, 2.0, -1.5, 0.3];
    let q: Vec<f64> = (-(&w * DVector::from_row_slice(&exact)))
        .iter()
        .copied()
        .collect();
    let p = problem(&w, &q, &[f64::INFINITY, f64::INFINITY]);
    for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
        let report = solve_tight(&p, mode);
        assert_eq!(report.status, SolveStatus::Converged);
        assert_close(&report.r, &exact, 1e-8);
        assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
    }
}

#[test]
fn relaxed_sliding_opens_the_contact_and_coulomb_does_not() {
    let w = DMatrix::identity(3, 3);
    let p = problem(&w, &[-1.0, 2.0, 0.0], &[0.3]);
    let relaxed = solve(&p, ConicMode::Relaxed);
    assert_eq!(relaxed.status, SolveStatus::Converged);
    let u = p.velocity(&relaxed.r);
    let slip = u[1].hypot(u[2]);
    // The associated law: u_N = mu |u_T| > 0, r on the cone; here r = P_K(-q).
    assert!(u[0] > 0.4, "{u:?}");
    assert!((u[0] - 0.3 * slip).abs() <= 1e-7 * slip, "{u:?}");
    assert!(associated_natural_map(&p, &relaxed.r) <= 1e-7);
    assert!(natural_map_error(&p, &relaxed.r).relative > 0.1);

    let coulomb = solve(&p, ConicMode::Coulomb);
    assert_eq!(
        coulomb.status,
        SolveStatus::Converged,
        "{:?}",
        coulomb.notes
    );
    assert_close(&coulomb.r, &[1.0, -0.3, 0.0], 1e-8);
    let u = p.velocity(&coulomb.r);
    assert!(u[0].abs() < 1e-8 && u[1] > 1.6, "{u:?}");
    assert!(natural_map_error(&p, &coulomb.r).relative <= 1e-7);
    assert!(coulomb.outer_iterations >= 1);
}

/// Contact 1 is separated in the frictionless start (bound 0, an SOC without interior) and
/// is pressed closed by contact 0's friction through the coupling W_{N1,T0}.
fn friction_closes_a_contact() -> ContactProblem {
    let mut w = DMatrix::identity(6, 6);
    w[(3, 1)] = 0.5;
    w[(1, 3)] = 0.5;
    problem(&w, &[-1.0, 2.0, 0.0, 0.1, 0.5, 0.0], &[0.3, 0.3])
}

#[test]
fn coulomb_handles_zero_tresca_bounds() {
    let p = friction_closes_a_contact();
    let relaxed = solve(&p, ConicMode::Relaxed);
    assert_eq!(relaxed.status, SolveStatus::Converged);
    let report = solve(&p, ConicMode::Coulomb);
    assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
    // Exact: contact 0 slides (u_N = 0, u_T = 1.725 > 0); contact 1 is closed by
    // W_{N1,T0} r_T0 = -0.15 against its gap 0.1 and slides too (u_T = 0.485 > 0).
    assert_close(&report.r, &[1.0, -0.3, 0.0, 0.05, -0.015, 0.0], 1e-7);
    // Its friction needs the second Tresca solve (bound 0 in the first).
    assert!(report.outer_iterations >= 2);
    assert!(
        natural_map_error(&p, &report.r).relative <= 1e-7,
        "{:?}",
        report.r
    );
    // A contact separated throughout keeps a zero bound every iteration.
    let p = problem(
        &DMatrix::identity(6, 6),
        &[-1.0, 2.0, 0.0, 0.5, 1.0, 0.0],
        &[0.3, 0.3],
    );
    let report = solve(&p, ConicMode::Coulomb);
    assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
    assert_close(&report.r, &[1.0, -0.3, 0.0, 0.0, 0.0, 0.0], 1e-8);
    assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
}

/// What Clarabel does with an SOC without interior (`|r_T| <= 0`), on a contact whose
/// tangential load would make it slide: it reports Solved, with `r_T` at roundoff.
#[test]
fn a_zero_tresca_bound_is_solved_with_zero_tangential_force() {
    let w = coupled_w();
    let q = [-1.0, 2.0, -1.0, -1.0, -0.5, 0.3];
    let p = problem(&w, &q, &[0.3, 0.3]);
    let limits = SolveLimits::default();
    let clock = Instant::now();
    let solver = ConicSolver::new(ConicMode::Coulomb);
    let mut run = Run::new(&solver, &p, &limits, clock);
    let frictionless = ConicProgram::build(&p, &contact_laws(&p, |_| Law::Frictionless));
    let reference = run.solve_once(&frictionless).unwrap();
    assert_eq!(reference.status, SolverStatus::Solved);
    let reference = frictionless.r_of(&reference.x);
    for bound in [0.0, 1e-300] {
        let laws = contact_laws(&p, |_| Law::Tresca { bound });
        let solve = run.solve_once(&ConicProgram::build(&p, &laws)).unwrap();
        println!(
            "bound {bound:e}: {:?} in {} iterations",
            solve.status, solve.iterations
        );
        assert_eq!(solve.status, SolverStatus::Solved);
        let r = ConicProgram::build(&p, &laws).r_of(&solve.x);
        assert_close(&r, &reference, 1e-7);
    }
}

#[test]
fn caps_and_limits_are_reported_not_hidden() {
    let p = friction_closes_a_contact();
    let mut solver = ConicSolver::new(ConicMode::Coulomb);
    solver.max_outer = 1;
    let report = solver.solve(&p, &SolveLimits::default()).unwrap();
    assert_eq!(report.status, SolveStatus::MaxIterations);
    assert_eq!(report.outer_iterations, 1);
    let few = SolveLimits {
        max_iterations: 1,
        ..Default::default()
    };
    let report = ConicSolver::new(ConicMode::Relaxed)
        .solve(&p, &few)
        .unwrap();
    assert_eq!(report.status, SolveStatus::MaxIterations);
    assert_eq!(report.r.len(), 6);
    assert!(report.r.iter().all(|v| v.is_finite()));
    let none = SolveLimits {
        time_limit: Some(Duration::ZERO),
        ..Default::default()
    };
    for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
        let report = ConicSolver::new(mode).solve(&p, &none).unwrap();
        assert_eq!(report.status, SolveStatus::TimeLimit, "{mode:?}");
    }
}

#[test]
fn asymmetry_is_removed_and_reported() {
    let mut w = coupled_w();
    w[(3, 0)] += 1e-3;
    let sym = (&w + w.transpose()) * 0.5;
    let q = [-1.0, 0.0, 0.0, -2.0, 0.0, 0.0];
    let report = solve(&problem(&w, &q, &[0.0, 0.0]), ConicMode::Relaxed);
    assert!(
        report.notes.iter().any(|n| n.contains("asymmetry")),
        "{:?}",
        report.notes
    );
    let symmetric = solve(&problem(&sym, &q, &[0.0, 0.0]), ConicMode::Relaxed);
    assert!(symmetric.notes.is_empty());
    assert_close(&report.r, &symmetric.r, 1e-8);
}

#[test]
fn invalid_problems_are_errors_and_empty_ones_trivial() {
    let p = problem(&DMatrix::identity(3, 3), &[-1.0, 0.0, 0.0], &[-0.1]);
    let err = ConicSolver::new(ConicMode::Relaxed).solve(&p, &SolveLimits::default());
    assert!(matches!(
        err,
        Err(ContactSolverError::InvalidProblem { .. })
    ));
    let empty = problem(&DMatrix::zeros(0, 0), &[], &[]);
    let report = solve(&empty, ConicMode::Coulomb);
    assert_eq!(report.status, SolveStatus::Converged);
    assert!(report.r.is_empty());
    assert_eq!(ConicSolver::new(ConicMode::Coulomb).name(), "conic/coulomb");
    assert_eq!(ConicSolver::new(ConicMode::Relaxed).name(), "conic/relaxed");
}

/// The problem of the fuzz findings (N2), `q = [-1e300, 2e300, 3e300]`, `mu = 0.1`, with an
/// isotropic tangential block, `W = diag(15, 14, 14)` (N2 has 14, 16). Its Coulomb solution is
/// finite and analytic: the contact is closed (`u_N = 0`, `r_N = 1e300 / 15`), and it slides,
/// because sticking needs `|r_T| = |q_T| / 14 = 2.6e299 > mu r_N = 6.7e297`; sliding with
/// `W_TT = 14 I` puts `r_T = -mu r_N q_T / |q_T|`, opposite to `u_T`, which is along `q_T`.
#[test]
fn huge_q_is_solved_to_its_analytic_coulomb_solution() {
    let w = DMatrix::from_row_slice(3, 3, &[15.0, 0.0, 0.0, 0.0, 14.0, 0.0, 0.0, 0.0, 14.0]);
    let p = problem(&w, &[-1e300, 2e300, 3e300], &[0.1]);
    let r_n = 1e300 / 15.0;
    let q_t = (2e300f64).hypot(3e300);
    let exact = [r_n, -0.1 * r_n * (2e300 / q_t), -0.1 * r_n * (3e300 / q_t)];
    assert!(exact.iter().all(|v| v.is_finite()), "{exact:?}");
    let report = solve_tight(&p, ConicMode::Coulomb);
    assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
    assert_close(&report.r, &exact, 1e-6);
    let relaxed = solve(&p, ConicMode::Relaxed);
    assert!(relaxed.r.iter().all(|v| v.is_finite()), "{:?}", relaxed.r);
}

/// `W = 1e-10 I`, `q = [-1e300, 0, 0]`: the exact `r_N = 1e310` is beyond f64. The program is
/// solved scaled (to `W = I`, `q = [-1, 0, 0]`) and converges; the multipliers scaled back are
/// infinite, and a solve that returns them must not report convergence.
#[test]
fn multipliers_that_overflow_are_a_failure_not_convergence() {
    let w = DMatrix::from_diagonal_element(3, 3, 1e-10);
    let p = problem(&w, &[-1e300, 0.0, 0.0], &[0.1]);
    for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
        let report = solve(&p, mode);
        assert!(report.r[0].is_infinite(), "{mode:?}: {:?}", report.r);
        assert!(
            matches!(&report.status, SolveStatus::Failed(why) if why.contains("not finite")),
            "{mode:?}: {:?}",
            report.status
        );
    }
}
