//! The interface every contact solver offers on FC(W, q, mu) (see `problem.rs`), so the harness
//! can run them on identical problems and measure them with one residual.

use std::time::Duration;

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
    pub status: SolveStatus,
    /// Sweeps (Gauss-Seidel) or interior-point iterations summed over all conic solves.
    pub iterations: usize,
    /// Outer fixed-point iterations (the conic `coulomb` mode); 1 otherwise.
    pub outer_iterations: usize,
    pub seconds: f64,
    /// Anything the solver wants a reader to know (removed asymmetry, fallbacks taken).
    pub notes: Vec<String>,
}

/// Setup failures: the problem cannot be posed to this solver at all.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ContactSolverError {
    #[error("contact problem `{problem}`: {message}")]
    InvalidProblem { problem: String, message: String },
    #[error("contact solver `{solver}` on `{problem}`: {message}. Fix: {fix}")]
    Setup {
        solver: String,
        problem: String,
        message: String,
        fix: String,
    },
}

/// Stopping rule shared by all solvers; each states what `tolerance` bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveLimits {
    pub tolerance: f64,
    pub max_iterations: usize,
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

/// A contact solver on FC(W, q, mu).
pub trait ContactSolver {
    /// Name for tables and plots, for example `gauss-seidel/exact` or `conic/coulomb`.
    fn name(&self) -> String;

    /// Solves from zero multipliers.
    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError>;
}
