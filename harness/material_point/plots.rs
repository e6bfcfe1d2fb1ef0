//! Building the plots of a material case: series in report units (stress in MPa, strain in
//! 1e-3), thinned to a readable number of points, with target windows, reference lines and
//! dashed reference curves.

use super::{MaterialPlot, TargetBox};
use crate::results::{PlotData, ReferenceLine, Series};

/// Most points a stored curve keeps: enough for a smooth line at 560 px, few enough to keep the
/// page and `results.json` small.
pub const MAX_POINTS: usize = 300;

/// Axis label of strains plotted in units of 1e-3.
pub const STRAIN_AXIS: &str = "strain [1e-3]";

/// `x` to six significant figures: plenty for a plot, and a third of the characters in
/// `results.json`.
pub fn round6(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(5 - x.abs().log10().floor() as i32);
    if !scale.is_finite() || scale == 0.0 {
        return x;
    }
    (x * scale).round() / scale
}

/// Indices `0..len` thinned to at most about `max`, keeping the first, the last and `keep`.
pub fn thin_indices(len: usize, max: usize, keep: &[usize]) -> Vec<usize> {
    if len <= max {
        return (0..len).collect();
    }
    let stride = len.div_ceil(max).max(1);
    let mut idx: Vec<usize> = (0..len).step_by(stride).collect();
    idx.push(len - 1);
    idx.extend(keep.iter().copied().filter(|&k| k < len));
    idx.sort_unstable();
    idx.dedup();
    idx
}

/// A series from `(x, y)` pairs, thinned to [`MAX_POINTS`] keeping the point of largest `|y|`.
pub fn series(name: impl Into<String>, points: &[(f64, f64)]) -> Series {
    let peak = (0..points.len())
        .max_by(|&a, &b| points[a].1.abs().total_cmp(&points[b].1.abs()))
        .unwrap_or(0);
    series_keeping(name, points, &[peak])
}

/// A series from `(x, y)` pairs, thinned to [`MAX_POINTS`] keeping the indices `keep` (the
/// corners of a strain cycle).
pub fn series_keeping(name: impl Into<String>, points: &[(f64, f64)], keep: &[usize]) -> Series {
    let idx = thin_indices(points.len(), MAX_POINTS, keep);
    Series {
        name: name.into(),
        x: idx.iter().map(|&i| round6(points[i].0)).collect(),
        y: idx.iter().map(|&i| round6(points[i].1)).collect(),
    }
}

/// A function sampled at `n + 1` points of `[a, b]` (linear), or of `[a, b]` in log spacing.
pub fn sampled(
    name: impl Into<String>,
    a: f64,
    b: f64,
    n: usize,
    log: bool,
    f: impl Fn(f64) -> f64,
) -> Series {
    let x: Vec<f64> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            if log {
                10f64.powf(a.log10() + t * (b.log10() - a.log10()))
            } else {
                a + t * (b - a)
            }
        })
        .collect();
    Series {
        name: name.into(),
        y: x.iter().map(|&v| round6(f(v))).collect(),
        x: x.into_iter().map(round6).collect(),
    }
}

impl MaterialPlot {
    /// An empty plot with its title and axis labels (with units), linear axes.
    pub fn new(title: impl Into<String>, x_label: &str, y_label: &str) -> Self {
        MaterialPlot {
            plot: PlotData {
                title: title.into(),
                x_label: x_label.into(),
                y_label: y_label.into(),
                series: Vec::new(),
                reference_lines: Vec::new(),
                log_log: false,
            },
            log_x: false,
            log_y: false,
            boxes: Vec::new(),
            dashed: Vec::new(),
        }
    }

    /// Adds a curve of results.
    pub fn curve(mut self, s: Series) -> Self {
        self.plot.series.push(s);
        self
    }

    /// Adds a reference curve, drawn dashed.
    pub fn reference_curve(mut self, s: Series) -> Self {
        self.dashed.push(s.name.clone());
        self.plot.series.push(s);
        self
    }

    /// Adds a horizontal reference line with an optional band; infinite band edges (one-sided
    /// targets) are left out.
    pub fn line(mut self, label: impl Into<String>, y: f64, band: Option<[f64; 2]>) -> Self {
        self.plot.reference_lines.push(ReferenceLine {
            label: label.into(),
            y,
            band: band.filter(|b| b.iter().all(|v| v.is_finite())),
        });
        self
    }

    /// Adds a target window when both bands are finite.
    pub fn target(mut self, label: impl Into<String>, x: [f64; 2], y: [f64; 2]) -> Self {
        if x.iter().chain(&y).all(|v| v.is_finite()) {
            self.boxes.push(TargetBox {
                label: label.into(),
                x: x.to_vec(),
                y: y.to_vec(),
            });
        }
        self
    }

    /// The plot with a logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// The plot with a logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_ends_and_the_peak() {
        let idx = thin_indices(1000, 100, &[537]);
        assert!(idx.len() <= 103);
        assert_eq!(idx[0], 0);
        assert_eq!(*idx.last().unwrap(), 999);
        assert!(idx.contains(&537));
        assert_eq!(thin_indices(5, 100, &[]), vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn rounding_keeps_six_figures() {
        assert_eq!(round6(1.234567891), 1.23457);
        assert_eq!(round6(-2.5e-7), -2.5e-7);
        assert_eq!(round6(0.0), 0.0);
        assert!(round6(f64::NAN).is_nan());
    }
}
