//! The measures of history signals: extremes, the final value, peaks and their times, windows,
//! level crossings and drifts of one column (or of a few read together).

use impact_solver::Vector3;

use super::columns::Histories;
use super::Measure;
use crate::curve::CurveError;

/// Why a measure of history signals has no value: each message names the column it read.
#[derive(Debug, thiserror::Error)]
pub enum SignalError {
    /// The run kept no history, or the history lacks the column (the message lists those it
    /// has).
    #[error(transparent)]
    Column(#[from] CurveError),
    /// The column has no record: no last value, no peak.
    #[error("`{column}` has no record")]
    Empty {
        /// The column.
        column: String,
    },
    /// No record in a plateau's time window.
    #[error("no record of `{column}` between t = {from} and {to}: widen the window")]
    NoRecordInWindow {
        /// The column.
        column: String,
        /// Start of the window (s).
        from: f64,
        /// End of the window (s).
        to: f64,
    },
    /// The drifting vector is zero at the start: its drift has no scale.
    #[error("{columns:?} is zero at the start: no relative drift")]
    VectorZero {
        /// The columns of its components.
        columns: [String; 3],
    },
    /// The column crosses its mean upwards fewer than twice: no period.
    #[error("`{column}` crosses its mean upwards fewer than twice: no frequency")]
    FewCrossings {
        /// The column.
        column: String,
    },
    /// The column is zero at its peak and around it.
    #[error("`{column}` is zero around its largest value: no peak")]
    ColumnZero {
        /// The column.
        column: String,
    },
    /// The signal never reaches the arrival level.
    #[error("`{column}` never reaches {level}")]
    NeverReaches {
        /// The column.
        column: String,
        /// The level, in the column's unit.
        level: f64,
    },
}

fn empty(column: &str) -> SignalError {
    SignalError::Empty {
        column: column.to_string(),
    }
}

/// Evaluates `measure` when it reads history signals only; `None` for a measure of another
/// family.
pub(super) fn evaluate(measure: &Measure, h: &Histories) -> Result<Option<f64>, SignalError> {
    Ok(Some(match measure {
        Measure::HistoryMax { column: c } => {
            h.column(c)?.into_iter().fold(f64::NEG_INFINITY, f64::max)
        }
        Measure::HistoryPeakMagnitude { column: c } => h
            .column(c)?
            .into_iter()
            .fold(0.0, |a: f64, x| a.max(x.abs())),
        Measure::HistoryMin { column: c } => h.column(c)?.into_iter().fold(f64::INFINITY, f64::min),
        Measure::HistoryFinal { column: c, scale } => {
            h.column(c)?.last().ok_or_else(|| empty(c))? * scale
        }
        Measure::PeakTime { column: c } => {
            let (t, y) = (h.time()?, h.column(c)?);
            let i = (0..y.len())
                .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                .ok_or_else(|| empty(c))?;
            t[i]
        }
        Measure::ValueAtPeak {
            column: c,
            of,
            scale,
        } => value_at_peak(&h.column(c)?, &h.column(of)?).ok_or_else(|| empty(of))? * scale,
        Measure::PeakOverNeighbours { column: c } => peak_over_neighbours(c, &h.column(c)?)?,
        Measure::DurationAbove {
            column: c,
            threshold,
        } => {
            let (t, y) = (h.time()?, h.column(c)?);
            (1..y.len())
                .filter(|&i| y[i] > *threshold)
                .map(|i| t[i] - t[i - 1])
                .sum()
        }
        Measure::PlateauMean {
            column: c,
            from,
            to,
        } => plateau_mean(h, c, *from, *to)?,
        Measure::ArrivalTime { column: c, level } => {
            crossing(&h.time()?, c, &h.column(c)?, *level)?
        }
        Measure::FrontSpeed {
            from,
            to,
            distance,
            level,
        } => {
            let t = h.time()?;
            distance
                / (crossing(&t, to, &h.column(to)?, *level)?
                    - crossing(&t, from, &h.column(from)?, *level)?)
        }
        Measure::MaxChange { column: c, scale } => {
            let y = h.column(c)?;
            y.iter().map(|x| (x - y[0]).abs()).fold(0.0, f64::max) / scale
        }
        Measure::RelativeDrift { columns } => relative_drift(h, columns)?,
        Measure::ZeroCrossingFrequency { column: c } => zero_crossing_frequency(h, c)?,
        _ => return Ok(None),
    }))
}

/// The mean of `column` over the records with `from <= t <= to` (the plateau behind a front);
/// an error when no record falls in the window.
fn plateau_mean(h: &Histories, column: &str, from: f64, to: f64) -> Result<f64, SignalError> {
    let (t, y) = (h.time()?, h.column(column)?);
    let window: Vec<f64> = (0..y.len())
        .filter(|&i| t[i] >= from && t[i] <= to)
        .map(|i| y[i])
        .collect();
    if window.is_empty() {
        return Err(SignalError::NoRecordInWindow {
            column: column.to_string(),
            from,
            to,
        });
    }
    Ok(window.iter().sum::<f64>() / window.len() as f64)
}

/// `max_i |v_i - v_0| / |v_0|` of the vector whose three components are `columns` (a quantity
/// that must be conserved, such as a momentum).
fn relative_drift(h: &Histories, columns: &[String; 3]) -> Result<f64, SignalError> {
    let c = [
        h.column(&columns[0])?,
        h.column(&columns[1])?,
        h.column(&columns[2])?,
    ];
    let at = |i: usize| Vector3::new(c[0][i], c[1][i], c[2][i]);
    let initial = at(0).norm();
    if initial == 0.0 {
        return Err(SignalError::VectorZero {
            columns: columns.clone(),
        });
    }
    Ok((0..c[0].len())
        .map(|i| (at(i) - at(0)).norm())
        .fold(0.0, f64::max)
        / initial)
}

/// The frequency of an oscillation: upward crossings of its mean, linearly interpolated, counted
/// between the first and the last (at least two needed).
fn zero_crossing_frequency(h: &Histories, column: &str) -> Result<f64, SignalError> {
    let (t, y) = (h.time()?, h.column(column)?);
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let ups: Vec<f64> = (1..y.len())
        .filter(|&i| y[i - 1] < mean && y[i] >= mean)
        .map(|i| t[i - 1] + (mean - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]))
        .collect();
    if ups.len() < 2 {
        return Err(SignalError::FewCrossings {
            column: column.to_string(),
        });
    }
    Ok((ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0]))
}

