//! Axis ranges and tick positions of the plots. The plots are drawn on linear plotters axes in
//! "plot space" (log10 of the data for log axes) with ticks chosen here, because plotters' own log
//! axis labels nothing when the data span less than a decade, which is common for wall times.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};

use super::format;

/// Roughly how many ticks an axis gets; more would make the labels collide at 640 px.
const TARGET_TICKS: f64 = 6.0;

/// One axis of a plot: its scale and its range in plot space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub log: bool,
    pub lo: f64,
    pub hi: f64,
    /// Ticks only at whole numbers (run indices of the trend plots).
    pub integer: bool,
}

impl Axis {
    /// The axis spanning `points` (already in plot space) with a small margin; a range of a
    /// single value is widened so that a constant curve still gets a readable axis.
    pub fn spanning(points: impl IntoIterator<Item = f64>, log: bool) -> Option<Axis> {
        let (lo, hi) = points
            .into_iter()
            .filter(|p| p.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            });
        if lo > hi {
            return None;
        }
        let (lo, hi) = widen(lo, hi, log);
        let margin = 0.05 * (hi - lo);
        let axis = Axis {
            log,
            lo: lo - margin,
            hi: hi + margin,
            integer: false,
        };
        (axis.hi - axis.lo).is_finite().then_some(axis)
    }

    /// Where data value `v` lies in plot space, or `None` when it cannot be drawn on this axis.
    pub fn map(&self, v: f64) -> Option<f64> {
        to_plot(v, self.log)
    }

    /// The plot-space value clamped into the axis range (bands reaching past the axis).
    pub fn clamp(&self, p: f64) -> f64 {
        p.clamp(self.lo, self.hi)
    }

    /// Tick positions in plot space.
    pub fn ticks(&self) -> Vec<f64> {
        if self.log {
            log_ticks(self.lo, self.hi)
        } else if self.integer {
            nice_ticks(self.lo, self.hi, 1.0)
        } else {
            nice_ticks(self.lo, self.hi, 0.0)
        }
    }

    /// The label of a plot-space tick, in data units.
    pub fn label(&self, p: f64) -> String {
        format::tick(if self.log { 10f64.powf(p) } else { p })
    }
}

/// plotters draws on the axis directly: linear in plot space, bold grid lines and labels at
/// [`Axis::ticks`], no light grid lines (they would fall between our ticks).
impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let fraction = (v - self.lo) / (self.hi - self.lo);
        limit.0 + (fraction * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks()
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// Data value to plot space: log10 on log axes; `None` when not drawable.
pub fn to_plot(v: f64, log: bool) -> Option<f64> {
    if !v.is_finite() || (log && v <= 0.0) {
        None
    } else if log {
        Some(v.log10())
    } else {
        Some(v)
    }
}

/// Widens a degenerate range (all values equal) so that plotters gets a non-empty axis:
/// half a decade each way on log axes, 10 % of the value (or 1 around zero) on linear ones.
fn widen(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    let scale = lo.abs().max(hi.abs());
    if hi - lo > 1e-9 * scale && hi > lo {
        return (lo, hi);
    }
    let pad = if log {
        0.5
    } else if scale > 0.0 {
        0.1 * scale
    } else {
        1.0
    };
    (lo - pad, hi + pad)
}

/// Ticks at 1, 2 or 5 times a power of ten, about [`TARGET_TICKS`] of them, with a step of at
/// least `min_step` (1 for integer axes).
fn nice_ticks(lo: f64, hi: f64, min_step: f64) -> Vec<f64> {
    let step = nice_step((hi - lo) / TARGET_TICKS).max(min_step);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|k| k as f64 * step)
        // Multiples of a decimal step are not exact in binary: snap the ones next to zero.
        .map(|t| if t.abs() < 1e-9 * step { 0.0 } else { t })
        .collect()
}

/// The smallest of 1, 2, 5 times a power of ten that is at least `raw`.
fn nice_step(raw: f64) -> f64 {
    let magnitude = 10f64.powf(raw.log10().floor());
    let normalised = raw / magnitude;
    let factor = if normalised <= 1.0 {
        1.0
    } else if normalised <= 2.0 {
        2.0
    } else if normalised <= 5.0 {
        5.0
    } else {
        10.0
    };
    factor * magnitude
}

/// Ticks of a log axis whose plot-space range is `[lo, hi]` (decades): every decade, or every
/// k-th one when there are many; 1-2-5 within decades when the range is narrower; linear nice
/// ticks when even those leave fewer than two labels.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let first = lo.ceil() as i64;
    let last = hi.floor() as i64;
    let decades = (last - first + 1).max(0) as f64;
    if decades >= 3.0 {
        let every = (decades / TARGET_TICKS).ceil().max(1.0) as i64;
        return (first..=last)
            .filter(|d| d.rem_euclid(every) == 0)
            .map(|d| d as f64)
            .collect();
    }
    let one_two_five: Vec<f64> = (lo.floor() as i64..=hi.ceil() as i64)
        .flat_map(|d| [1.0, 2.0, 5.0].map(|m| (m * 10f64.powi(d as i32)).log10()))
        .filter(|p| (lo..=hi).contains(p))
        .collect();
    if one_two_five.len() >= 3 {
        return one_two_five;
    }
    nice_ticks(10f64.powf(lo), 10f64.powf(hi), 0.0)
        .into_iter()
        .filter(|&t| t > 0.0)
        .map(f64::log10)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The axis of data values, as the plots build it.
    fn covering<const N: usize>(values: [f64; N], log: bool) -> Option<Axis> {
        Axis::spanning(values.into_iter().filter_map(|v| to_plot(v, log)), log)
    }

    #[test]
    fn constant_values_get_a_range() {
        let axis = covering([3.0, 3.0], false).unwrap();
        assert!(axis.lo < 3.0 && axis.hi > 3.0);
        let axis = covering([0.0], false).unwrap();
        assert!(axis.lo < 0.0 && axis.hi > 0.0);
        let axis = covering([1e-3], true).unwrap();
        assert!(axis.lo < -3.0 && axis.hi > -3.0);
    }

    #[test]
    fn undrawable_values_give_no_axis() {
        assert_eq!(covering([f64::NAN, f64::INFINITY], false), None);
        assert_eq!(covering([-1.0, 0.0], true), None);
    }

    #[test]
    fn narrow_log_ranges_still_have_ticks() {
        let axis = covering([2.0, 3.0], true).unwrap();
        assert!(axis.ticks().len() >= 2, "{:?}", axis.ticks());
        let axis = covering([1e-8, 1e2], true).unwrap();
        assert!((2..=8).contains(&axis.ticks().len()));
    }
}
