//! Nonlinear (projected) Gauss-Seidel on FC(W, q, mu) (thesis Box 6.1; Jean 1999; the NSGS of
//! Acary, Bremond & Huber 2018).
//!
//! The matrix-free `gauss_seidel` of the time stepper is this iteration with the thesis local
//! step on our own problems (it reads the gaps from the corrected positions instead of `W r + q`;
//! the two are equal, see the test `the_stepper_iteration_is_nsgs_with_the_thesis_step`); it is
//! what [`ContactSolver::solve_matrix_free`] of the thesis variant runs, so the stepper reaches it
//! through the trait without assembling W.

use std::time::Instant;

use nalgebra::{Matrix3, Vector3};

use super::gauss_seidel::{gauss_seidel, ContactSolution, GaussSeidelSettings};
use super::local::{exact_step, thesis_step, LocalCase};
use super::problem::{natural_map_error, ContactProblem};
use super::solver::{
    ContactSolver, ContactSolverError, PositionProblem, SolveLimits, SolveStatus, SolverReport,
};

/// The one-contact step of each Gauss-Seidel update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LocalSolver {
    /// The thesis step (6.71)-(6.77): close the gap with the block's diagonal, clamp, return
    /// radially. Exact for blocks that are multiples of the identity (ours, lumped mass).
    Thesis,
    /// Exact for a general 3x3 block: separation, stick, or slip found by a scan of the slip
    /// direction (`local::exact_step`).
    Exact,
}

/// Nonlinear Gauss-Seidel over the contacts in their order.
///
/// Stopping: after each sweep the cheap change `||r_k - r_{k-1}|| / ||r_k||` is formed; when it
/// is at most `tolerance` (and every tenth sweep), the natural-map error `||F(r)|| / ||q||` is
/// computed, and the solve has converged when that is at most `tolerance` (the "light error, full
/// final" of Siconos).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NonsmoothGaussSeidel {
    /// The one-contact step of each update: the thesis step or the exact one.
    pub local: LocalSolver,
}

impl NonsmoothGaussSeidel {
    /// The solver with the one-contact step `local`.
    pub fn new(local: LocalSolver) -> Self {
        Self { local }
    }
}

impl ContactSolver for NonsmoothGaussSeidel {
    fn name(&self) -> String {
        match self.local {
            LocalSolver::Thesis => "gauss-seidel/thesis".into(),
            LocalSolver::Exact => "gauss-seidel/exact".into(),
        }
    }

    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError> {
        let started = Instant::now();
        let nc = problem.contacts();
        if problem.q.len() != 3 * nc || problem.w.size != 3 * nc {
            return Err(ContactSolverError::InvalidProblem {
                problem: problem.source.clone(),
                message: format!(
                    "{nc} contacts but q has {} and W {} rows",
                    problem.q.len(),
                    problem.w.size
                ),
            });
        }
        Ok(self.solve_from(problem, vec![0.0; 3 * nc], limits, started))
    }

    /// The thesis variant runs the stepper's matrix-free iteration
    /// ([`super::gauss_seidel::gauss_seidel`], Box 6.1) with `limits.tolerance`
    /// and `limits.max_iterations` as its stopping rule; it has no clock, so `time_limit` is not
    /// read. The exact local step needs the off-diagonal terms of each block, hence W: `None`.
    fn solve_matrix_free(
        &mut self,
        problem: &PositionProblem<'_>,
        x: &mut [Vector3<f64>],
        limits: &SolveLimits,
    ) -> Option<ContactSolution> {
        (self.local == LocalSolver::Thesis).then(|| {
            let settings = GaussSeidelSettings {
                tolerance: limits.tolerance,
                max_iterations: limits.max_iterations,
            };
            gauss_seidel(
                problem.constraints,
                problem.inverse_mass,
                problem.beta_dt2,
                x,
                &settings,
            )
        })
    }
}

