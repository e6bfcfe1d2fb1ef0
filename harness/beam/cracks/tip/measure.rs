//! The crack-tip quantities a case can measure, with the verdict a speed reading carries.

use serde::{Deserialize, Serialize};

use super::{CrackTipReport, TipReading, TipStatus};
use crate::beam::BeamSpec;

/// A speed reading's verdict: whether it passes, and one line saying why (the judge's
/// `Reading`, kept here so that the beam measures do not depend on the judge).
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedVerdict {
    /// Whether the reading passes.
    pub pass: bool,
    /// Its status and deciding window, as the report shows it.
    pub text: String,
}

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
    /// Largest windowed speed of the pre-damage front down the column under the load over the
    /// dilatational speed `c_p` (`track::damage_front`): a damage front the compressive wave
    /// drives cannot outrun it. Judged by its resolution (`v + h/T < c_p` in every window
    /// passes, an inconclusive reading does not); no pre-damage front passes, since nothing then
    /// runs ahead of the wave: its value is then 0. A front that never advances 3 cells is
    /// read over its whole record (`TipReading::of_front`).
    DamageFrontSpeedRatio,
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
    /// The quantity from a report, with the verdict of its speed reading for the speed ratios
    /// (a tip's fail, inconclusive reading or no tip does not pass, whatever the tolerance
    /// says; the damage front's fail or inconclusive reading does not). The value of a speed
    /// ratio is its fastest window's speed over its bound, NaN without a window.
    pub fn read(&self, report: &CrackTipReport) -> (f64, Option<SpeedVerdict>) {
        let ratio = |r: &TipReading, bound: f64| r.fastest.map_or(f64::NAN, |w| w.speed / bound);
        let tip = |r: &TipReading| {
            let c_r = report.rayleigh_speed;
            let verdict = SpeedVerdict {
                pass: r.status == TipStatus::Pass,
                text: r.describe(c_r),
            };
            (ratio(r, c_r), Some(verdict))
        };
        match self.quantity {
            CrackTipQuantity::CohesiveSpeedRatio => tip(&report.cohesive_speed),
            CrackTipQuantity::TractionFreeSpeedRatio => tip(&report.traction_free_speed),
            CrackTipQuantity::InitiationLength => {
                (report.initiation.map_or(f64::NAN, |i| i.length), None)
            }
            CrackTipQuantity::CoalescenceLength => (report.coalescence_length, None),
            CrackTipQuantity::DamageFrontSpeedRatio => {
                let (r, c_p) = (&report.damage_front_speed, report.dilatational_speed);
                if report.damage_front.iter().all(|d| d.is_nan()) {
                    let none = SpeedVerdict {
                        pass: true,
                        text: "no pre-damage front in the column under the load".into(),
                    };
                    return (0.0, Some(none));
                }
                let verdict = SpeedVerdict {
                    pass: r.status == TipStatus::Pass,
                    text: r.describe_against(c_p, "c_p"),
                };
                (ratio(r, c_p), Some(verdict))
            }
        }
    }
}
