//! The contact solvers by name: one spelling per solver, `family/variant`, used alike by scene
//! files (a pair's `solver`), the harness's `contact-compare` and replays, and the names written
//! into reports and recorded problems.

use std::fmt;

use super::conic::{ConicMode, ConicSolver};
use super::newton::AlartCurnierNewton;
use super::nsgs::{LocalSolver, NonsmoothGaussSeidel};
use super::solver::{ContactSolver, SolveLimits};

/// A contact solver known by name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum SolverKind {
    /// Nonlinear Gauss-Seidel with the thesis local step (Box 6.1, (6.71)-(6.77)); matrix-free in
    /// the time stepper. The stepper's default.
    #[default]
    GaussSeidelThesis,
    /// Nonlinear Gauss-Seidel with the exact local step for general 3x3 blocks.
    GaussSeidelExact,
    /// One SOCP with associated friction (Clarabel).
    ConicRelaxed,
    /// The Tresca fixed point of conic programs, converging to Coulomb's law (Clarabel).
    ConicCoulomb,
    /// Semismooth Newton on the Alart-Curnier function with a Goldstein-Price line search
    /// (`faer` LU), falling back to `GaussSeidelExact` when it stalls (the notes say so).
    NewtonAlartCurnier,
}

impl SolverKind {
    /// Every solver, in the order tables list them.
    pub const ALL: [SolverKind; 5] = [
        SolverKind::GaussSeidelThesis,
        SolverKind::GaussSeidelExact,
        SolverKind::ConicRelaxed,
        SolverKind::ConicCoulomb,
        SolverKind::NewtonAlartCurnier,
    ];

    /// The one spelling of this solver.
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::GaussSeidelThesis => "gauss-seidel/thesis",
            SolverKind::GaussSeidelExact => "gauss-seidel/exact",
            SolverKind::ConicRelaxed => "conic/relaxed",
            SolverKind::ConicCoulomb => "conic/coulomb",
            SolverKind::NewtonAlartCurnier => super::newton::NAME,
        }
    }

    /// The solver spelled `name`; anything else is an error naming the known spellings.
    pub fn from_name(name: &str) -> Result<Self, UnknownSolver> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| UnknownSolver(name.to_string()))
    }

    /// A fresh solver. `Send`, so that a run holding one can move to another thread.
    pub fn build(self) -> Box<dyn ContactSolver + Send> {
        match self {
            SolverKind::GaussSeidelThesis => {
                Box::new(NonsmoothGaussSeidel::new(LocalSolver::Thesis))
            }
            SolverKind::GaussSeidelExact => Box::new(NonsmoothGaussSeidel::new(LocalSolver::Exact)),
            SolverKind::ConicRelaxed => Box::new(ConicSolver::new(ConicMode::Relaxed)),
            SolverKind::ConicCoulomb => Box::new(ConicSolver::new(ConicMode::Coulomb)),
            SolverKind::NewtonAlartCurnier => Box::new(AlartCurnierNewton::default()),
        }
    }

    /// The iteration cap a contact pair gets when its scene gives none: sweeps for Gauss-Seidel
    /// (one step's problem is small and warm; 500 is the thesis-era default), interior-point
    /// iterations per conic solve for Clarabel (it needs 10-40), Newton iterations for
    /// `newton/alart-curnier` (a solve from zero needs a few to a few tens).
    pub fn default_max_iterations(self) -> usize {
        match self {
            SolverKind::GaussSeidelThesis | SolverKind::GaussSeidelExact => 500,
            SolverKind::ConicRelaxed | SolverKind::ConicCoulomb => 200,
            SolverKind::NewtonAlartCurnier => 100,
        }
    }
}

impl fmt::Display for SolverKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The spellings of all solvers, in [`SolverKind::ALL`] order.
pub fn names() -> Vec<&'static str> {
    SolverKind::ALL.iter().map(|k| k.name()).collect()
}

/// A solver name nobody knows.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown contact solver `{0}`: use one of {known}", known = names().join(", "))]
pub struct UnknownSolver(pub String);

/// Which solver a contact pair uses in the time stepper, and its stopping rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverChoice {
    /// The solver, by its one name.
    pub kind: SolverKind,
    /// `tolerance` is what the solver's own stopping test bounds (see each solver's `solve`);
    /// the stepper never sets a time limit, so that runs are reproducible.
    pub limits: SolveLimits,
}

impl SolverChoice {
    /// `kind` with the stepper's default tolerance `1e-10` and `kind`'s default iteration cap.
    pub fn new(kind: SolverKind) -> Self {
        Self {
            kind,
            limits: SolveLimits {
                tolerance: 1e-10,
                max_iterations: kind.default_max_iterations(),
                time_limit: None,
            },
        }
    }
}

impl Default for SolverChoice {
    fn default() -> Self {
        Self::new(SolverKind::GaussSeidelThesis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back_as_its_solver_and_builds_one_of_that_name() {
        for kind in SolverKind::ALL {
            assert_eq!(SolverKind::from_name(kind.name()), Ok(kind));
            assert_eq!(kind.build().name(), kind.name());
        }
    }

    #[test]
    fn an_unknown_or_old_spelling_is_an_error_naming_the_known_ones() {
        for old in ["gauss_seidel", "gauss-seidel", "conic"] {
            let e = SolverKind::from_name(old).unwrap_err().to_string();
            assert!(e.contains(&format!("`{old}`")), "{e}");
            for name in names() {
                assert!(e.contains(name), "{e}");
            }
        }
    }
}
