//! The energy measures of an explicit run: the balance of its energy ledger, the drift of the
//! kinetic energy, and the energy left in the bodies at the end.

use super::columns::Histories;
use super::Measure;
use crate::curve::CurveError;
use impact_solver::analysis::Execution;

/// Why an energy measure has no value.
#[derive(Debug, thiserror::Error)]
pub enum EnergyError {
    /// The run kept no history, or the history lacks an energy column (the message lists those
    /// it has).
    #[error(transparent)]
    Column(#[from] CurveError),
    /// The energy balance is kept by an explicit run only.
    #[error("energy_balance_error reads the energy ledger of an explicit run; this run has none")]
    NeedsExplicitRun,
    /// An energy column without a record.
    #[error("`{column}` has no record")]
    Empty {
        /// The column.
        column: &'static str,
    },
    /// The kinetic energy is not positive at the start: its drift has no scale.
    #[error(
        "the initial kinetic energy is {initial} J: no relative drift (the case needs a body in \
         motion at the start)"
    )]
    KineticZero {
        /// The first record of `kinetic` (J).
        initial: f64,
    },
}

/// The column `name`, with at least one record.
fn column(h: &Histories, name: &'static str) -> Result<Vec<f64>, EnergyError> {
    let c = h.column(name)?;
    if c.is_empty() {
        return Err(EnergyError::Empty { column: name });
    }
    Ok(c)
}

/// Evaluates `measure` when it is an energy measure; `None` for a measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, EnergyError> {
    Ok(Some(match measure {
        Measure::EnergyBalanceError => {
            run.summary
                .as_ref()
                .ok_or(EnergyError::NeedsExplicitRun)?
                .max_relative_energy_error
        }
        Measure::KineticEnergyDrift => {
            let k = column(h, "kinetic")?;
            let k0 = k[0];
            if !(k0 > 0.0) {
                return Err(EnergyError::KineticZero { initial: k0 });
            }
            k.iter().map(|x| (x - k0).abs() / k0).fold(0.0, f64::max)
        }
        Measure::FinalEnergyRatio => {
            let (k, w) = (column(h, "kinetic")?, column(h, "stored_energy")?);
            (k[k.len() - 1] + w[w.len() - 1]) / k[0]
        }
        _ => return Ok(None),
    }))
}

#[cfg(test)]
mod tests {
    use super::super::synthetic::{bar, explicit, history, rest, run, value};
    use super::super::{Measure, MeasureError};
    use super::EnergyError;
    use crate::curve::CurveError;
    use impact_solver::analysis::Execution;

    /// An explicit run with the given kinetic and stored energy histories (J) and a largest
    /// relative balance error of 1.25 %.
    fn ledger(kinetic: &[f64], stored: &[f64]) -> Execution {
        let problem = bar();
        let h = history(&[("kinetic", kinetic), ("stored_energy", stored)]);
        explicit(run(&problem, rest, Some(h)), &problem, rest, 1.0, 0.0125)
    }

    fn error(measure: Measure, run: &Execution) -> EnergyError {
        match measure.evaluate(&bar(), run) {
            Err(MeasureError::Energy(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn balance_drift_and_final_ratio_of_known_energies() {
        let r = ledger(&[4.0, 5.0, 3.0, 1.0], &[0.0, 1.0, 2.0, 2.0]);
        // The ledger's own largest relative error, as the run reported it.
        assert_eq!(value(Measure::EnergyBalanceError, &r), 0.0125);
        // Largest |K - K_0| is 3 J (at 1 J), over K_0 = 4 J.
        assert_eq!(value(Measure::KineticEnergyDrift, &r), 0.75);
        // (1 + 2) J left of the 4 J at the start.
        assert_eq!(value(Measure::FinalEnergyRatio, &r), 0.75);
        let gained = ledger(&[4.0, 5.0], &[0.0, 1.0]);
        assert_eq!(value(Measure::KineticEnergyDrift, &gained), 0.25);
        assert_eq!(value(Measure::FinalEnergyRatio, &gained), 1.5);
    }

    #[test]
    fn each_error_says_what_the_run_lacks() {
        let problem = bar();
        let static_run = run(&problem, rest, None);
        let e = error(Measure::EnergyBalanceError, &static_run);
        assert!(matches!(e, EnergyError::NeedsExplicitRun), "{e}");
        let e = error(Measure::KineticEnergyDrift, &static_run);
        assert!(
            matches!(e, EnergyError::Column(CurveError::NoHistory)),
            "{e}"
        );
        let at_rest = ledger(&[0.0, 1.0], &[0.0, 0.0]);
        let e = error(Measure::KineticEnergyDrift, &at_rest);
        assert!(
            matches!(e, EnergyError::KineticZero { initial } if initial == 0.0),
            "{e}"
        );
        let empty = ledger(&[], &[]);
        let e = error(Measure::FinalEnergyRatio, &empty);
        assert!(matches!(e, EnergyError::Empty { column: "kinetic" }), "{e}");
        let h = history(&[("kinetic", &[1.0])]);
        let no_stored = run(&problem, rest, Some(h));
        let e = error(Measure::FinalEnergyRatio, &no_stored);
        assert!(
            matches!(&e, EnergyError::Column(CurveError::NoColumn { name, .. }) if name == "stored_energy"),
            "{e}"
        );
    }
}
