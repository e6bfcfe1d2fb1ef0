//! Measures of the thesis' plain concrete beam (chapter 10; `docs/catalogue.md`,
//! "Validation: the thesis' plain concrete beam"): the failure mode from the crack pattern
//! (FORMULATION 5), the bending-crack tip against time, and the history checks of the drop and
//! static three-point-bending cases.
//!
//! - [`cracks`]: cracked zones, their crack planes, the failure-mode classification and the
//!   bending-crack tips ([`crack_tip_report`], for the report too).
//! - [`column_demand`]: the elastic column's demand under the hammer against the rate-enhanced
//!   Kupfer envelope, beside the measured pre-damage in the report.
//! - [`history`]: checks on history columns (quasi-static ratio, secant stiffness, peak ratios,
//!   the force balance (6.48) of a body).

pub mod column_demand;
pub mod cracks;
pub mod history;

pub use cracks::{
    classify, crack_tip_report, failure_mode_details, failure_mode_judged, BeamFrame, BeamSpec,
    Crack, CrackKind, CrackTipMeasure, CrackTipReport, FailureMode, JudgedAt, ModeSet,
};

/// Name of the metric whose value is a beam case's failure-mode code ([`FailureMode::code`]):
/// the report's failure-mode comparison shows its value and reference, if present.
pub const FAILURE_MODE_METRIC: &str = "failure_mode";
