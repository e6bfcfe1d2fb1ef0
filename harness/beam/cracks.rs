//! Cracked zones of a beam, the failure-mode classification (FORMULATION 5, thesis 10.3) and the
//! bending-crack tips against time (`tip`).
//!
//! An element is cracked when its crack indicator `eps_1 / eps_r` (largest principal
//! Green-Lagrange strain over `eps_r = w_cr / L`, thesis 5.1) is at least 1. The indicator is
//! history-free, so it is computed from any displacement (the final state or a snapshot).
//!
//! Geometry is read in the reference configuration, side view `x`-`y` (`x` along the beam, `y`
//! up): the beam's bounding box gives the bottom `y_b` and the height `h`; the load acts at
//! `x_load` (default: mid-span of the box) over `|x - x_load| <= a` (default `a = h / 4`, the
//! thesis hammer's half width); the supports are the body's constraints whose nodes all lie on the
//! bottom face; the cell size is `c = (6 V)^(1/3)` of the mean element volume `V` (six tetrahedra
//! per cube).

mod classify;
mod error;
#[cfg(test)]
mod fixtures;
mod frame;
mod tip;

pub use classify::{
    classify, contact_end, failure_mode_at, failure_mode_details, failure_mode_judged, zones,
};
pub use error::CrackError;
pub use frame::{BeamElement, BeamFrame};
pub use tip::{
    cohesive_opening, crack_tip_report, opening_at_stress_fraction, CrackTipMeasure,
    CrackTipQuantity, CrackTipReport, Initiation, SpeedVerdict, SpeedWindow, TipReading, TipStatus,
    TipTrack, WaveSpeeds, COHESIVE_STRESS_FRACTION, TIP_OPENING_FRACTION, WINDOW_CELLS,
};

use impact_solver::problem::Problem;
use impact_solver::Vector3;
use serde::{Deserialize, Serialize};

/// The beam a crack measure looks at (every field has a default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    /// The beam body.
    #[serde(default = "beam_body")]
    pub body: String,
    /// Position of the load along the beam (m); mid-span of the body's box by default.
    #[serde(default)]
    pub load_x: Option<f64>,
    /// Half width of the loaded strip (m); a quarter of the beam height by default.
    #[serde(default)]
    pub load_half_width: Option<f64>,
    /// Cracks (zone parts) of fewer elements are ignored.
    #[serde(default = "min_elements")]
    pub min_elements: usize,
    /// The state the failure mode is judged in: the end of the run (default) or the end of
    /// the contact (thesis 10.3.2.1). The tip measure reads every snapshot whatever it says.
    #[serde(default)]
    pub at: JudgedAt,
}

/// When a beam's crack pattern is judged.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum JudgedAt {
    /// The final state of the run.
    #[default]
    End,
    /// The first snapshot at or after the end of the contact: the first time after the peak of
    /// `|column|` at which it falls below `fraction` of that peak (thesis 10.3.2.1: "up to the
    /// moment when the beam-hammer contact force drops approximately to zero";
    /// [`crate::beam::history::contact_end_time`]).
    ContactEnd {
        /// History column of the contact force (default `impact_force_y`).
        #[serde(default = "contact_force_column")]
        column: String,
        /// Fraction of the peak below which the contact has ended (default 0.01).
        #[serde(default = "one_percent")]
        fraction: f64,
    },
}

fn contact_force_column() -> String {
    "impact_force_y".into()
}

fn one_percent() -> f64 {
    0.01
}

/// Lower level of the crack indicator `eps_1 / eps_r` for a damage zone: elements at or above
/// it and below 1 are damaged but not cracked. A bending crack with inclined damage zones on
/// its sides (25 to 65 degrees, as a shear crack) but no shear crack is the thesis' transition
/// mode at 4 m/s ("dominating bending crack enriched with two inclined lateral damage zones,
/// which can be interpreted as incoming cracks", 10.3.2.1 and chapter 11, Fig. 10.7). Half the
/// cracking strain: with `eps_r = 0.004` on 50 mm (`w_cr` 0.2 mm) an element there has an
/// opening of about 0.1 mm, past the kink `w_1 = G_F / f_t` = 0.037 mm of the calibrated
/// concrete's MC2010 law, where the law keeps about 11 % of `f_t`: an incoming crack, halfway
/// to the opening that makes it a crack.
pub const DAMAGE_LEVEL: f64 = 0.5;

