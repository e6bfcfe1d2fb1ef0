//! Evaluating a per-run measure on a run's histories and final fields: each family of measures
//! has a module of its own, and this one hands a measure to its family.

use impact_solver::problem::Problem;

use super::columns::Histories;
use super::{energy, motion, signal, stress, structure};
use super::{Measure, MeasureError};
use crate::judge::{Measured, Reading};
use impact_solver::analysis::Execution;

impl Measure {
    /// Evaluates a per-run measure.
    pub fn evaluate(&self, problem: &Problem, run: &Execution) -> Result<f64, MeasureError> {
        self.evaluate_read(problem, run).map(|m| m.value)
    }

    /// Evaluates a per-run measure, with its own verdict where it gives one (the crack tips).
    pub fn evaluate_read(
        &self,
        problem: &Problem,
        run: &Execution,
    ) -> Result<Measured, MeasureError> {
        let h = Histories::of(run);
        let value = match self {
            Measure::CrackTip(m) => {
                let report = crate::beam::crack_tip_report(problem, run.snapshots(), &m.beam)?;
                let (value, verdict) = m.read(&report);
                let reading = verdict.map(|v| Reading {
                    pass: v.pass,
                    text: v.text,
                });
                return Ok(Measured { value, reading });
            }
            Measure::ContactReplay {
                solver,
                quantity,
                tolerance,
                only_converged,
            } => crate::replay::evaluate(
                &run.contact_problems,
                solver,
                *quantity,
                *tolerance,
                *only_converged,
            )?,
            Measure::CrackBand(m) => m.evaluate(&problem.model, &|c| h.column(c))?,
            Measure::CrackBandPoint(m) => m.evaluate(&problem.model)?,
            _ => self.evaluate_in_family(problem, run, &h)?,
        };
        Ok(Measured::from(value))
    }

    /// Evaluates a measure of the families of history signals, energies, the final motion, the
    /// final stresses and the structural response: each family answers `None` for a measure not
    /// its own, so that the first answer is the measure's. A sweep measure is of none: it needs
    /// the levels of a sweep, not one run.
    fn evaluate_in_family(
        &self,
        problem: &Problem,
        run: &Execution,
        h: &Histories,
    ) -> Result<f64, MeasureError> {
        let value = if let Some(v) = signal::evaluate(self, h)? {
            v
        } else if let Some(v) = energy::evaluate(self, run, h)? {
            v
        } else if let Some(v) = motion::evaluate(self, problem, run)? {
            v
        } else if let Some(v) = stress::evaluate(self, problem, run, h)? {
            v
        } else if let Some(v) = structure::evaluate(self, problem, run, h)? {
            v
        } else {
            return Err(MeasureError::SweepMeasure {
                measure: format!("{self:?}"),
            });
        };
        Ok(value)
    }
}
