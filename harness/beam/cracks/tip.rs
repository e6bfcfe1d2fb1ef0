//! The bending-crack tips of a beam over the snapshots of a run, and their speeds against the
//! Rayleigh speed `c_R`, told apart from what is not a tip moving.
//!
//! The tips follow the crack *opening* `w` of each element (the crack band's inelastic strain
//! times its width, `Model::crack_openings`), which an element only has once it softens; the
//! strain indicator `eps_1 / eps_r` also flags elements strained elastically ahead of a crack.
//!
//! - **Path** ([`path`]): the bending crack is the face-connected set of beam elements with
//!   `w >= w_th`, grown by flood fill from the bottom cell layer within one cell of mid-span,
//!   outside the loading region. A tip is the highest centroid of that set.
//! - **Two tips**: the *cohesive* tip at `w_th = w_p`, the opening at which the material's
//!   `sigma(w)` has fallen to 0.9 `f_t` ([`cohesive_opening`]): the process zone's front, which
//!   strain gauges on a ligament see (Zhang et al. 2010). The *traction-free* tip at
//!   `w_th = TIP_OPENING_FRACTION w_cr` = 0.1 mm, where the calibrated law keeps about 11 % of
//!   `f_t`: the visible crack.
//! - **What is not propagation** ([`track`]): an element past `w_p` before the connected
//!   cohesive crack reached an element sharing a node with it is pre-damaged (the wave's
//!   splitting, another crack; a tetrahedral front advances across edges and corners as well as
//!   faces): the advance into it is *coalescence*, taken out of the propagation height
//!   and reported as a length. The traction-free crack appears inside the process zone present
//!   then: its speed counts only once it has passed the height the cohesive tip had at that
//!   moment, the *initiation length* (a front sweeping an existing process zone is not bounded
//!   by `c_R`; Hillerborg, Modéer & Petersson 1976 for the process zone of an unnotched beam).
//! - **Speed with its resolution** ([`speed`]): least squares over windows spanning at least 3
//!   cells of advance, each with its resolution `h / T`; a reading passes when `v + h/T < c_R`
//!   in every window, fails when `v - h/T > c_R` in one, and is inconclusive otherwise. A
//!   crack tip in mode I cannot outrun `c_R` (Freund 1990); the thesis finds about 0.55 `c_R`.

mod measure;
mod path;
mod speed;
mod track;

#[cfg(test)]
mod tests;

pub use measure::{CrackTipMeasure, CrackTipQuantity, SpeedVerdict};
pub use path::CrackPath;
pub use speed::{
    reading_status, speed_windows, whole_window, window_status, SpeedWindow, TipStatus,
    WINDOW_CELLS,
};
pub use track::{track, TipTrack};

use impact_solver::material::microplane::experiments::crack_opening_curve;
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::MaterialModel;
use impact_solver::problem::Problem;
use serde::{Deserialize, Serialize};

use super::{beam_body_index, BeamFrame, BeamSpec, CrackError};

/// The opening of the traction-free tip, as a fraction of the critical opening `w_cr` of the
/// crack indicator: with `w_cr` = 0.2 mm, 0.1 mm, where the calibrated concrete's law keeps
/// about 11 % of `f_t` (the same level as the damage zones' `eps_1 / eps_r` = 0.5,
/// `crate::beam::cracks::DAMAGE_LEVEL`).
pub const TIP_OPENING_FRACTION: f64 = 0.5;

/// The stress, as a fraction of `f_t`, at which the cohesive tip's opening `w_p` is read on the
/// material's `sigma(w)`: past the peak, early on the softening branch.
pub const COHESIVE_STRESS_FRACTION: f64 = 0.9;

/// The first opening at which a softening law `(w, sigma)` (ascending `w`, starting at the
/// peak `f_t = sigma[0]`) falls to `fraction f_t`, linear between its points; `None` if it
/// never does.
pub fn opening_at_stress_fraction(w: &[f64], sigma: &[f64], fraction: f64) -> Option<f64> {
    let level = fraction * sigma.first()?;
    (1..w.len()).find_map(|i| {
        (sigma[i - 1] > level && sigma[i] <= level).then(|| {
            w[i - 1] + (sigma[i - 1] - level) / (sigma[i - 1] - sigma[i]) * (w[i] - w[i - 1])
        })
    })
}

