//! The crack-tip quantities a case can measure, with the verdict a speed reading carries.

use serde::{Deserialize, Serialize};

use super::{CrackTipReport, TipReading};
use crate::beam::BeamSpec;

/// What a `crack_tip` metric reads from the beam's [`CrackTipReport`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrackTipQuantity {
    /// Largest windowed speed of the cohesive tip (`w >= w_p`) over `c_R`, from its appearance
    /// on, coalescence taken out; judged by its resolution as well (`v + h/T < c_R` in every
    /// window passes; "inconclusive" and "no tip" do not).
    CohesiveSpeedRatio,
    /// The same for the traction-free tip (`w >= w_cr / 2`), from where it passes the
    /// initiation length.
    TractionFreeSpeedRatio,
    /// The cohesive tip's height when the traction-free crack appears (m): the process zone
    /// the traction-free front first sweeps; NaN without a traction-free crack.
    InitiationLength,
    /// Advance of the cohesive tip through elements past `w_p` before the crack reached a
    /// neighbour of theirs (m): pre-damage joined by coalescence.
    CoalescenceLength,
}

/// A `crack_tip` measure: a quantity of a beam's crack tips.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackTipMeasure {
    /// The quantity read.
    pub quantity: CrackTipQuantity,
    /// The beam (default: body `beam`, load at mid-span).
    #[serde(default)]
    pub beam: BeamSpec,
}

impl CrackTipMeasure {
    /// The quantity from a report, with the speed reading it is judged by for the speed
    /// ratios (a fail, an inconclusive reading or no tip does not pass, whatever the tolerance
    /// says). The value of a speed ratio is its fastest window's speed over `c_R`, NaN without
    /// a window.
    pub fn read<'a>(&self, report: &'a CrackTipReport) -> (f64, Option<&'a TipReading>) {
        let c_r = report.rayleigh_speed;
        let speed = |r: &'a TipReading| (r.fastest.map_or(f64::NAN, |w| w.speed / c_r), Some(r));
        match self.quantity {
            CrackTipQuantity::CohesiveSpeedRatio => speed(&report.cohesive_speed),
            CrackTipQuantity::TractionFreeSpeedRatio => speed(&report.traction_free_speed),
            CrackTipQuantity::InitiationLength => {
                (report.initiation.map_or(f64::NAN, |i| i.length), None)
            }
            CrackTipQuantity::CoalescenceLength => (report.coalescence_length, None),
        }
    }
}
