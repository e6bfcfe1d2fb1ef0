//! Replaying the contact problems a run recorded through another contact solver: agreement of
//! the multipliers and the natural-map residual on identical problems (issue 5,
//! `contact/solver-agreement`).

use impact_solver::contact::problem::{natural_map_error, ContactProblem};
use impact_solver::contact::solver::SolveLimits;
use impact_solver::contact::RecordedProblem;
use serde::{Deserialize, Serialize};

use crate::contact_compare::error::CompareError;
use crate::contact_compare::run::solver_entries;

/// Why recorded contact problems cannot be replayed.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The run recorded no problem.
    #[error(
        "the run recorded no contact problem: set `record_problems_every` on the scene's contact \
         pair, and make sure the bodies touch"
    )]
    NothingRecorded,
    /// The replaying solver is unknown.
    #[error(transparent)]
    Solver(#[from] CompareError),
    /// The replaying solver refuses a recorded problem.
    #[error(transparent)]
    Solve(#[from] impact_solver::contact::solver::ContactSolverError),
}

/// What a replay measures, worst over the recorded problems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReplayQuantity {
    /// `max |r_replay - r_run| / max |r_run|`, over the problems the run's solver converged on.
    MultiplierDifference,
    /// The natural-map error `||F(r)|| / ||q||` of the replayed multipliers.
    NaturalMapError,
    /// The deepest penetration left by the replayed multipliers, `max(0, -u_N) / max |q_N|`
    /// (Signorini's first condition on the corrected gaps).
    Penetration,
    /// The largest normal opening of a contact that carries a normal force, `u_N / max |q_N|`
    /// where `r_N > 0`: zero under Coulomb's law, about `mu |u_T|` on sliding contacts under the
    /// associated law of the relaxed conic mode.
    NormalOpening,
    /// The fraction of the recorded problems on which the run's solver met its stopping test
    /// (the solver argument is ignored).
    ConvergedFraction,
}

/// `solver`: a name known to `contact-compare` (`gauss-seidel/exact`, `conic/coulomb`, ...), or
/// `recorded` for the multipliers the run's own solver returned.
///
/// `only_converged`: look only at the problems the run's solver converged on (always so for
/// `multiplier_difference`).
pub fn evaluate(
    problems: &[RecordedProblem],
    solver: &str,
    quantity: ReplayQuantity,
    tolerance: f64,
    only_converged: bool,
) -> Result<f64, ReplayError> {
    if problems.is_empty() {
        return Err(ReplayError::NothingRecorded);
    }
    if quantity == ReplayQuantity::ConvergedFraction {
        let converged = problems.iter().filter(|p| p.converged).count();
        return Ok(converged as f64 / problems.len() as f64);
    }
    let limits = SolveLimits {
        tolerance,
        ..Default::default()
    };
    let entry = if solver == "recorded" {
        None
    } else {
        let entry = solver_entries(&[solver.to_string()])?
            .pop()
            .expect("one entry");
        Some(entry)
    };
    let mut worst = 0.0f64;
    for recorded in problems {
        if (only_converged || quantity == ReplayQuantity::MultiplierDifference)
            && !recorded.converged
        {
            continue;
        }
        let r = match &entry {
            None => recorded.r.clone(),
            Some(entry) => {
                let limits = SolveLimits {
                    max_iterations: entry.max_iterations,
                    ..limits
                };
                (entry.make)().solve(&recorded.problem, &limits)?.r
            }
        };
        let value = match quantity {
            ReplayQuantity::MultiplierDifference => {
                let scale = max_abs(&recorded.r);
                let difference = recorded
                    .r
                    .iter()
                    .zip(&r)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                if scale > 0.0 {
                    difference / scale
                } else {
                    difference
                }
            }
            ReplayQuantity::NaturalMapError => natural_map_error(&recorded.problem, &r).relative,
            ReplayQuantity::Penetration => normal_extreme(&recorded.problem, &r, |_, un| -un),
            ReplayQuantity::NormalOpening => {
                normal_extreme(
                    &recorded.problem,
                    &r,
                    |rn, un| if rn > 0.0 { un } else { 0.0 },
                )
            }
            ReplayQuantity::ConvergedFraction => unreachable!("answered above"),
        };
        worst = worst.max(value);
    }
    Ok(worst)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// `max(0, max_a f(r_N, u_N)) / max_a |q_N|`.
fn normal_extreme(problem: &ContactProblem, r: &[f64], f: impl Fn(f64, f64) -> f64) -> f64 {
    let u = problem.velocity(r);
    let scale = (0..problem.contacts()).fold(0.0f64, |m, a| m.max(problem.q[3 * a].abs()));
    let worst = (0..problem.contacts()).fold(0.0f64, |m, a| m.max(f(r[3 * a], u[3 * a])));
    if scale > 0.0 {
        worst / scale
    } else {
        worst
    }
}