/// The cohesive tip's opening `w_p` (m) of a microplane concrete at element size `cell` (m):
/// the opening at which the crack-opening law of its quasi-static uniaxial tension test
/// (`experiments::crack_opening_curve`, `w = h (eps - sigma / E)` after the peak, the same
/// quantity as `Model::crack_openings` under uniaxial tension) has fallen to
/// [`COHESIVE_STRESS_FRACTION`] `f_t`. The quasi-static law, not the rate-raised one: the
/// threshold marks a place on the softening branch, which the rate effect scales but does not
/// move much.
pub fn cohesive_opening(model: &MaterialModel, cell: f64) -> Result<f64, CrackError> {
    let MaterialModel::Microplane(parameters) = model else {
        return Err(CrackError::NotMicroplane);
    };
    let concrete = MicroplaneConcrete::new(*parameters)?;
    let (w, sigma) = crack_opening_curve(&concrete, cell);
    opening_at_stress_fraction(&w, &sigma, COHESIVE_STRESS_FRACTION).ok_or(
        CrackError::NoCohesiveOpening {
            cell,
            fraction: COHESIVE_STRESS_FRACTION,
        },
    )
}

/// A tip's speed reading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TipReading {
    /// The verdict against `c_R`.
    pub status: TipStatus,
    /// The window of the largest speed, if any.
    pub fastest: Option<SpeedWindow>,
    /// The window that decides the verdict: the failing or inconclusive one with the largest
    /// `v - h/T`, or for a pass the one with the largest `v + h/T`.
    pub decisive: Option<SpeedWindow>,
    /// Number of speed windows.
    pub windows: usize,
}

impl TipReading {
    /// The reading of a tip's propagation heights (see `speed_windows`, `reading_status`).
    pub fn of(times: &[f64], heights: &[f64], cell: f64, c_r: f64) -> Self {
        let windows = speed_windows(times, heights, cell);
        let status = reading_status(&windows, c_r);
        let by = |key: fn(&SpeedWindow) -> f64, filter: &dyn Fn(&SpeedWindow) -> bool| {
            windows
                .iter()
                .filter(|w| filter(w))
                .max_by(|a, b| key(a).total_cmp(&key(b)))
                .copied()
        };
        let decisive = match status {
            TipStatus::Pass => by(|w| w.speed + w.resolution, &|_| true),
            TipStatus::NoTip => None,
            s => by(|w| w.speed - w.resolution, &|w| window_status(w, c_r) == s),
        };
        Self {
            status,
            fastest: by(|w| w.speed, &|_| true),
            decisive,
            windows: windows.len(),
        }
    }

    /// The reading of a damage front's depths: as [`Self::of`], and where the front never
    /// advances [`WINDOW_CELLS`] cells, one window over its whole record (`whole_window`), so
    /// that a front that hardly moves reads a speed near zero with the resolution of the run.
    pub fn of_front(times: &[f64], depths: &[f64], cell: f64, c_p: f64) -> Self {
        let reading = Self::of(times, depths, cell, c_p);
        if reading.windows > 0 {
            return reading;
        }
        match whole_window(times, depths, cell) {
            Some(w) => Self {
                status: window_status(&w, c_p),
                fastest: Some(w),
                decisive: Some(w),
                windows: 1,
            },
            None => reading,
        }
    }

    /// One line: the verdict and its deciding window over `c_R`, with the resolution.
    pub fn describe(&self, c_r: f64) -> String {
        self.describe_against(c_r, "c_R")
    }

    /// One line: the verdict and its deciding window over the bounding speed `bound` named
    /// `name`, with the resolution.
    pub fn describe_against(&self, bound: f64, name: &str) -> String {
        match &self.decisive {
            None => format!(
                "{}: no window of {WINDOW_CELLS} cells of propagation",
                self.status.name()
            ),
            Some(w) => format!(
                "{}: {:.2} ± {:.2} {name} over {:.4}-{:.4} ms ({:.3} m; {} windows)",
                self.status.name(),
                w.speed / bound,
                w.resolution / bound,
                w.start * 1e3,
                w.end * 1e3,
                w.advance,
                self.windows
            ),
        }
    }
}

