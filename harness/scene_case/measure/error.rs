//! Why a per-run measure has no value: each family of measures has an error of its own, naming
//! what the measure lacks; this one wraps them, with the errors of the measures that other
//! modules evaluate (crack band, crack tips, contact replay) and of the sweep measures.

use super::energy::EnergyError;
use super::motion::MotionError;
use super::signal::SignalError;
use super::stress::StressError;
use super::structure::StructureError;
use crate::band::BandError;
use crate::beam::cracks::CrackError;
use crate::replay::ReplayError;

/// Why a measure has no value: the run lacks what the measure reads (a history, a column, a
/// body, a snapshot), or the values make it undefined. Each message names the column, body or
/// constraint and, where one exists, what to change in the case.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// A measure of history signals.
    #[error(transparent)]
    Signal(#[from] SignalError),
    /// An energy measure.
    #[error(transparent)]
    Energy(#[from] EnergyError),
    /// A measure of the final motion.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A measure of the final stresses, strains or reactions.
    #[error(transparent)]
    Stress(#[from] StressError),
    /// A structural measure.
    #[error(transparent)]
    Structure(#[from] StructureError),
    /// A crack-band measure has no value.
    #[error(transparent)]
    Band(#[from] BandError),
    /// The beam's crack tips cannot be read.
    #[error(transparent)]
    Crack(#[from] CrackError),
    /// The recorded contact problems cannot be replayed.
    #[error(transparent)]
    Replay(#[from] ReplayError),
    /// A sweep measure in a per-run metric.
    #[error("{measure} is a sweep measure: the case needs a sweep")]
    SweepMeasure {
        /// The measure, as written by `Debug`.
        measure: String,
    },
    /// A sweep measure in a case without a sweep.
    #[error("this measure needs a sweep in the case")]
    NeedsSweep,
    /// A sweep measure of the time step in another sweep.
    #[error("needs a time-step sweep")]
    NeedsTimeStepSweep,
    /// An observed order from fewer than two levels.
    #[error("metric `{metric}` has fewer than two levels with a positive error")]
    FewLevels {
        /// The metric whose errors are fitted.
        metric: String,
    },
}