impl NonsmoothGaussSeidel {
    /// The sweeps of [`ContactSolver::solve`] from the multipliers `r` (`3 nc` values, sizes
    /// checked by the caller) instead of zero, with the clock of `limits.time_limit` started at
    /// `started`: the fallback of a Newton solve that stalled continues from where it stopped.
    pub fn solve_from(
        &self,
        problem: &ContactProblem,
        mut r: Vec<f64>,
        limits: &SolveLimits,
        started: Instant,
    ) -> SolverReport {
        let nc = problem.contacts();
        let blocks: Vec<Matrix3<f64>> = (0..nc).map(|a| problem.w.block(a, a)).collect();
        let mut fallbacks = 0usize;
        let mut status = SolveStatus::MaxIterations;
        let mut iterations = 0;
        for sweep in 1..=limits.max_iterations {
            iterations = sweep;
            let (mut change, mut total) = (0.0, 0.0);
            for (a, block) in blocks.iter().enumerate() {
                let ra = Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2]);
                let u = Vector3::from_fn(|k, _| {
                    problem.w.row_dot(3 * a + k, &r) + problem.q[3 * a + k]
                });
                let next = match self.local {
                    LocalSolver::Thesis => thesis_step(block, &ra, &u, problem.mu[a]),
                    LocalSolver::Exact => {
                        let (next, case) = exact_step(block, &(u - block * ra), problem.mu[a], &ra);
                        fallbacks += usize::from(case == LocalCase::Fallback);
                        next
                    }
                };
                change += (next - ra).norm_squared();
                total += next.norm_squared();
                r[3 * a..3 * a + 3].copy_from_slice(next.as_slice());
            }
            let light = if total > 0.0 {
                (change / total).sqrt()
            } else {
                change.sqrt()
            };
            // The natural map is a sweep's cost: checked when the change is small, and every
            // tenth sweep, because on rank-deficient W the multipliers can keep drifting along
            // the null space after the law already holds.
            if (light <= limits.tolerance || sweep % 10 == 0)
                && natural_map_error(problem, &r).relative <= limits.tolerance
            {
                status = SolveStatus::Converged;
                break;
            }
            if !light.is_finite() {
                status = SolveStatus::Failed(format!("multipliers diverged at sweep {sweep}"));
                break;
            }
            if limits
                .time_limit
                .is_some_and(|limit| started.elapsed() >= limit)
            {
                status = SolveStatus::TimeLimit;
                break;
            }
        }
        let mut notes = Vec::new();
        if fallbacks > 0 {
            notes.push(format!(
                "{fallbacks} local solves found no slip direction and took the thesis step"
            ));
        }
        SolverReport {
            r,
            status,
            iterations,
            outer_iterations: 1,
            seconds: started.elapsed().as_secs_f64(),
            notes,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::contact::gauss_seidel::ContactConstraint;
    use crate::contact::problem::SparseMatrix;

    /// Three slaves over one shared face, with friction, as in the stepper.
    pub(in crate::contact) fn coupled(
        friction: f64,
    ) -> (Vec<ContactConstraint>, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.2, 0.2, -2e-3),
            Vector3::new(0.5, 0.3, -1e-3),
            Vector3::new(0.3, 0.5, 5e-4),
        ];
        let inverse_mass: Vec<Vector3<f64>> = [1.0, 0.5, 2.0, 1.0, 3.0, 1.5]
            .iter()
            .map(|&m| Vector3::repeat(m))
            .collect();
        let normal = Vector3::new(0.2, -0.1, 1.0).normalize();
        let make = |slave: u32, weights: [f64; 3]| ContactConstraint {
            slave,
            face: [0, 1, 2],
            weights,
            normal,
            friction,
            allowance: 0.0,
        };
        let c = vec![
            make(3, [0.6, 0.2, 0.2]),
            make(4, [0.2, 0.5, 0.3]),
            make(5, [0.2, 0.3, 0.5]),
        ];
        (c, inverse_mass, x)
    }

    #[test]
    fn the_stepper_iteration_is_nsgs_with_the_thesis_step() {
        for friction in [0.0, 0.3, f64::INFINITY] {
            let (c, inverse_mass, x) = coupled(friction);
            let beta_dt2 = 1e-2;
            let problem =
                ContactProblem::from_constraints(&c, &inverse_mass, beta_dt2, &x, "test".into());
            let mut moved = x.clone();
            let settings = GaussSeidelSettings {
                tolerance: 1e-14,
                max_iterations: 10_000,
            };
            let stepper = gauss_seidel(&c, &inverse_mass, beta_dt2, &mut moved, &settings);
            let limits = SolveLimits {
                tolerance: 1e-13,
                ..Default::default()
            };
            let nsgs = NonsmoothGaussSeidel::new(LocalSolver::Thesis)
                .solve(&problem, &limits)
                .unwrap();
            assert!(nsgs.status.converged(), "{friction}: {:?}", nsgs.status);
            let expected = problem.to_local(&stepper.forces).unwrap();
            let scale = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (got, want) in nsgs.r.iter().zip(&expected) {
                assert!(
                    (got - want).abs() < 1e-10 * scale,
                    "{friction}: {got} vs {want}"
                );
            }
            assert!(natural_map_error(&problem, &nsgs.r).relative < 1e-12);
        }
    }

    #[test]
    fn only_the_thesis_step_works_matrix_free_and_it_is_the_stepper_iteration() {
        let (c, inverse_mass, x) = coupled(0.3);
        let problem = PositionProblem {
            constraints: &c,
            inverse_mass: &inverse_mass,
            beta_dt2: 1e-2,
        };
        let limits = SolveLimits {
            tolerance: 1e-12,
            max_iterations: 1000,
            time_limit: None,
        };
        // The exact step needs W: no answer, and the positions are left for the caller to
        // assemble from.
        let mut untouched = x.clone();
        assert!(NonsmoothGaussSeidel::new(LocalSolver::Exact)
            .solve_matrix_free(&problem, &mut untouched, &limits)
            .is_none());
        assert_eq!(untouched, x);
        let mut through_trait = x.clone();
        let solved = NonsmoothGaussSeidel::new(LocalSolver::Thesis)
            .solve_matrix_free(&problem, &mut through_trait, &limits)
            .unwrap();
        let mut direct = x.clone();
        let settings = GaussSeidelSettings {
            tolerance: 1e-12,
            max_iterations: 1000,
        };
        let expected = gauss_seidel(&c, &inverse_mass, 1e-2, &mut direct, &settings);
        assert!(expected.converged);
        assert_eq!(solved, expected);
        assert_eq!(through_trait, direct);
    }

    #[test]
    fn a_general_block_needs_the_exact_local_solver() {
        // One contact with a coupled SPD block, sliding: the thesis step iterates on without
        // the block's coupling; the exact step solves it in one sweep.
        let a = [[2.0, 0.6, -0.3], [0.6, 1.0, 0.2], [-0.3, 0.2, 0.5]];
        let triplets: Vec<_> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j, a[i][j])))
            .collect();
        let problem = ContactProblem {
            w: SparseMatrix::from_triplets(3, &triplets).unwrap(),
            q: vec![-1.0, 0.8, 0.3],
            mu: vec![0.1],
            frames: None,
            compliance: 1.0,
            source: "block".into(),
        };
        let limits = SolveLimits {
            tolerance: 1e-12,
            max_iterations: 1000,
            time_limit: None,
        };
        let exact = NonsmoothGaussSeidel::new(LocalSolver::Exact)
            .solve(&problem, &limits)
            .unwrap();
        assert!(exact.status.converged());
        assert!(exact.iterations <= 2, "{}", exact.iterations);
        let thesis = NonsmoothGaussSeidel::new(LocalSolver::Thesis)
            .solve(&problem, &limits)
            .unwrap();
        assert!(thesis.iterations > exact.iterations);
    }
}
