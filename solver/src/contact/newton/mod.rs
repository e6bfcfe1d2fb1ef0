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
//! When Newton stalls (no step decreases `psi`, or no shift makes `J` solvable), nonlinear
//! Gauss-Seidel with the exact local step continues from the multipliers Newton reached until
//! the natural map has dropped a hundredfold, and Newton resumes from there (a hybrid in the
//! spirit of Siconos's NSN hybrid strategies); the report's notes then say so, and which of the
//! two answered.

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
    /// Most Gauss-Seidel sweeps after stalls, over the whole solve; 0: no fallback (a stall
    /// ends the solve with `Failed`).
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

/// How a run of Newton iterations ended.
enum NewtonEnd {
    /// The solve is over with this status (converged, cap, clock, non-finite merit).
    Done(SolveStatus),
    /// No shift made `J` solvable.
    Singular,
    /// The line search found no step that decreases the merit.
    LineSearch,
}

/// Counters over the whole solve.
#[derive(Default)]
struct Counts {
    newton: usize,
    shifted: usize,
    sweeps: usize,
}

/// Newton iterations from `r` (updated in place) until the natural map meets the tolerance, a
/// limit is reached, or Newton stalls.
fn newton_run(
    problem: &ContactProblem,
    rho: &[[f64; 2]],
    r: &mut [f64],
    limits: &SolveLimits,
    started: Instant,
    counts: &mut Counts,
) -> NewtonEnd {
    let n = r.len();
    let (mut pieces, mut psi) = evaluate(problem, rho, r);
    loop {
        if natural_map_error(problem, r).relative <= limits.tolerance {
            return NewtonEnd::Done(SolveStatus::Converged);
        }
        if counts.newton >= limits.max_iterations {
            return NewtonEnd::Done(SolveStatus::MaxIterations);
        }
        if limits.time_limit.is_some_and(|l| started.elapsed() >= l) {
            return NewtonEnd::Done(SolveStatus::TimeLimit);
        }
        counts.newton += 1;
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
            return NewtonEnd::Singular;
        };
        counts.shifted += usize::from(was_shifted);
        let trial = |t: f64| {
            let moved: Vec<f64> = r.iter().zip(&d).map(|(r, d)| r + t * d).collect();
            evaluate(problem, rho, &moved).1
        };
        let Some(t) = goldstein_price(psi, -2.0 * psi, trial, &LineSearch::default()) else {
            return NewtonEnd::LineSearch;
        };
        r.iter_mut().zip(&d).for_each(|(r, d)| *r += t * d);
        (pieces, psi) = evaluate(problem, rho, r);
        if !psi.is_finite() {
            return NewtonEnd::Done(SolveStatus::Failed(format!(
                "the merit is not finite at iteration {}",
                counts.newton
            )));
        }
    }
}

impl ContactSolver for AlartCurnierNewton {
    fn name(&self) -> String {
        NAME.into()
    }

    /// `limits.max_iterations` bounds the Newton iterations; the sweeps after stalls are bounded
    /// by `fallback_sweeps` and by what is left of `limits.time_limit`. The reported iterations
    /// are Newton iterations plus sweeps (the notes give each, and which method answered).
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
        let mut counts = Counts::default();
        let mut notes = Vec::new();
        let mut stalls = 0usize;
        // Newton, and on each stall Gauss-Seidel sweeps from where Newton stopped until the
        // natural map has dropped a hundredfold (or meets the tolerance), then Newton again
        // from there: the sweeps move the multipliers off the point where the merit's model
        // failed, and Newton's fast local convergence resumes nearer the solution.
        let status = loop {
            let why = match newton_run(problem, &rho, &mut r, limits, started, &mut counts) {
                NewtonEnd::Done(status) => break status,
                NewtonEnd::Singular => "no shift made the Jacobian solvable",
                NewtonEnd::LineSearch => "the line search found no decrease of the merit",
            };
            let error = natural_map_error(problem, &r).relative;
            stalls += 1;
            if self.fallback_sweeps == 0 {
                break SolveStatus::Failed(format!(
                    "Newton stalled at iteration {} (natural map {error:.2e}): {why}",
                    counts.newton
                ));
            }
            let sweeps_left = self.fallback_sweeps.saturating_sub(counts.sweeps);
            let gs_limits = SolveLimits {
                tolerance: (1e-2 * error).max(limits.tolerance),
                max_iterations: sweeps_left,
                time_limit: limits.time_limit,
            };
            let gs = NonsmoothGaussSeidel::new(LocalSolver::Exact).solve_from(
                problem,
                std::mem::take(&mut r),
                &gs_limits,
                started,
            );
            counts.sweeps += gs.iterations;
            r = gs.r;
            if stalls == 1 {
                notes.push(format!(
                    "Newton stalled at iteration {} (natural map {error:.2e}): {why}; \
                     gauss-seidel/exact sweeps took over",
                    counts.newton
                ));
            }
            let reached = natural_map_error(problem, &r).relative;
            if reached <= limits.tolerance {
                notes.push(format!(
                    "gauss-seidel/exact answered after {} Newton iterations, {} sweeps, {stalls} stalls",
                    counts.newton, counts.sweeps
                ));
                break SolveStatus::Converged;
            }
            if !gs.status.converged() {
                notes.push(format!(
                    "gauss-seidel/exact answered ({}) after {} Newton iterations, {} sweeps, {stalls} stalls",
                    gs.status.label(),
                    counts.newton,
                    counts.sweeps
                ));
                break gs.status;
            }
        };
        if stalls > 0 && status.converged() && !notes.iter().any(|n| n.contains("answered")) {
            notes.push(format!(
                "Newton answered after {} iterations, {} Gauss-Seidel sweeps, {stalls} stalls",
                counts.newton, counts.sweeps
            ));
        }
        if counts.shifted > 0 {
            notes.push(format!(
                "{} of {} Newton systems were singular and took a Levenberg-Marquardt shift",
                counts.shifted, counts.newton
            ));
        }
        let total_iterations = counts.newton + counts.sweeps;
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
