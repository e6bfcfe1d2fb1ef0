//! Contact as a conic program solved by Clarabel (FORMULATION section 4, "Conic solver").
//!
//! Every mode minimises the quadratic `1/2 r^T W r + q^T r` over the multipliers `r` (three per
//! contact, local order `[normal, t1, t2]`) on a product of cones, one factor per contact:
//!
//! - frictionless (`mu = 0`): `r_N >= 0`, `r_T = 0`. The tangential components are eliminated
//!   from the program (they are not variables at all), so a frictionless problem is the QP in the
//!   normal components with `P = W_NN`. Its optimality conditions are Signorini's, so the result
//!   is the exact solution of FC(W, q, 0). (A second-order cone with `mu = 0` is never used: it
//!   would force `r_T = 0` but leave `r_N` free.)
//! - stick (`mu = inf`): `r_N >= 0`, `r_T` free; optimality gives `u_T = 0`, the stick law.
//! - Coulomb (`0 < mu < inf`) depends on [`ConicMode`]:
//!   - [`ConicMode::Relaxed`]: `(mu r_N, r_T)` in a second-order cone, one SOCP. This is the
//!     associated (convex) relaxation of Coulomb's law (Anitescu & Tasora 2010; Acary, Cadoux,
//!     Lemarechal & Malick 2011, "convex relaxation"): its optimality conditions are
//!     `K ∋ r _|_ u ∈ K*` without the De Saxce shift, so a sliding contact opens normally,
//!     `u_N = mu |u_T|`, about `mu` times its slip. It is not the Coulomb solution.
//!   - [`ConicMode::Coulomb`]: a fixed point on the normal force (Acary, Cadoux, Lemarechal &
//!     Malick 2011, the Tresca fixed point): solve Tresca problems `|r_T| <= s_a`, `r_N >= 0` with
//!     `s_a = mu_a r_N,a` of the previous iterate, until the normal forces stop changing. A fixed
//!     point satisfies Coulomb's law exactly; convergence is not guaranteed (it is for small `mu`
//!     times the normal-tangential coupling), hence the cap [`ConicSolver::max_outer`].
//!
//! Clarabel solves `min 1/2 x^T P x + c^T x` s.t. `A x + s = b`, `s ∈ K`, reading only the upper
//! triangle of `P`; `P = (W + W^T)/2` is built explicitly and any asymmetry of `W` is reported
//! in the notes, because a one-triangle solver otherwise solves a different problem unnoticed.

mod program;
mod run;
#[cfg(test)]
mod tests;

use std::time::Instant;

use nalgebra::Vector3;

use super::problem::{contact_natural_map, project_on_coulomb_cone, ContactProblem};
use super::solver::{ContactSolver, ContactSolverError, SolveLimits, SolveStatus, SolverReport};
use program::{contact_laws, ConicProgram, Law};
use run::Run;

/// How Coulomb contacts (`0 < mu < inf`) enter the conic program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConicMode {
    /// One SOCP with the associated (convex) relaxation `(mu r_N, r_T) ∈ SOC`; sliding contacts
    /// open normally by about `mu` times their slip. Not Coulomb's law.
    Relaxed,
    /// Fixed point of Tresca problems on the normal force; converges to Coulomb's law.
    Coulomb,
}

/// FC(W, q, mu) as conic programs for Clarabel (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConicSolver {
    /// One relaxed SOCP, or the Tresca fixed point that converges to Coulomb's law.
    pub mode: ConicMode,
    /// Cap on the Tresca solves of the Coulomb fixed point (ignored by the relaxed mode).
    pub max_outer: usize,
}

impl ConicSolver {
    /// The solver in `mode`, with at most 50 Tresca solves for the Coulomb fixed point.
    pub fn new(mode: ConicMode) -> Self {
        Self {
            mode,
            max_outer: 50,
        }
    }
}

impl ContactSolver for ConicSolver {
    fn name(&self) -> String {
        match self.mode {
            ConicMode::Relaxed => "conic/relaxed".into(),
            ConicMode::Coulomb => "conic/coulomb".into(),
        }
    }