fn beam_body() -> String {
    "beam".into()
}

fn min_elements() -> usize {
    12
}

impl Default for BeamSpec {
    fn default() -> Self {
        Self {
            body: beam_body(),
            load_x: None,
            load_half_width: None,
            min_elements: min_elements(),
            at: JudgedAt::End,
        }
    }
}

/// Failure mode of a beam (thesis 10.3.2), with its code as a metric value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureMode {
    /// No qualifying crack: code 0.
    None,
    /// Mode I: only the bending crack, at any height: code 1.
    Bending,
    /// A bending crack reaching half the height, and shear cracks: code 2.
    Mixed,
    /// Only shear cracks, or shear cracks beside a bending crack below half the height: code 3.
    Shear,
    /// The transition: a bending crack with inclined damage zones on its sides but no shear
    /// crack ([`DAMAGE_LEVEL`]): code 4.
    BendingInclined,
}

impl FailureMode {
    /// The metric value: 0 none, 1 bending, 2 mixed, 3 shear, 4 bending with inclined damage.
    pub fn code(self) -> f64 {
        match self {
            FailureMode::None => 0.0,
            FailureMode::Bending => 1.0,
            FailureMode::Mixed => 2.0,
            FailureMode::Shear => 3.0,
            FailureMode::BendingInclined => 4.0,
        }
    }

    /// The mode of a metric value (`None` for anything that is not a code).
    pub fn from_code(code: f64) -> Option<FailureMode> {
        [
            FailureMode::None,
            FailureMode::Bending,
            FailureMode::Mixed,
            FailureMode::Shear,
            FailureMode::BendingInclined,
        ]
        .into_iter()
        .find(|m| m.code() == code)
    }

    /// The mode's name in reports and case files (`none`, `bending`, `mixed`, `shear`,
    /// `bending_inclined`).
    pub fn name(self) -> &'static str {
        match self {
            FailureMode::None => "none",
            FailureMode::Bending => "bending",
            FailureMode::Mixed => "mixed",
            FailureMode::Shear => "shear",
            FailureMode::BendingInclined => "bending_inclined",
        }
    }
}

/// The failure modes a reference accepts: one mode (`failure_mode: bending`) or any of a list
/// (`failure_mode: [mixed, shear]`, for a bar that accepts either: at 6 and 8 m/s shear
/// dominates, thesis 10.3.2, with or without a bending crack reaching half the height).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ModeSet {
    /// Exactly this mode.
    One(FailureMode),
    /// Any of these modes (at least one).
    AnyOf(Vec<FailureMode>),
}

impl ModeSet {
    /// The accepted modes.
    pub fn modes(&self) -> &[FailureMode] {
        match self {
            ModeSet::One(m) => std::slice::from_ref(m),
            ModeSet::AnyOf(m) => m,
        }
    }

    /// The names joined by "or" (`mixed or shear`).
    pub fn name(&self) -> String {
        let names: Vec<String> = self
            .modes()
            .iter()
            .map(|m| format!("`{}`", m.name()))
            .collect();
        names.join(" or ")
    }

    /// Whether a measured failure-mode code is one of the accepted modes.
    pub fn accepts(&self, code: f64) -> bool {
        self.modes().iter().any(|m| m.code() == code)
    }

    /// The first accepted mode's code (NaN for an empty list, which then never passes).
    pub fn first_code(&self) -> f64 {
        self.modes().first().map_or(f64::NAN, |m| m.code())
    }
}

