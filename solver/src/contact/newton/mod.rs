//! Semismooth Newton on the Alart-Curnier function (Alart & Curnier 1991; Siconos
//! `fc3d_nonsmooth_Newton_AlartCurnier`; Acary, Bremond & Huber 2018, section 4.2), globalized by
//! a Goldstein-Price line search on the merit `psi(r) = |Phi(r)|^2 / 2`.
//!
//! Each iteration evaluates `Phi(r)` and an element `J = A + B W` of its generalized Jacobian
//! (`alart_curnier`), solves `J d = -Phi` (`linear`, `faer` dense or sparse LU), and moves to
//! `r + t d` with the step `t` of the line search (`line_search`). Where `J` is singular (the
//! rank-deficient `W` of rigid-body sets) a Levenberg-Marquardt shift `delta I` is added, grown
//! until the system solves.
//!
//! Stopping: the natural-map error `||F(r)|| / ||q||` of `problem.rs`, the measure every solver
//! is judged by, at most `tolerance`.
//!
//! When Newton stalls (no step decreases `psi`, or no shift makes `J` solvable), the solve goes
//! on with nonlinear Gauss-Seidel with the exact local step from the multipliers Newton reached;
//! the report's notes then say so, and which of the two answered.

pub mod alart_curnier;
mod line_search;
pub mod linear;
#[cfg(test)]
mod tests;

use std::time::Instant;

use nalgebra::Vector3;

use super::nsgs::{LocalSolver, NonsmoothGaussSeidel};
use super::problem::{natural_map_error, ContactProblem};
use super::solver::{ContactSolver, ContactSolverError, SolveLimits, SolveStatus, SolverReport};
use alart_curnier::{alart_curnier, weights, AlartCurnierPiece};
use line_search::{goldstein_price, LineSearch};

/// The registry's name of this solver.
pub const NAME: &str = "newton/alart-curnier";

/// Semismooth Newton on the Alart-Curnier function, with a Gauss-Seidel fallback.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlartCurnierNewton {
    /// Most Gauss-Seidel sweeps of the fallback after a stall; 0: no fallback (a stall ends the
    /// solve with `Failed`).
    pub fallback_sweeps: usize,
}

impl Default for AlartCurnierNewton {
    fn default() -> Self {
        Self {
            fallback_sweeps: 100_000,
        }
    }
}

/// `Phi(r)` per contact with its derivatives, and the merit `psi = |Phi|^2 / 2`.
fn evaluate(
    problem: &ContactProblem,
    rho: &[[f64; 2]],
    r: &[f64],
) -> (Vec<AlartCurnierPiece>, f64) {
    let u = problem.velocity(r);
    let pieces: Vec<AlartCurnierPiece> = problem
        .mu
        .iter()
        .enumerate()
        .map(|(a, &mu)| {
            let ra = Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2]);
            let ua = Vector3::new(u[3 * a], u[3 * a + 1], u[3 * a + 2]);
            alart_curnier(&ra, &ua, mu, rho[a])
        })
        .collect();
    let psi = 0.5 * pieces.iter().map(|p| p.value.norm_squared()).sum::<f64>();
    (pieces, psi)
}

/// Why Newton stopped before converging.
enum Stall {
    /// No shift made `J` solvable.
    Singular,
    /// The line search found no step that decreases the merit.
    LineSearch,
}

impl ContactSolver for AlartCurnierNewton {
    fn name(&self) -> String {
        NAME.into()
    }

