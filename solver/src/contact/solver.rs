//! The interface every contact solver offers on FC(W, q, mu) (see `problem.rs`), so the harness
//! can run them on identical problems and measure them with one residual, and the time stepper
//! calls each of them the same way.
//!
//! Two inputs, one trait: [`ContactSolver::solve`] takes the assembled problem (W, q, mu), which
//! every solver accepts; [`ContactSolver::solve_matrix_free`] takes the stepper's constraints on
//! the predicted positions, which a solver that never needs W (the thesis Gauss-Seidel, Box 6.1)
//! solves directly, so the stepper assembles W only for the solvers that need it or to record.

use std::time::Duration;

use nalgebra::Vector3;

use super::gauss_seidel::{ContactConstraint, ContactSolution};
use super::problem::ContactProblem;

/// How a solve ended. Non-convergence is a result to report, not an error.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveStatus {
    /// The solver's own stopping test passed.
    Converged,
    /// The iteration cap was reached first.
    MaxIterations,
    /// The time limit was reached first.
    TimeLimit,
    /// The method gave up (stalled, numerical trouble, infeasibility); the text says how, in the
    /// solver's own words (for example Clarabel's status).
    Failed(String),
}

impl SolveStatus {
    /// Whether the solver met its stopping test.
    pub fn converged(&self) -> bool {
        matches!(self, SolveStatus::Converged)
    }

    /// Short label for tables: `converged`, `max-iterations`, `time-limit`, `failed`.
    pub fn label(&self) -> &'static str {
        match self {
            SolveStatus::Converged => "converged",
            SolveStatus::MaxIterations => "max-iterations",
            SolveStatus::TimeLimit => "time-limit",
            SolveStatus::Failed(_) => "failed",
        }
    }
}

/// The multipliers a solver returned and what it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverReport {
    /// Local multipliers, `3 nc`, `[normal, tangent1, tangent2]` per contact: the best the
    /// solver has, also when it did not converge.
    pub r: Vec<f64>,
    /// How the solve ended.
    pub status: SolveStatus,
    /// Sweeps (Gauss-Seidel) or interior-point iterations summed over all conic solves.
    pub iterations: usize,
    /// Outer fixed-point iterations (the conic `coulomb` mode); 1 otherwise.
    pub outer_iterations: usize,
    /// Wall-clock time of the solve (s of real time).
    pub seconds: f64,
    /// Anything the solver wants a reader to know (removed asymmetry, fallbacks taken).
    pub notes: Vec<String>,
}

/// Setup failures: the problem cannot be posed to this solver at all.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ContactSolverError {
    /// The problem itself is inconsistent (sizes, values).
    #[error("contact problem `{problem}`: {message}")]
    InvalidProblem {
        /// The problem's source (file, run, step).
        problem: String,
        /// What is wrong with it.
        message: String,
    },
    /// The solver cannot take this problem (for example a structure it does not support).
    #[error("contact solver `{solver}` on `{problem}`: {message}. Fix: {fix}")]
    Setup {
        /// The solver's name (`registry` spelling).
        solver: String,
        /// The problem's source (file, run, step).
        problem: String,
        /// What went wrong.
        message: String,
        /// How to get a problem or a solver that works.
        fix: String,
    },
}

/// Stopping rule shared by all solvers; each states what `tolerance` bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveLimits {
    /// The bound of the solver's stopping test (relative or in the problem's scaled units, as
    /// each solver states); default 1e-8.
    pub tolerance: f64,
    /// Most iterations (sweeps, interior-point iterations) before `MaxIterations`; default
    /// 10 000.
    pub max_iterations: usize,
    /// Wall-clock budget of one solve; `None` (default): no limit.
    pub time_limit: Option<Duration>,
}

impl Default for SolveLimits {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 10_000,
            time_limit: None,
        }
    }
}

/// The time stepper's contact problem before assembly: the constraints of one detection pass on
/// the predicted positions, with the masses that turn forces into corrections,
/// `dx = beta dt^2 M^-1 C^T r` (thesis (6.71d)).
#[derive(Debug, Clone, Copy)]
pub struct PositionProblem<'a> {
    /// The contacts of the pass: slave node, master face, weights, normal, friction.
    pub constraints: &'a [ContactConstraint],
    /// Inverse lumped mass per node and component; zero where a component is prescribed.
    pub inverse_mass: &'a [Vector3<f64>],
    /// `(beta_0 + 1/2) dt^2` (6.4.2.4).
    pub beta_dt2: f64,
}

/// A contact solver on FC(W, q, mu).
pub trait ContactSolver {
    /// Name for tables and plots, the solver's spelling in the registry
    /// (`contact::registry`), for example `gauss-seidel/exact` or `conic/coulomb`.
    fn name(&self) -> String;

    /// Solves from zero multipliers.
    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError>;

    /// Solves the stepper's constraints matrix-free from zero forces, correcting the positions
    /// `x` in place, and returns the global force on each constraint's slave node.
    ///
    /// `None`, with `x` untouched, when this solver needs the assembled problem: the caller then
    /// assembles FC(W, q, mu) from the same constraints and positions and calls
    /// [`ContactSolver::solve`]. Only solvers that can work without W override this.
    fn solve_matrix_free(
        &mut self,
        problem: &PositionProblem<'_>,
        x: &mut [Vector3<f64>],
        limits: &SolveLimits,
    ) -> Option<ContactSolution> {
        let _ = (problem, x, limits);
        None
    }
}