/// What a crack is taken for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrackKind {
    /// Rising from the bottom face within one beam height of the load, plane within 30 degrees
    /// of vertical (angle to the axis at least 60 degrees).
    Bending,
    /// Beside the loaded strip, plane inclined 25 to 65 degrees to the beam axis.
    Shear,
    /// Anything else (a vertical crack away from mid-span, a horizontal one, an inclined part
    /// under the load).
    Other,
    /// Not a crack: a damage zone ([`DAMAGE_LEVEL`]) beside the loaded strip, inclined 25 to 65
    /// degrees to the beam axis, that holds no shear crack.
    InclinedDamage,
}

/// Which side of the loaded strip a crack lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Left of the loaded strip (smaller `x`).
    Left,
    /// Under the loaded strip.
    Under,
    /// Right of the loaded strip (larger `x`).
    Right,
}

/// One crack: the part of a connected cracked zone on one side of (or under) the load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Crack {
    /// Index of the connected zone it belongs to.
    pub zone: usize,
    /// Which side of the loaded strip it lies on.
    pub side: Side,
    /// What it is taken for: bending, shear or other.
    pub kind: CrackKind,
    /// Number of cracked elements in it.
    pub elements: usize,
    /// Mean `x` of its element centroids (m).
    pub x_center: f64,
    /// Angle of its plane (major principal axis of the centroids in the side view) to the beam
    /// axis, 0 to 90 degrees.
    pub angle_deg: f64,
    /// Extent of the centroids along that axis plus one cell (m).
    pub length: f64,
    /// Lowest and highest centroid above the bottom face (m): `top` is the height it reached.
    pub bottom: f64,
    /// Highest centroid above the bottom face (m); see `bottom`.
    pub top: f64,
    /// Whether it starts in the bottom layer of cells.
    pub from_bottom: bool,
}

/// The crack indicator `eps_1 / eps_r` of every element of the beam at displacement `u`.
fn indicator_at(
    problem: &Problem,
    spec: &BeamSpec,
    u: &[Vector3<f64>],
) -> Result<Vec<f64>, CrackError> {
    let range = beam_elements(problem, spec)?;
    let indicator = problem.model.element_fields(u).crack_indicator;
    Ok(indicator[range].to_vec())
}

/// Time of the first snapshot in which an element of the beam outside the loading region (the
/// crushing under the impactor, [`BeamFrame::in_loading_region`]) is cracked (`eps_1 / eps_r`
/// at least 1), `None` when none is.
pub fn first_crack_time(
    problem: &Problem,
    spec: &BeamSpec,
    snapshots: &[impact_solver::dynamics::Snapshot],
) -> Result<Option<f64>, CrackError> {
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    for s in snapshots {
        let indicator = indicator_at(problem, spec, &s.u)?;
        if elements
            .iter()
            .zip(&indicator)
            .any(|(e, &i)| i >= 1.0 && !frame.in_loading_region(&e.centroid))
        {
            return Ok(Some(s.time));
        }
    }
    Ok(None)
}

/// The model's index of the beam body, or the error naming it.
pub(crate) fn beam_body_index(problem: &Problem, spec: &BeamSpec) -> Result<usize, CrackError> {
    problem
        .model
        .body_index(&spec.body)
        .ok_or_else(|| CrackError::NoBody {
            body: spec.body.clone(),
        })
}

/// The model's element range of the beam body.
fn beam_elements(problem: &Problem, spec: &BeamSpec) -> Result<std::ops::Range<usize>, CrackError> {
    Ok(problem.model.bodies[beam_body_index(problem, spec)?]
        .elements
        .clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        for m in [
            FailureMode::None,
            FailureMode::Bending,
            FailureMode::Mixed,
            FailureMode::Shear,
            FailureMode::BendingInclined,
        ] {
            assert_eq!(FailureMode::from_code(m.code()), Some(m));
        }
        assert_eq!(FailureMode::from_code(1.5), None);
    }
}

// Diagnostics that run beam cases (test builds only: the file is `#![cfg(test)]`).
mod case_run;