/// `|y_p| / mean(|y_i|, |i - p| <= 2)` at the row `p` of the largest `|y|` (the first of equal
/// ones): how far the peak stands above the rows around it
/// ([`Measure::PeakOverNeighbours`]); `column` names `y` in an error.
fn peak_over_neighbours(column: &str, y: &[f64]) -> Result<f64, SignalError> {
    let p = (0..y.len())
        .reduce(|a, b| if y[b].abs() > y[a].abs() { b } else { a })
        .ok_or_else(|| empty(column))?;
    let around = &y[p.saturating_sub(2)..(p + 3).min(y.len())];
    let mean = around.iter().map(|v| v.abs()).sum::<f64>() / around.len() as f64;
    if mean == 0.0 {
        return Err(SignalError::ColumnZero {
            column: column.to_string(),
        });
    }
    Ok(y[p].abs() / mean)
}

/// First time `signal` (the column `column`) reaches `level` (upward or downward, whichever way
/// it starts from).
fn crossing(time: &[f64], column: &str, signal: &[f64], level: f64) -> Result<f64, SignalError> {
    let start = signal.first().copied().unwrap_or(0.0);
    let up = level >= start;
    for i in 1..signal.len() {
        let reached = if up {
            signal[i] >= level
        } else {
            signal[i] <= level
        };
        if reached {
            let s = (level - signal[i - 1]) / (signal[i] - signal[i - 1]);
            return Ok(time[i - 1] + s * (time[i] - time[i - 1]));
        }
    }
    Err(SignalError::NeverReaches {
        column: column.to_string(),
        level,
    })
}

/// `y` in the row of the largest `|peak|` (the first of equal ones; [`Measure::ValueAtPeak`]);
/// `None` without a row.
fn value_at_peak(y: &[f64], peak: &[f64]) -> Option<f64> {
    let p =
        (0..peak.len().min(y.len()))
            .reduce(|a, b| if peak[b].abs() > peak[a].abs() { b } else { a })?;
    Some(y[p])
}

#[cfg(test)]
mod tests {
    use super::super::synthetic::{bar, history, rest, run, value};
    use super::super::{Measure, MeasureError};
    use super::{peak_over_neighbours, value_at_peak, SignalError};
    use crate::curve::CurveError;
    use impact_solver::analysis::Execution;