    /// `limits.tolerance` is Clarabel's tolerance (duality gap, absolute and relative, and
    /// feasibility) of the single conic solve; in the Coulomb mode it bounds the relative change
    /// of the normal forces between two Tresca solves (2-norms), and each conic solve gets a
    /// tenth of it. `max_iterations` caps the interior-point iterations of each conic solve;
    /// `time_limit` covers the whole call (each solve gets the time left).
    ///
    /// Clarabel's tolerances are absolute where the objective is below one, so the program is
    /// solved on the problem scaled to `W / w` and `q / s` (`w` the mean diagonal of `W`, `s`
    /// the largest `|q|`); the solution `r = r~ s / w` is the same, because FC(W, q, mu) is
    /// homogeneous. Natural-map tests inside (AlmostSolved) read the scaled problem.
    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError> {
        let clock = Instant::now();
        validate(problem)?;
        let n = problem.w.size;
        let trace: f64 = (0..n).map(|i| problem.w.get(i, i)).sum();
        let w_scale = if trace > 0.0 { trace / n as f64 } else { 1.0 };
        let q_scale = problem.q.iter().fold(0.0f64, |m, q| m.max(q.abs()));
        if q_scale == 0.0 || (w_scale == 1.0 && q_scale == 1.0) {
            return self
                .solve_scaled(problem, limits, clock)
                .map(refuse_non_finite);
        }
        let mut scaled = problem.clone();
        scaled.w.values.iter_mut().for_each(|v| *v /= w_scale);
        scaled.q.iter_mut().for_each(|v| *v /= q_scale);
        let mut report = self.solve_scaled(&scaled, limits, clock)?;
        let back = q_scale / w_scale;
        report.r.iter_mut().for_each(|r| *r *= back);
        Ok(refuse_non_finite(report))
    }
}

/// A report whose multipliers are not all finite is a failure, whatever Clarabel said: the
/// scaled program can converge while `r = r~ |q|_max / w` overflows f64 (a tiny `W` against a
/// huge `q`), and a caller must not take infinite forces as a solution.
fn refuse_non_finite(mut report: SolverReport) -> SolverReport {
    if report.r.iter().all(|v| v.is_finite()) {
        return report;
    }
    let why = "the multipliers are not finite (they overflow f64 once scaled back from the \
               program's units)";
    report.notes.push(format!(
        "solve ended {} but {why}; reported as failed",
        report.status.label()
    ));
    report.status = SolveStatus::Failed(why.into());
    report
}

impl ConicSolver {
    fn solve_scaled(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
        clock: Instant,
    ) -> Result<SolverReport, ContactSolverError> {
        let mut run = Run::new(self, problem, limits, clock);
        run.note_asymmetry();
        if problem.contacts() == 0 {
            return Ok(run.finish(Vec::new(), SolveStatus::Converged));
        }
        let has_coulomb = problem.mu.iter().any(|m| *m > 0.0 && m.is_finite());
        let (r, status) = if self.mode == ConicMode::Coulomb && has_coulomb {
            run.coulomb_fixed_point()?
        } else {
            // One program: relaxed cones for Coulomb contacts (only reached in relaxed mode or
            // when there are none).
            let laws = contact_laws(problem, |mu| Law::Associated { mu });
            let program = ConicProgram::build(problem, &laws);
            let solve = run.solve_once(&program)?;
            run.outer_iterations = 1;
            run.conclude_single(&program, solve)
        };
        Ok(run.finish(r, status))
    }
}

/// Relative natural-map residual of the problem the single program solves: Coulomb contacts
/// with the associated law `r - P_K(r - u)` (no De Saxce shift), the others as in
/// [`natural_map_error`](crate::contact::problem::natural_map_error); same `/||q||` normalisation.
pub fn associated_natural_map(problem: &ContactProblem, r: &[f64]) -> f64 {
    let u = problem.velocity(r);
    let mut sum = 0.0;
    for (a, &mu) in problem.mu.iter().enumerate() {
        let ra = Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2]);
        let ua = Vector3::new(u[3 * a], u[3 * a + 1], u[3 * a + 2]);
        let f = if mu > 0.0 && mu.is_finite() {
            ra - project_on_coulomb_cone(&(ra - ua), mu)
        } else {
            contact_natural_map(&ra, &ua, mu)
        };
        sum += f.norm_squared();
    }
    let q = problem.q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if q > 0.0 {
        sum.sqrt() / q
    } else {
        sum.sqrt()
    }
}

/// Sizes agree, numbers are finite, `mu` is `>= 0` or `+inf`.
fn validate(problem: &ContactProblem) -> Result<(), ContactSolverError> {
    let invalid = |message: String| ContactSolverError::InvalidProblem {
        problem: problem.source.clone(),
        message,
    };
    let n = 3 * problem.contacts();
    if problem.q.len() != n || problem.w.size != n {
        return Err(invalid(format!(
            "{} contacts need q and W of size {n}; got q {} and W {}",
            problem.contacts(),
            problem.q.len(),
            problem.w.size
        )));
    }
    if let Some(a) = problem.mu.iter().position(|m| m.is_nan() || *m < 0.0) {
        return Err(invalid(format!("mu[{a}] = {} is not >= 0", problem.mu[a])));
    }
    if problem
        .q
        .iter()
        .chain(&problem.w.values)
        .any(|v| !v.is_finite())
    {
        return Err(invalid("W or q holds a non-finite value".into()));
    }
    Ok(())
}
