//! Nonlinear Gauss-Seidel on FC(W, q, mu).

use super::problem::ContactProblem;
use super::solver::{ContactSolver, ContactSolverError, SolveLimits, SolverReport};

/// The one-contact step of each Gauss-Seidel update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LocalSolver {
    /// The thesis step (6.71)-(6.77): close the gap with the block's diagonal, clamp, return
    /// radially. Exact for blocks that are multiples of the identity (ours, lumped mass).
    Thesis,
    /// Exact for a general 3x3 block: separation, stick, or slip found by a scan of the slip
    /// direction.
    Exact,
}

/// Nonlinear (projected) Gauss-Seidel over the contacts in their order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NonsmoothGaussSeidel {
    pub local: LocalSolver,
}

impl NonsmoothGaussSeidel {
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
        _problem: &ContactProblem,
        _limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError> {
        todo!("being written")
    }
}