    /// `limits.max_iterations` bounds the Newton iterations; the fallback's sweeps are bounded
    /// by `fallback_sweeps` and by what is left of `limits.time_limit`. The reported iterations
    /// are Newton iterations plus fallback sweeps (the notes give each).
    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError> {
        let started = Instant::now();
        let nc = problem.contacts();
        let n = 3 * nc;
        if problem.q.len() != n || problem.w.size != n {
            return Err(ContactSolverError::InvalidProblem {
                problem: problem.source.clone(),
                message: format!(
                    "{nc} contacts but q has {} and W {} rows",
                    problem.q.len(),
                    problem.w.size
                ),
            });
        }
        let mean_diagonal = (0..n).map(|i| problem.w.get(i, i)).sum::<f64>() / n.max(1) as f64;
        let fallback_rho = if mean_diagonal > 0.0 {
            1.0 / mean_diagonal
        } else {
            1.0
        };
        let rho: Vec<[f64; 2]> = (0..nc)
            .map(|a| weights(&problem.w.block(a, a), fallback_rho))
            .collect();
        let mut r = vec![0.0; n];
        let (mut pieces, mut psi) = evaluate(problem, &rho, &r);
        let mut status = SolveStatus::MaxIterations;
        let mut stall = None;
        let mut iterations = 0;
        let mut shifted = 0usize;
        let mut notes = Vec::new();
        loop {
            if natural_map_error(problem, &r).relative <= limits.tolerance {
                status = SolveStatus::Converged;
                break;
            }
            if iterations >= limits.max_iterations {
                break;
            }
            if limits.time_limit.is_some_and(|l| started.elapsed() >= l) {
                status = SolveStatus::TimeLimit;
                break;
            }
            iterations += 1;
            let triplets = linear::jacobian_triplets(&problem.w, &pieces);
            let rhs: Vec<f64> = pieces
                .iter()
                .flat_map(|p| [-p.value.x, -p.value.y, -p.value.z])
                .collect();
            let scale = triplets
                .iter()
                .fold(0.0f64, |m, t| m.max(t.val.abs()))
                .max(1e-300);
            let direction =
                [0.0, 1e-12, 1e-9, 1e-6, 1e-3]
                    .iter()
                    .enumerate()
                    .find_map(|(k, &delta)| {
                        linear::solve(n, &triplets, delta * scale, &rhs).map(|d| (k > 0, d))
                    });
            let Some((was_shifted, d)) = direction else {
                stall = Some(Stall::Singular);
                break;
            };
            shifted += usize::from(was_shifted);
            let search = LineSearch::default();
            let trial = |t: f64| {
                let moved: Vec<f64> = r.iter().zip(&d).map(|(r, d)| r + t * d).collect();
                evaluate(problem, &rho, &moved).1
            };
            let Some(t) = goldstein_price(psi, -2.0 * psi, trial, &search) else {
                stall = Some(Stall::LineSearch);
                break;
            };
            r.iter_mut().zip(&d).for_each(|(r, d)| *r += t * d);
            (pieces, psi) = evaluate(problem, &rho, &r);
            if !psi.is_finite() {
                status = SolveStatus::Failed(format!(
                    "the merit is not finite at iteration {iterations}"
                ));
                break;
            }
        }
        if shifted > 0 {
            notes.push(format!(
                "{shifted} of {iterations} Newton systems were singular and took a Levenberg-Marquardt shift"
            ));
        }
        let mut total_iterations = iterations;
        if let Some(stall) = stall {
            let why = match stall {
                Stall::Singular => "no shift made the Jacobian solvable",
                Stall::LineSearch => "the line search found no decrease of the merit",
            };
            let error = natural_map_error(problem, &r).relative;
            if self.fallback_sweeps == 0 {
                status = SolveStatus::Failed(format!(
                    "Newton stalled at iteration {iterations} (natural map {error:.2e}): {why}"
                ));
            } else {
                let fallback_limits = SolveLimits {
                    max_iterations: self.fallback_sweeps,
                    ..*limits
                };
                let gs = NonsmoothGaussSeidel::new(LocalSolver::Exact).solve_from(
                    problem,
                    r,
                    &fallback_limits,
                    started,
                );
                notes.push(format!(
                    "Newton stalled at iteration {iterations} (natural map {error:.2e}): {why}; \
                     gauss-seidel/exact answered after {} sweeps ({})",
                    gs.iterations,
                    gs.status.label()
                ));
                notes.extend(gs.notes);
                total_iterations += gs.iterations;
                status = gs.status;
                r = gs.r;
            }
        }
        Ok(SolverReport {
            r,
            status,
            iterations: total_iterations,
            outer_iterations: 1,
            seconds: started.elapsed().as_secs_f64(),
            notes,
        })
    }
}
