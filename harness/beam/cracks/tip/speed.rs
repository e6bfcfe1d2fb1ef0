//! Tip speeds with their resolution, and the verdict of a reading against the Rayleigh speed.

use serde::{Deserialize, Serialize};

use crate::curve::least_squares_slope;

/// Cells of advance a speed window spans at least: over fewer, quantising the tip to cells
/// makes the slope's uncertainty `h / T` as large as the speeds it is to judge.
pub const WINDOW_CELLS: f64 = 3.0;

/// One least-squares speed over a window of the tip's advance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedWindow {
    /// First snapshot time of the window (s).
    pub start: f64,
    /// Last snapshot time of the window (s).
    pub end: f64,
    /// Advance over the window (m), at least [`WINDOW_CELLS`] cells.
    pub advance: f64,
    /// Least-squares slope of height against time over the window's snapshots (m/s).
    pub speed: f64,
    /// Resolution `h / T`: one cell `h` of position over the window's duration `T` (m/s). The
    /// tip is quantised to cells, so a slope is known to about one cell over the window.
    pub resolution: f64,
}

/// The verdict of a tip-speed reading against the Rayleigh speed `c_R`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TipStatus {
    /// Every window has `v + h/T < c_R`: below `c_R` by more than the resolution.
    Pass,
    /// Some window has `v - h/T > c_R`: above `c_R` by more than the resolution.
    Fail,
    /// No window fails, but some has `|v - c_R| <= h/T`: the measure cannot tell. Not a pass.
    Inconclusive,
    /// No window of genuine propagation (no crack, or one that never advances
    /// [`WINDOW_CELLS`] cells past its initiation): nothing to judge. Not a pass.
    NoTip,
}

impl TipStatus {
    /// The name in reports (`pass`, `fail`, `inconclusive`, `no tip`).
    pub fn name(self) -> &'static str {
        match self {
            TipStatus::Pass => "pass",
            TipStatus::Fail => "fail",
            TipStatus::Inconclusive => "inconclusive",
            TipStatus::NoTip => "no tip",
        }
    }
}

/// Speed windows of a tip's propagation heights `heights` at `times` (same length, heights
/// not decreasing): from each snapshot, the shortest run of snapshots over which the height
/// rises by at least [`WINDOW_CELLS`] cells of size `cell`, and the least-squares slope through
/// all of its snapshots. Windows that would reach past the last snapshot are not formed.
pub fn speed_windows(times: &[f64], heights: &[f64], cell: f64) -> Vec<SpeedWindow> {
    let need = WINDOW_CELLS * cell * (1.0 - 1e-9);
    let mut out = Vec::new();
    for i in 0..heights.len() {
        let Some(j) = (i + 1..heights.len()).find(|&j| heights[j] - heights[i] >= need) else {
            break;
        };
        let (t, h) = (&times[i..=j], &heights[i..=j]);
        out.push(SpeedWindow {
            start: times[i],
            end: times[j],
            advance: heights[j] - heights[i],
            // Snapshot times increase, so the fit exists.
            speed: least_squares_slope(t, h).unwrap_or(f64::NAN),
            resolution: cell / (times[j] - times[i]),
        });
    }
    out
}

/// One window over the whole of `times` and `heights` (at least two snapshots), whatever the
/// advance: the speed of a front that never advances [`WINDOW_CELLS`] cells, with the
/// resolution of the whole span. `None` with fewer than two snapshots.
pub fn whole_window(times: &[f64], heights: &[f64], cell: f64) -> Option<SpeedWindow> {
    let (first, last) = (*times.first()?, *times.last()?);
    (times.len() >= 2 && last > first).then(|| SpeedWindow {
        start: first,
        end: last,
        advance: heights[heights.len() - 1] - heights[0],
        speed: least_squares_slope(times, heights).unwrap_or(f64::NAN),
        resolution: cell / (last - first),
    })
}

/// The verdict of one window: pass when `v + h/T < c_R`, fail when `v - h/T > c_R`,
/// inconclusive in between.
pub fn window_status(w: &SpeedWindow, c_r: f64) -> TipStatus {
    if w.speed + w.resolution < c_r {
        TipStatus::Pass
    } else if w.speed - w.resolution > c_r {
        TipStatus::Fail
    } else {
        TipStatus::Inconclusive
    }
}

/// The verdict of a reading: fail if any window fails, else inconclusive if any is, else pass;
/// no tip without windows. The bar holds for every window of genuine propagation.
pub fn reading_status(windows: &[SpeedWindow], c_r: f64) -> TipStatus {
    let statuses: Vec<TipStatus> = windows.iter().map(|w| window_status(w, c_r)).collect();
    if statuses.is_empty() {
        TipStatus::NoTip
    } else if statuses.contains(&TipStatus::Fail) {
        TipStatus::Fail
    } else if statuses.contains(&TipStatus::Inconclusive) {
        TipStatus::Inconclusive
    } else {
        TipStatus::Pass
    }
}
