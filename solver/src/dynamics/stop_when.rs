//! A run's own end before its end time: a history column reaching a level. The nail of the
//! thesis' section 10.4 is run "until the nail stops": its mean velocity along the shot
//! reaching zero ends the run, where a fixed end time would either cut the penetration short or
//! spend the rest of the run on the rebound.

use serde::{Deserialize, Serialize};

use crate::error::{Result, SolverError};

/// Ends an explicit run at the first history row where `column` has reached `level` from the
/// side of it the run's first row was on ([`crate::dynamics::ExplicitSettings::stop_when`]).
/// `end_time` stays the run's bound: a run that never reaches the level ends there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopWhen {
    /// A history column (`time`, an energy, `<probe>_x/y/z`, `<constraint>_reaction_x/y/z`).
    pub column: String,
    /// The level whose reaching ends the run, in the column's unit.
    pub level: f64,
}

/// Where the run stands with its [`StopWhen`], kept over every segment of a run that remeshes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StopProgress {
    /// Whether the first row was below the level (`None` before the first row).
    started_below: Option<bool>,
    /// The time of the row that reached the level.
    reached_at: Option<f64>,
}

impl StopWhen {
    /// The column's index among `columns`; an error naming the columns there are otherwise.
    pub fn column_index(&self, columns: &[String]) -> Result<usize> {
        columns
            .iter()
            .position(|c| *c == self.column)
            .ok_or_else(|| SolverError::InvalidScene {
                entity: "analysis.explicit.stop_when.column".into(),
                message: format!(
                    "`{}` is not a history column; the columns are: {}",
                    self.column,
                    columns.join(", ")
                ),
            })
    }
}

impl StopProgress {
    /// Takes a history row's watched value: whether it has reached the level from the first
    /// row's side (the first row sets the side), or the run has already ended on an earlier row.
    /// The run ends where [`Self::end`] is called.
    pub fn reached(&mut self, stop: &StopWhen, value: f64) -> bool {
        if self.reached_at.is_some() {
            return true;
        }
        let below = value < stop.level;
        match self.started_below {
            None => {
                self.started_below = Some(below);
                false
            }
            Some(started_below) => started_below != below || value == stop.level,
        }
    }

    /// Records that the run ended on the row at `time`.
    pub fn end(&mut self, time: f64) {
        self.reached_at.get_or_insert(time);
    }

    /// The time of the row that reached the level, if one has.
    pub fn reached_at(&self) -> Option<f64> {
        self.reached_at
    }

    /// The two facts it keeps (the first row's side, the time of the row that reached the
    /// level), for a checkpoint; [`Self::from_parts`] rebuilds it.
    pub fn parts(&self) -> (Option<bool>, Option<f64>) {
        (self.started_below, self.reached_at)
    }

    /// The progress of [`Self::parts`].
    pub fn from_parts(started_below: Option<bool>, reached_at: Option<f64>) -> Self {
        Self {
            started_below,
            reached_at,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nail_stops() -> StopWhen {
        StopWhen {
            column: "nail_velocity_y".into(),
            level: 0.0,
        }
    }

    #[test]
    fn a_velocity_rising_through_zero_ends_the_run_at_the_first_row_past_it() {
        let stop = nail_stops();
        let mut progress = StopProgress::default();
        let rows = [
            (0.0, -200.0),
            (1.0, -120.0),
            (2.0, -3.0),
            (3.0, 1.5),
            (4.0, -0.5),
        ];
        let ended: Vec<bool> = rows
            .iter()
            .map(|&(t, v)| {
                let reached = progress.reached(&stop, v);
                if reached {
                    progress.end(t);
                }
                reached
            })
            .collect();
        assert_eq!(ended, [false, false, false, true, true]);
        assert_eq!(progress.reached_at(), Some(3.0));
    }

    #[test]
    fn the_side_is_the_first_rows_so_a_falling_column_ends_the_run_too() {
        let stop = StopWhen {
            column: "gap".into(),
            level: 1.0,
        };
        let mut progress = StopProgress::default();
        assert!(!progress.reached(&stop, 3.0));
        assert!(!progress.reached(&stop, 1.2));
        assert!(progress.reached(&stop, 1.0));
    }

    #[test]
    fn a_run_that_never_reaches_the_level_is_not_ended() {
        let stop = nail_stops();
        let mut progress = StopProgress::default();
        assert!((0..100).all(|i| !progress.reached(&stop, -1.0 - i as f64)));
        assert_eq!(progress.reached_at(), None);
    }

    #[test]
    fn an_unknown_column_names_the_columns_there_are() {
        let columns = vec!["time".to_string(), "nail_velocity_x".to_string()];
        let message = nail_stops().column_index(&columns).unwrap_err().to_string();
        assert!(message.contains("nail_velocity_y") && message.contains("nail_velocity_x"));
    }
}
