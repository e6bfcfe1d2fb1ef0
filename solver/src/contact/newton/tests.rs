//! The Newton solver against Gauss-Seidel on problems both solve, and its convergence rate.

use nalgebra::Matrix3;

use super::*;
use crate::contact::problem::SparseMatrix;

fn limits(tolerance: f64) -> SolveLimits {
    SolveLimits {
        tolerance,
        max_iterations: 100,
        time_limit: None,
    }
}

/// Three slaves over one shared face, as the stepper builds them (lumped masses): the
/// Gauss-Seidel tests' fixture, assembled.
fn coupled(friction: f64) -> ContactProblem {
    let (c, inverse_mass, x) = crate::contact::nsgs::tests::coupled(friction);
    ContactProblem::from_constraints(&c, &inverse_mass, 1e-2, &x, "coupled".into())
}

/// A dense SPD problem of `nc` contacts with random data.
fn random_problem(nc: usize, seed: u64, mu: f64) -> ContactProblem {
    let mut rng = crate::rng::SplitMix64::new(seed);
    let n = 3 * nc;
    let m: Vec<f64> = (0..n * n).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let mut triplets = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let v: f64 = (0..n).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>() / n as f64;
            triplets.push((i, j, v + if i == j { 0.1 } else { 0.0 }));
        }
    }
    ContactProblem {
        w: SparseMatrix::from_triplets(n, &triplets).unwrap(),
        q: (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect(),
        mu: vec![mu; nc],
        frames: None,
        compliance: 1.0,
        source: format!("random {seed}"),
    }
}

#[test]
fn it_agrees_with_gauss_seidel_on_the_steppers_problems() {
    for friction in [0.0, 0.3, f64::INFINITY] {
        let problem = coupled(friction);
        let newton = AlartCurnierNewton::default()
            .solve(&problem, &limits(1e-13))
            .unwrap();
        assert!(newton.status.converged(), "{friction}: {:?}", newton.status);
        assert!(newton.notes.is_empty(), "{friction}: {:?}", newton.notes);
        let gs = NonsmoothGaussSeidel::new(LocalSolver::Exact)
            .solve(
                &problem,
                &SolveLimits {
                    tolerance: 1e-13,
                    max_iterations: 100_000,
                    time_limit: None,
                },
            )
            .unwrap();
        assert!(gs.status.converged());
        let scale = gs.r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in newton.r.iter().zip(&gs.r) {
            assert!((a - b).abs() < 1e-9 * scale, "{friction}: {a} vs {b}");
        }
    }
}

#[test]
fn a_coupled_block_is_solved_in_a_few_newton_steps() {
    // The sliding block of the nsgs tests: one contact, strong normal-tangential coupling.
    let a = Matrix3::new(2.0, 0.6, -0.3, 0.6, 1.0, 0.2, -0.3, 0.2, 0.5);
    let triplets: Vec<_> = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j, a[(i, j)])))
        .collect();
    for mu in [0.1, 0.5, 2.0] {
        let problem = ContactProblem {
            w: SparseMatrix::from_triplets(3, &triplets).unwrap(),
            q: vec![-1.0, 0.8, 0.3],
            mu: vec![mu],
            frames: None,
            compliance: 1.0,
            source: "block".into(),
        };
        let report = AlartCurnierNewton::default()
            .solve(&problem, &limits(1e-14))
            .unwrap();
        assert!(report.status.converged(), "{mu}: {:?}", report.status);
        assert!(report.iterations <= 10, "{mu}: {}", report.iterations);
        assert!(natural_map_error(&problem, &report.r).relative <= 1e-14);
    }
}

#[test]
fn random_dense_problems_converge_without_the_fallback() {
    let (mut total, mut worst) = (0, 0);
    for seed in 0..20 {
        for mu in [0.1, 0.5, 1.0] {
            let problem = random_problem(8, seed, mu);
            let report = AlartCurnierNewton { fallback_sweeps: 0 }
                .solve(&problem, &limits(1e-12))
                .unwrap();
            assert!(
                report.status.converged(),
                "seed {seed} mu {mu}: {:?}",
                report.status
            );
            total += report.iterations;
            worst = worst.max(report.iterations);
        }
    }
    println!("iterations: mean {:.1}, most {worst}", total as f64 / 60.0);
    assert!(worst <= 50, "{worst}");
}

#[test]
fn the_sparse_and_dense_systems_give_the_same_steps() {
    // 110 contacts, 330 unknowns: above the dense threshold. The same problem with a
    // block-diagonal W is solved dense per block in effect; compare with GS exact.
    let nc = 110;
    let mut rng = crate::rng::SplitMix64::new(5);
    let mut triplets = Vec::new();
    for a in 0..nc {
        let m = Matrix3::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let b = m * m.transpose() + Matrix3::identity() * 0.2;
        for i in 0..3 {
            for j in 0..3 {
                triplets.push((3 * a + i, 3 * a + j, b[(i, j)]));
            }
        }
        // A weak coupling to the next contact's normal.
        if a + 1 < nc {
            triplets.push((3 * a, 3 * a + 3, 0.05));
            triplets.push((3 * a + 3, 3 * a, 0.05));
        }
    }
    let problem = ContactProblem {
        w: SparseMatrix::from_triplets(3 * nc, &triplets).unwrap(),
        q: (0..3 * nc).map(|_| rng.uniform(-1.0, 1.0)).collect(),
        mu: vec![0.4; nc],
        frames: None,
        compliance: 1.0,
        source: "sparse".into(),
    };
    assert!(3 * nc > linear::DENSE_UP_TO);
    let report = AlartCurnierNewton { fallback_sweeps: 0 }
        .solve(&problem, &limits(1e-12))
        .unwrap();
    assert!(report.status.converged(), "{:?}", report.status);
    assert!(natural_map_error(&problem, &report.r).relative <= 1e-12);
}

#[test]
fn a_stall_without_fallback_is_a_failure_and_with_it_the_notes_name_gauss_seidel() {
    // W = 0 with a penetrating q: Phi_N = rho_N u_N = rho_N q_N cannot be moved by r, J is
    // singular in the normal rows whatever the shift, and no step decreases the merit.
    let problem = ContactProblem {
        w: SparseMatrix::from_triplets(3, &[]).unwrap(),
        q: vec![-1.0, 0.0, 0.0],
        mu: vec![0.3],
        frames: None,
        compliance: 1.0,
        source: "no compliance".into(),
    };
    let failed = AlartCurnierNewton { fallback_sweeps: 0 }
        .solve(&problem, &limits(1e-10))
        .unwrap();
    assert!(
        matches!(failed.status, SolveStatus::Failed(_)),
        "{:?}",
        failed.status
    );
    let fallen = AlartCurnierNewton { fallback_sweeps: 5 }
        .solve(&problem, &limits(1e-10))
        .unwrap();
    assert!(
        fallen
            .notes
            .iter()
            .any(|n| n.contains("gauss-seidel/exact answered")),
        "{:?}",
        fallen.notes
    );
}
