//! The measures of history signals: extremes, the final value, peaks and their times, windows,
//! level crossings and drifts of one column (or of a few read together).

use impact_solver::Vector3;

use super::columns::Histories;
use super::{Measure, MeasureError};

/// Evaluates `measure` when it reads history signals only; `None` for a measure of another
/// family.
pub(super) fn evaluate(measure: &Measure, h: &Histories) -> Result<Option<f64>, MeasureError> {
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
            h.column(c)?.last().ok_or(MeasureError::Empty)? * scale
        }
        Measure::PeakTime { column: c } => {
            let (t, y) = (h.time()?, h.column(c)?);
            let i = (0..y.len())
                .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                .ok_or(MeasureError::Empty)?;
            t[i]
        }
        Measure::ValueAtPeak {
            column: c,
            of,
            scale,
        } => value_at_peak(&h.column(c)?, &h.column(of)?)? * scale,
        Measure::PeakOverNeighbours { column: c } => peak_over_neighbours(&h.column(c)?)?,
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
        Measure::ArrivalTime { column: c, level } => crossing(&h.time()?, &h.column(c)?, *level)?,
        Measure::FrontSpeed {
            from,
            to,
            distance,
            level,
        } => {
            let t = h.time()?;
            distance
                / (crossing(&t, &h.column(to)?, *level)? - crossing(&t, &h.column(from)?, *level)?)
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
fn plateau_mean(h: &Histories, column: &str, from: f64, to: f64) -> Result<f64, MeasureError> {
    let (t, y) = (h.time()?, h.column(column)?);
    let window: Vec<f64> = (0..y.len())
        .filter(|&i| t[i] >= from && t[i] <= to)
        .map(|i| y[i])
        .collect();
    if window.is_empty() {
        return Err(MeasureError::NoRecordInWindow {
            column: column.to_string(),
            from,
            to,
        });
    }
    Ok(window.iter().sum::<f64>() / window.len() as f64)
}

/// `max_i |v_i - v_0| / |v_0|` of the vector whose three components are `columns` (a quantity
/// that must be conserved, such as a momentum).
fn relative_drift(h: &Histories, columns: &[String; 3]) -> Result<f64, MeasureError> {
    let c = [
        h.column(&columns[0])?,
        h.column(&columns[1])?,
        h.column(&columns[2])?,
    ];
    let at = |i: usize| Vector3::new(c[0][i], c[1][i], c[2][i]);
    let initial = at(0).norm();
    if initial == 0.0 {
        return Err(MeasureError::VectorZero);
    }
    Ok((0..c[0].len())
        .map(|i| (at(i) - at(0)).norm())
        .fold(0.0, f64::max)
        / initial)
}

/// The frequency of an oscillation: upward crossings of its mean, linearly interpolated, counted
/// between the first and the last (at least two needed).
fn zero_crossing_frequency(h: &Histories, column: &str) -> Result<f64, MeasureError> {
    let (t, y) = (h.time()?, h.column(column)?);
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let ups: Vec<f64> = (1..y.len())
        .filter(|&i| y[i - 1] < mean && y[i] >= mean)
        .map(|i| t[i - 1] + (mean - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]))
        .collect();
    if ups.len() < 2 {
        return Err(MeasureError::FewCrossings {
            column: column.to_string(),
        });
    }
    Ok((ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0]))
}

/// `|y_p| / mean(|y_i|, |i - p| <= 2)` at the row `p` of the largest `|y|` (the first of equal
/// ones): how far the peak stands above the rows around it
/// ([`Measure::PeakOverNeighbours`]).
fn peak_over_neighbours(y: &[f64]) -> Result<f64, MeasureError> {
    let p = (0..y.len())
        .reduce(|a, b| if y[b].abs() > y[a].abs() { b } else { a })
        .ok_or(MeasureError::Empty)?;
    let around = &y[p.saturating_sub(2)..(p + 3).min(y.len())];
    let mean = around.iter().map(|v| v.abs()).sum::<f64>() / around.len() as f64;
    if mean == 0.0 {
        return Err(MeasureError::ColumnZero);
    }
    Ok(y[p].abs() / mean)
}

/// First time `signal` reaches `level` (upward or downward, whichever way it starts from).
fn crossing(time: &[f64], signal: &[f64], level: f64) -> Result<f64, MeasureError> {
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
    Err(MeasureError::NeverReaches { level })
}

/// `y` in the row of the largest `|peak|` (the first of equal ones; [`Measure::ValueAtPeak`]).
fn value_at_peak(y: &[f64], peak: &[f64]) -> Result<f64, MeasureError> {
    let p = (0..peak.len().min(y.len()))
        .reduce(|a, b| if peak[b].abs() > peak[a].abs() { b } else { a })
        .ok_or(MeasureError::Empty)?;
    Ok(y[p])
}
#[cfg(test)]
mod tests {
    use super::{peak_over_neighbours, value_at_peak};

    #[test]
    fn the_value_at_a_peak_is_read_in_the_peaks_row() {
        // A load that peaks (in magnitude, negative) at the third row: the opening there.
        let load = [0.0, -2.0, -5.0, -3.0, 5.0];
        let opening = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(value_at_peak(&opening, &load).unwrap(), 2.0);
        assert!(value_at_peak(&[], &[]).is_err());
    }

    #[test]
    fn a_resolved_peak_stands_little_above_its_neighbours_and_a_spike_stands_far() {
        // A half sine over 40 rows: its five rows around the peak are within 1 - cos(2 pi / 40)
        // of it, so the ratio is below 1.01.
        let pulse: Vec<f64> = (0..=40)
            .map(|i| -(std::f64::consts::PI * f64::from(i) / 40.0).sin())
            .collect();
        let ratio = peak_over_neighbours(&pulse).unwrap();
        assert!((1.0..1.01).contains(&ratio), "{ratio}");
        // One row at three times a plateau: 3 / ((3 + 4) / 5).
        let mut spike = vec![1.0; 11];
        spike[5] = 3.0;
        let ratio = peak_over_neighbours(&spike).unwrap();
        assert!((ratio - 15.0 / 7.0).abs() < 1e-12, "{ratio}");
        // At the end of the history the window is cut: 2 / ((1 + 1 + 2) / 3).
        let ratio = peak_over_neighbours(&[0.0, 1.0, 1.0, 2.0]).unwrap();
        assert!((ratio - 1.5).abs() < 1e-12, "{ratio}");
        assert!(peak_over_neighbours(&[0.0; 4]).is_err());
    }
}
