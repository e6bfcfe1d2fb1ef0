//! The run's history columns as the measures read them: by name, with an error that names the
//! missing column and lists those the run wrote.

use crate::curve::CurveError;
use impact_solver::analysis::Execution;

/// The history table of one run, read column by column.
pub(super) struct Histories<'a> {
    run: &'a Execution,
}

impl<'a> Histories<'a> {
    /// The histories of `run`.
    pub(super) fn of(run: &'a Execution) -> Self {
        Histories { run }
    }

    /// The column `name`: an error when the run kept no history, or no column of that name (the
    /// error lists the columns it has, so that a misspelt name in the case file shows).
    pub(super) fn column(&self, name: &str) -> Result<Vec<f64>, CurveError> {
        let h = self.run.history.as_ref().ok_or(CurveError::NoHistory)?;
        h.column(name).ok_or_else(|| CurveError::NoColumn {
            name: name.into(),
            columns: h.columns().to_vec(),
        })
    }

    /// The `time` column (s).
    pub(super) fn time(&self) -> Result<Vec<f64>, CurveError> {
        self.column("time")
    }
}
