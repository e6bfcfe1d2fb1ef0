//! Measured and computed load-opening curves: reading named columns of a data file, and the
//! initial stiffness of a curve by one least-squares rule that serves both the tests and the
//! model, so that the two slopes compared are measured the same way.

use std::path::Path;

/// Why a history column, a data file's columns or a curve's slope cannot be read: each message
/// names the column or file and what it holds.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CurveError {
    /// The measure reads a history, and the run kept none (a static run).
    #[error("this measure needs an explicit run's history")]
    NoHistory,
    /// The history lacks a column: the message lists those it has.
    #[error("the history has no column `{name}`; it has {columns:?}")]
    NoColumn {
        /// The column asked for.
        name: String,
        /// The history's columns.
        columns: Vec<String>,
    },
    /// A data file cannot be read.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// A data file has no header line.
    #[error("{path}: no header line")]
    NoHeader {
        /// The file.
        path: String,
    },
    /// A data file lacks a column.
    #[error("{path}: no column `{name}` in {header:?}")]
    NoFileColumn {
        /// The file.
        path: String,
        /// The column asked for.
        name: String,
        /// The file's header.
        header: Vec<String>,
    },
    /// A data row that is not a number in every column asked for.
    #[error("{path}: bad data row {row}")]
    BadRow {
        /// The file.
        path: String,
        /// The data row (1-based, comments and blank lines not counted).
        row: usize,
    },
    /// Loads and openings of different lengths, or none.
    #[error("{loads} loads against {openings} openings")]
    Lengths {
        /// Number of loads.
        loads: usize,
        /// Number of openings.
        openings: usize,
    },
    /// Fewer than two records in the fitting window.
    #[error(
        "{records} records of the rising branch have a load in [{from}, {to}]: too few to fit"
    )]
    TooFewInWindow {
        /// Records in the window.
        records: usize,
        /// Lower load of the window.
        from: f64,
        /// Upper load of the window.
        to: f64,
    },
    /// The opening is constant over the fitted records.
    #[error("the opening does not change over the fitted records")]
    OpeningConstant,
}

/// The named columns of a CSV file (a header line of column names, `#` comment lines and blank
/// lines skipped), each as a vector in the file's units. An error names the file and the
/// missing column or the bad data row.
pub fn read_columns(file: &Path, names: &[&str]) -> Result<Vec<Vec<f64>>, CurveError> {
    let path = || file.display().to_string();
    let text = std::fs::read_to_string(file).map_err(|e| CurveError::Read {
        path: path(),
        message: e.to_string(),
    })?;
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'));
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| CurveError::NoHeader { path: path() })?
        .split(',')
        .map(str::trim)
        .collect();
    let index: Vec<usize> = names
        .iter()
        .map(|name| {
            header
                .iter()
                .position(|h| h == name)
                .ok_or_else(|| CurveError::NoFileColumn {
                    path: path(),
                    name: name.to_string(),
                    header: header.iter().map(|h| h.to_string()).collect(),
                })
        })
        .collect::<Result<_, _>>()?;
    let mut columns = vec![Vec::new(); names.len()];
    for (k, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        for (column, &i) in columns.iter_mut().zip(&index) {
            let value =
                fields
                    .get(i)
                    .and_then(|f| f.parse().ok())
                    .ok_or_else(|| CurveError::BadRow {
                        path: path(),
                        row: k + 1,
                    })?;
            column.push(value);
        }
    }
    Ok(columns)
}