    /// A signal of five records one second apart, its peak of magnitude 6 at t = 2 s, with an
    /// opening `w`, two ramps `a` and `b` that pass 1.5 one second apart, a momentum vector
    /// `p` and a square wave `sq` of period 2 s.
    fn signals() -> Execution {
        run(
            &bar(),
            rest,
            Some(history(&[
                ("time", &[0.0, 1.0, 2.0, 3.0, 4.0]),
                ("y", &[0.0, 2.0, -6.0, 4.0, 1.0]),
                ("w", &[10.0, 11.0, 12.0, 13.0, 14.0]),
                ("a", &[0.0, 0.0, 1.0, 2.0, 3.0]),
                ("b", &[0.0, 0.0, 0.0, 1.0, 2.0]),
                ("px", &[3.0, 3.0, 0.0, 3.0, 3.0]),
                ("py", &[4.0, 4.0, 4.0, 4.0, 4.0]),
                ("pz", &[0.0, 1.0, 0.0, 0.0, 0.0]),
                ("zero", &[0.0; 5]),
            ])),
        )
    }

    fn error(measure: Measure, run: &Execution) -> SignalError {
        match measure.evaluate(&bar(), run) {
            Err(MeasureError::Signal(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    fn col(name: &str) -> String {
        name.to_string()
    }

    #[test]
    fn extremes_final_value_and_peak_time_of_a_known_signal() {
        let r = signals();
        assert_eq!(value(Measure::HistoryMax { column: col("y") }, &r), 4.0);
        assert_eq!(value(Measure::HistoryMin { column: col("y") }, &r), -6.0);
        let magnitude = Measure::HistoryPeakMagnitude { column: col("y") };
        assert_eq!(value(magnitude, &r), 6.0);
        let last = Measure::HistoryFinal {
            column: col("y"),
            scale: -0.5,
        };
        assert_eq!(value(last, &r), -0.5);
        assert_eq!(value(Measure::PeakTime { column: col("y") }, &r), 2.0);
        // The opening in the peak's row (12), doubled.
        let at_peak = Measure::ValueAtPeak {
            column: col("w"),
            of: col("y"),
            scale: 2.0,
        };
        assert_eq!(value(at_peak, &r), 24.0);
        // |y| around the peak: (0 + 2 + 6 + 4 + 1) / 5 = 13/5, so 6 / (13/5) = 30/13.
        let over = value(Measure::PeakOverNeighbours { column: col("y") }, &r);
        assert!((over - 30.0 / 13.0).abs() < 1e-15, "{over}");
    }

    #[test]
    fn windows_and_changes_of_a_known_signal() {
        let r = signals();
        // y > 1 in the records at t = 1 and 3: one second each.
        let above = Measure::DurationAbove {
            column: col("y"),
            threshold: 1.0,
        };
        assert_eq!(value(above, &r), 2.0);
        // The records at t = 1 and 2 lie in [0.5, 2.5]: (2 - 6) / 2.
        let plateau = Measure::PlateauMean {
            column: col("y"),
            from: 0.5,
            to: 2.5,
        };
        assert_eq!(value(plateau, &r), -2.0);
        // Largest |y - y_0| is 6, over the scale 2.
        let change = Measure::MaxChange {
            column: col("y"),
            scale: 2.0,
        };
        assert_eq!(value(change, &r), 3.0);
        // p_0 = (3, 4, 0), |p_0| = 5; the largest change is (-3, 0, 0): 3/5.
        let drift = Measure::RelativeDrift {
            columns: [col("px"), col("py"), col("pz")],
        };
        assert!((value(drift, &r) - 0.6).abs() < 1e-15);
    }

    #[test]
    fn arrival_times_front_speed_and_frequency_of_hand_made_signals() {
        let r = signals();
        // `a` goes from 1 at t = 2 to 2 at t = 3: 1.5 at t = 2.5; `b` one second later.
        let arrival = Measure::ArrivalTime {
            column: col("a"),
            level: 1.5,
        };
        assert_eq!(value(arrival, &r), 2.5);
        // 2 m between the probes in one second.
        let speed = Measure::FrontSpeed {
            from: col("a"),
            to: col("b"),
            distance: 2.0,
            level: 1.5,
        };
        assert_eq!(value(speed, &r), 2.0);
        // A square wave of period 2 s crosses its mean upwards three times, 2 s apart.
        let square = run(
            &bar(),
            rest,
            Some(history(&[
                ("time", &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
                ("sq", &[-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0]),
            ])),
        );
        let f = value(
            Measure::ZeroCrossingFrequency { column: col("sq") },
            &square,
        );
        assert!((f - 0.5).abs() < 1e-15, "{f}");
    }

    #[test]
    fn each_error_names_the_column_it_read() {
        let r = signals();
        let missing = error(Measure::HistoryMax { column: col("z") }, &r);
        assert!(
            matches!(&missing, SignalError::Column(CurveError::NoColumn { name, columns })
                if name == "z" && columns.contains(&col("y"))),
            "{missing}"
        );
        let no_history = run(&bar(), rest, None);
        let e = error(Measure::HistoryMax { column: col("y") }, &no_history);
        assert!(
            matches!(e, SignalError::Column(CurveError::NoHistory)),
            "{e}"
        );
        let empty = run(&bar(), rest, Some(history(&[("time", &[]), ("y", &[])])));
        let last = Measure::HistoryFinal {
            column: col("y"),
            scale: 1.0,
        };
        let e = error(last, &empty);
        assert!(
            matches!(&e, SignalError::Empty { column } if column == "y"),
            "{e}"
        );
        let e = error(Measure::PeakTime { column: col("y") }, &empty);
        assert!(
            matches!(&e, SignalError::Empty { column } if column == "y"),
            "{e}"
        );
        let late = Measure::PlateauMean {
            column: col("y"),
            from: 10.0,
            to: 20.0,
        };
        let e = error(late, &r);
        assert!(
            matches!(&e, SignalError::NoRecordInWindow { column, from, .. }
                if column == "y" && *from == 10.0),
            "{e}"
        );
        let zero = Measure::RelativeDrift {
            columns: [col("zero"), col("zero"), col("zero")],
        };
        let e = error(zero, &r);
        assert!(matches!(e, SignalError::VectorZero { .. }), "{e}");
        let e = error(Measure::ZeroCrossingFrequency { column: col("a") }, &r);
        assert!(
            matches!(&e, SignalError::FewCrossings { column } if column == "a"),
            "{e}"
        );
        let e = error(
            Measure::PeakOverNeighbours {
                column: col("zero"),
            },
            &r,
        );
        assert!(
            matches!(&e, SignalError::ColumnZero { column } if column == "zero"),
            "{e}"
        );
        let never = Measure::FrontSpeed {
            from: col("a"),
            to: col("b"),
            distance: 1.0,
            level: 2.5,
        };
        let e = error(never, &r);
        assert!(
            matches!(&e, SignalError::NeverReaches { column, level } if column == "b" && *level == 2.5),
            "{e}"
        );
        assert!(e.to_string().contains("`b`"), "{e}");
    }

    #[test]
    fn the_value_at_a_peak_is_read_in_the_peaks_row() {
        // A load that peaks (in magnitude, negative) at the third row: the opening there.
        let load = [0.0, -2.0, -5.0, -3.0, 5.0];
        let opening = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(value_at_peak(&opening, &load), Some(2.0));
        assert_eq!(value_at_peak(&[], &[]), None);
    }

    #[test]
    fn a_resolved_peak_stands_little_above_its_neighbours_and_a_spike_stands_far() {
        // A half sine over 40 rows: its five rows around the peak are within 1 - cos(2 pi / 40)
        // of it, so the ratio is below 1.01.
        let pulse: Vec<f64> = (0..=40)
            .map(|i| -(std::f64::consts::PI * f64::from(i) / 40.0).sin())
            .collect();
        let ratio = peak_over_neighbours("pulse", &pulse).unwrap();
        assert!((1.0..1.01).contains(&ratio), "{ratio}");
        // One row at three times a plateau: 3 / ((3 + 4) / 5).
        let mut spike = vec![1.0; 11];
        spike[5] = 3.0;
        let ratio = peak_over_neighbours("spike", &spike).unwrap();
        assert!((ratio - 15.0 / 7.0).abs() < 1e-12, "{ratio}");
        // At the end of the history the window is cut: 2 / ((1 + 1 + 2) / 3).
        let ratio = peak_over_neighbours("end", &[0.0, 1.0, 1.0, 2.0]).unwrap();
        assert!((ratio - 1.5).abs() < 1e-12, "{ratio}");
        assert!(peak_over_neighbours("zero", &[0.0; 4]).is_err());
    }
}