impl Default for TipReading {
    /// No window: nothing to judge (a record written before a reading existed reads back so).
    fn default() -> Self {
        Self {
            status: TipStatus::NoTip,
            fastest: None,
            decisive: None,
            windows: 0,
        }
    }
}

/// When the traction-free crack appears, and the process zone it appears in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Initiation {
    /// First snapshot with a traction-free crack (s).
    pub time: f64,
    /// The initiation length: the cohesive tip's height at that snapshot (m). The
    /// traction-free tip's speed counts from where it passes this height.
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub length: f64,
    /// The traction-free crack's own height at that snapshot (m).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub traction_free_height: f64,
}

/// Everything the crack-tip measure reads from a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrackTipReport {
    /// Cell size `h` (m).
    pub cell: f64,
    /// Rayleigh speed of the beam's concrete `c_R` (m/s).
    pub rayleigh_speed: f64,
    /// Opening of the cohesive tip `w_p` (m).
    pub cohesive_opening: f64,
    /// Opening of the traction-free tip (m).
    pub traction_free_opening: f64,
    /// Snapshot times (s).
    pub times: Vec<f64>,
    /// Cohesive tip height per snapshot (m), NaN before it exists.
    // NaN is written as null (JSON has none) and read back as NaN.
    #[serde(deserialize_with = "crate::results::lenient::vec")]
    pub cohesive: Vec<f64>,
    /// Traction-free tip height per snapshot (m), NaN before it exists.
    // NaN is written as null (JSON has none) and read back as NaN.
    #[serde(deserialize_with = "crate::results::lenient::vec")]
    pub traction_free: Vec<f64>,
    /// The traction-free crack's appearance, `None` without one.
    pub initiation: Option<Initiation>,
    /// Total advance of the cohesive tip through pre-damaged elements (m).
    pub coalescence_length: f64,
    /// Number of pre-damaged elements in the cohesive crack.
    pub coalesced_elements: usize,
    /// The cohesive tip's speed, from its appearance on, coalescence taken out.
    pub cohesive_speed: TipReading,
    /// The traction-free tip's speed, from where it passes the initiation length, coalescence
    /// taken out.
    pub traction_free_speed: TipReading,
    /// Dilatational wave speed of the beam's concrete `c_p` (m/s), the bound of the damage
    /// front (NaN in a record written before the front was measured).
    #[serde(default = "nan", deserialize_with = "crate::results::lenient::f64")]
    pub dilatational_speed: f64,
    /// Depth of the pre-damage front below the top face per snapshot (m), NaN before it exists
    /// (`track::damage_front`).
    #[serde(default, deserialize_with = "crate::results::lenient::vec")]
    pub damage_front: Vec<f64>,
    /// The pre-damage front's speed down the column, judged against `c_p`.
    #[serde(default)]
    pub damage_front_speed: TipReading,
    /// Depth below the top face of the shallowest pre-damaged element of the column (m), NaN
    /// without pre-damage or in a record written before it was measured.
    #[serde(default = "nan", deserialize_with = "crate::results::lenient::f64")]
    pub damage_shallowest: f64,
}

fn nan() -> f64 {
    f64::NAN
}