/// Initial stiffness of a load-opening curve: the least-squares slope
/// `k = sum (w - w_m)(F - F_m) / sum (w - w_m)^2` over the records from the first up to the
/// first largest `F` (the peak) whose load lies in `[from, to]`. Only the rising branch counts:
/// a softening branch that falls back through the window is left out. The window keeps off the
/// first records (seating, the lead-in of a loading ramp) and off the nonlinear part before the
/// peak. Returns `k` and the number of records fitted; an error when fewer than two records fall
/// in the window or the opening does not change over them.
pub fn rising_branch_slope(
    load: &[f64],
    opening: &[f64],
    from: f64,
    to: f64,
) -> Result<(f64, usize), CurveError> {
    if load.is_empty() || load.len() != opening.len() {
        return Err(CurveError::Lengths {
            loads: load.len(),
            openings: opening.len(),
        });
    }
    let peak_at = load
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (i, &f)| {
            if f > best.1 {
                (i, f)
            } else {
                best
            }
        })
        .0;
    let (w, f): (Vec<f64>, Vec<f64>) = opening[..=peak_at]
        .iter()
        .zip(&load[..=peak_at])
        .filter(|(_, f)| (from..=to).contains(*f))
        .map(|(w, f)| (*w, *f))
        .unzip();
    let n = w.len();
    if n < 2 {
        return Err(CurveError::TooFewInWindow {
            records: n,
            from,
            to,
        });
    }
    let slope = least_squares_slope(&w, &f).ok_or(CurveError::OpeningConstant)?;
    Ok((slope, n))
}

/// Least-squares slope `sum (x - x_m)(y - y_m) / sum (x - x_m)^2` of `y` against `x` (same
/// length); `None` where `x` does not vary (or is empty).
pub fn least_squares_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let (xm, ym) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|x| (x - xm).powi(2)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(x, y)| (x - xm) * (y - ym)).sum();
    Some(sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::{read_columns, rising_branch_slope};

    /// A straight rising branch `F = 2 + 73 w` (w in um) to a peak at w = 10, then a softening
    /// branch that falls back through the window: the slope is 73 exactly, from the rising
    /// records in the window only, whatever the offset.
    #[test]
    fn the_slope_of_a_rising_branch_ignores_the_softening_branch() {
        let mut w: Vec<f64> = (0..=100).map(|i| 0.1 * i as f64).collect();
        let mut f: Vec<f64> = w.iter().map(|w| 2.0 + 73.0 * w).collect();
        for i in 1..=100 {
            w.push(10.0 + 0.5 * i as f64);
            f.push(732.0 - 20.0 * i as f64);
        }
        let (k, n) = rising_branch_slope(&f, &w, 150.0, 450.0).unwrap();
        assert!((k - 73.0).abs() < 1e-9, "{k}");
        // records with 150 <= 2 + 7.3 i <= 450: i = 21..=61
        assert_eq!(n, 41);
    }

    /// A curve bending over before its peak: the window picks the part it is given, so a
    /// window low on the branch gives the initial slope and a high one a smaller secant.
    #[test]
    fn the_window_selects_the_part_of_the_branch() {
        let w: Vec<f64> = (0..=200).map(|i| 0.05 * i as f64).collect();
        let f: Vec<f64> = w.iter().map(|w| 100.0 * w - 4.0 * w * w).collect();
        let (low, _) = rising_branch_slope(&f, &w, 0.0, 100.0).unwrap();
        let (high, _) = rising_branch_slope(&f, &w, 400.0, 600.0).unwrap();
        assert!(low > 95.0 && low < 100.0, "{low}");
        assert!(high < low - 20.0, "{high} {low}");
    }

    #[test]
    fn too_few_records_in_the_window_is_an_error() {
        let e = rising_branch_slope(&[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0], 5.0, 9.0).unwrap_err();
        assert!(e.to_string().contains("too few"), "{e}");
        let e = rising_branch_slope(&[1.0, 2.0], &[0.0], 0.0, 9.0).unwrap_err();
        assert!(e.to_string().contains("against"), "{e}");
    }

    /// Columns are read by name, in the order asked, with comments and blank lines skipped.
    #[test]
    fn columns_are_read_by_name() {
        let dir = std::env::temp_dir().join(format!("impact-curve-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("curve.csv");
        std::fs::write(
            &file,
            "# a test\ncmod, load_mean, load_min\n\n0.0, 1.0, 2.0\n",
        )
        .unwrap();
        let c = read_columns(&file, &["load_min", "cmod"]).unwrap();
        assert_eq!(c, vec![vec![2.0], vec![0.0]]);
        let e = read_columns(&file, &["load"]).unwrap_err();
        assert!(e.to_string().contains("no column `load`"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
