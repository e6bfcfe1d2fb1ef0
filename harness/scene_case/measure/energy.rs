//! The energy measures of an explicit run: the balance of its energy ledger, the drift of the
//! kinetic energy, and the energy left in the bodies at the end.

use super::columns::Histories;
use super::{Measure, MeasureError};
use impact_solver::analysis::Execution;

/// Evaluates `measure` when it is an energy measure; `None` for a measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, MeasureError> {
    Ok(Some(match measure {
        Measure::EnergyBalanceError => {
            run.summary
                .as_ref()
                .ok_or(MeasureError::NeedsExplicitRun)?
                .max_relative_energy_error
        }
        Measure::KineticEnergyDrift => {
            let k = h.column("kinetic")?;
            let k0 = k[0];
            if !(k0 > 0.0) {
                return Err(MeasureError::KineticZero);
            }
            k.iter().map(|x| (x - k0).abs() / k0).fold(0.0, f64::max)
        }
        Measure::FinalEnergyRatio => {
            let (k, w) = (h.column("kinetic")?, h.column("stored_energy")?);
            (k[k.len() - 1] + w[w.len() - 1]) / k[0]
        }
        _ => return Ok(None),
    }))
}
