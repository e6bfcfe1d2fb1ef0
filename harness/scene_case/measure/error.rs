//! Why a per-run measure has no value.

use crate::band::BandError;
use crate::beam::cracks::CrackError;
use crate::beam::history::HistoryError;
use crate::curve::CurveError;
use crate::replay::ReplayError;

/// Why a per-run measure has no value: the run lacks what the measure reads (a history, a
/// column, a body, a snapshot), or the values make it undefined. Each message names the column,
/// body or constraint and, where one exists, what to change in the case.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// A history column is missing, or a curve cannot be fitted.
    #[error(transparent)]
    Column(#[from] CurveError),
    /// A history check has no value.
    #[error(transparent)]
    History(#[from] HistoryError),
    /// A history check of a named column has no value.
    #[error("`{column}`: {source}")]
    OfColumn {
        /// The column.
        column: String,
        /// Why.
        source: HistoryError,
    },
    /// A crack-band measure has no value.
    #[error(transparent)]
    Band(#[from] BandError),
    /// The beam's cracks cannot be read.
    #[error(transparent)]
    Crack(#[from] CrackError),
    /// The recorded contact problems cannot be replayed.
    #[error(transparent)]
    Replay(#[from] ReplayError),
    /// The history has no record.
    #[error("empty history")]
    Empty,
    /// No record in a plateau's time window.
    #[error("no record of `{column}` between t = {from} and {to}")]
    NoRecordInWindow {
        /// The column.
        column: String,
        /// Start of the window (s).
        from: f64,
        /// End of the window (s).
        to: f64,
    },
    /// The measure reads the velocities or summary of an explicit run.
    #[error("needs an explicit run")]
    NeedsExplicitRun,
    /// The kinetic energy is zero at the start.
    #[error("the initial kinetic energy is zero")]
    KineticZero,
    /// A drifting vector starts at zero.
    #[error("the vector is zero at the start: no relative drift")]
    VectorZero,
    /// No body of that name.
    #[error("no body named `{body}`")]
    NoBody {
        /// The body asked for.
        body: String,
    },
    /// A body's inertia tensor cannot be inverted.
    #[error("the body's inertia tensor is singular")]
    SingularInertia,
    /// The uniform stress has no closed form for the material.
    #[error("uniform_stress_error has no closed form for {material}")]
    NoClosedForm {
        /// The material's name.
        material: String,
    },
    /// No constraint of that name.
    #[error("no constraint named `{constraint}`")]
    NoConstraint {
        /// The constraint asked for.
        constraint: String,
    },
    /// A column crosses its mean fewer than twice: no frequency.
    #[error("`{column}` crosses its mean fewer than twice")]
    FewCrossings {
        /// The column.
        column: String,
    },
    /// No crack in the snapshots: no window for the reaction asymmetry.
    #[error("no element of the beam cracks in the snapshots: no window")]
    NoCrackWindow,
    /// A sweep measure in a per-run metric.
    #[error("{measure} is a sweep measure: the case needs a sweep")]
    SweepMeasure {
        /// The measure, as written by `Debug`.
        measure: String,
    },
    /// No element centroid in the box of a stress measure.
    #[error("no element centroid lies in the box {min:?} - {max:?}")]
    EmptyBox {
        /// Lower corner (m).
        min: [f64; 3],
        /// Upper corner (m).
        max: [f64; 3],
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
    /// A column is zero throughout.
    #[error("the column is zero throughout")]
    ColumnZero,
    /// A signal never reaches the arrival level.
    #[error("the signal never reaches {level}")]
    NeverReaches {
        /// The level.
        level: f64,
    },
}