impl CrackTipReport {
    /// The report of a track (see the module documentation).
    pub fn of(track: &TipTrack, speeds: WaveSpeeds, cell: f64, w_p: f64, w_tf: f64) -> Self {
        let c_r = speeds.rayleigh;
        let times = &track.times;
        let nan = |h: &[Option<f64>]| h.iter().map(|h| h.unwrap_or(f64::NAN)).collect();
        // Propagation heights: the tip's height less the coalescence it went through, from `from`.
        let propagation = |tip: &[Option<f64>], coalescence: &[f64], from: Option<usize>| {
            let Some(from) = from else {
                return (Vec::new(), Vec::new());
            };
            let h: Vec<f64> = (from..times.len())
                .map(|k| tip[k].unwrap_or(0.0) - coalescence[k])
                .collect();
            (times[from..].to_vec(), h)
        };
        let appears = track.cohesive.iter().position(Option::is_some);
        let (t, h) = propagation(&track.cohesive, &track.cohesive_coalescence, appears);
        let cohesive_speed = TipReading::of(&t, &h, cell, c_r);
        let initiation = track
            .traction_free
            .iter()
            .position(Option::is_some)
            .map(|k| Initiation {
                time: times[k],
                length: track.cohesive[k].unwrap_or(f64::NAN),
                traction_free_height: track.traction_free[k].unwrap_or(f64::NAN),
            });
        // Heights are centroids: a tip that reaches the element that was the cohesive tip has
        // passed the initiation length.
        let passed = initiation.and_then(|i| {
            track
                .traction_free
                .iter()
                .position(|h| h.is_some_and(|h| h >= i.length * (1.0 - 1e-12)))
        });
        let (t, h) = propagation(
            &track.traction_free,
            &track.traction_free_coalescence,
            passed,
        );
        let traction_free_speed = TipReading::of(&t, &h, cell, c_r);
        // The front enters the column at its shallowest first element one snapshot before it
        // shows: a column opened at once over many cells advances that far in one interval.
        let front_from = track.damage_front.iter().position(Option::is_some);
        let damage_front_speed = match (front_from, track.damage_entry) {
            (Some(k), Some(entry)) => {
                let from = k.saturating_sub(1);
                let d: Vec<f64> = (from..times.len())
                    .map(|i| track.damage_front[i].unwrap_or(entry))
                    .collect();
                TipReading::of_front(&times[from..], &d, cell, speeds.dilatational)
            }
            _ => TipReading::default(),
        };
        Self {
            cell,
            rayleigh_speed: c_r,
            cohesive_opening: w_p,
            traction_free_opening: w_tf,
            times: times.clone(),
            cohesive: nan(&track.cohesive),
            traction_free: nan(&track.traction_free),
            initiation,
            coalescence_length: track.cohesive_coalescence.last().copied().unwrap_or(0.0),
            coalesced_elements: track.coalesced.iter().filter(|c| **c).count(),
            cohesive_speed,
            traction_free_speed,
            dilatational_speed: speeds.dilatational,
            damage_front: nan(&track.damage_front),
            damage_front_speed,
            damage_shallowest: track.damage_shallowest.unwrap_or(f64::NAN),
        }
    }
}

/// The wave speeds the fronts of a beam are judged against (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveSpeeds {
    /// Rayleigh speed `c_R`: the bound of a crack tip.
    pub rayleigh: f64,
    /// Dilatational speed `c_p`: the bound of a damage front the compressive wave drives.
    pub dilatational: f64,
}

/// The crack-tip report of `spec`'s beam over the snapshots of a run: the path from the mesh,
/// `w_p` from the beam's material at the cell size, `w_tf = TIP_OPENING_FRACTION w_cr`, `c_R`
/// of the beam's elastic constants.
pub fn crack_tip_report(
    problem: &Problem,
    snapshots: &[impact_solver::dynamics::Snapshot],
    spec: &BeamSpec,
) -> Result<CrackTipReport, CrackError> {
    if snapshots.is_empty() {
        return Err(CrackError::NoSnapshots);
    }
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    let b = beam_body_index(problem, spec)?;
    let range = problem.model.bodies[b].elements.clone();
    let material = &problem.model.bodies[b].material;
    let model = material
        .model()
        .ok_or_else(|| CrackError::NoMaterialModel {
            body: spec.body.clone(),
        })?;
    let w_p = cohesive_opening(&model, frame.cell)?;
    let w_tf = TIP_OPENING_FRACTION * problem.model.crack_indicator.crack_width;
    let constants = material.constants();
    let speeds = WaveSpeeds {
        rayleigh: impact_references::analytic::rayleigh_wave_speed(&constants),
        dilatational: impact_references::analytic::dilatational_wave_speed(&constants),
    };
    let path = CrackPath::of(&frame, &elements);
    let times: Vec<f64> = snapshots.iter().map(|s| s.time).collect();
    let openings = snapshots.iter().map(|s| {
        s.crack_opening
            .get(range.clone())
            .map(|w| w.iter().map(|&w| f64::from(w)).collect())
            .ok_or_else(|| CrackError::NoCrackOpenings {
                body: spec.body.clone(),
            })
    });
    let track = track(&path, &times, openings, w_p, w_tf)?;
    Ok(CrackTipReport::of(&track, speeds, frame.cell, w_p, w_tf))
}
