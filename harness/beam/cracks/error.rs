//! Why a beam's cracks cannot be read from a run.

use crate::beam::history::HistoryError;

/// Why the cracks, the failure mode or the crack tips of a beam cannot be read: each message
/// names the body, column or setting and what to set.
#[derive(Debug, thiserror::Error)]
pub enum CrackError {
    /// The case's beam body is not in the model.
    #[error("no body named `{body}`")]
    NoBody {
        /// The body asked for.
        body: String,
    },
    /// The beam body has no elements.
    #[error("body `{body}` has no elements")]
    NoElements {
        /// The body.
        body: String,
    },
    /// No snapshot was kept at or after the end of the contact.
    #[error(
        "no snapshot at or after the end of the contact ({end_ms:.4} ms): set the explicit \
         analysis' snapshot_interval"
    )]
    NoSnapshotAfterContact {
        /// The end of the contact (ms).
        end_ms: f64,
    },
    /// The run kept no history (a static run).
    #[error("the run kept no history")]
    NoHistory,
    /// The history has no time column.
    #[error("the history has no `time` column")]
    NoTime,
    /// The history lacks the contact force's column.
    #[error("the history has no column `{column}`")]
    NoColumn {
        /// The column asked for.
        column: String,
    },
    /// The end of the contact cannot be found in its column.
    #[error("`{column}`: {source}")]
    ContactEnd {
        /// The contact force's column.
        column: String,
        /// Why.
        source: HistoryError,
    },
    /// The cohesive tip is defined by the microplane law only.
    #[error("the cohesive tip needs a microplane concrete beam")]
    NotMicroplane,
    /// The beam's microplane parameters are refused.
    #[error(transparent)]
    Parameters(#[from] impact_solver::material::microplane::ParameterError),
    /// The crack-opening law never falls to the tip's stress fraction.
    #[error("the material's crack-opening law at {cell} m never falls to {fraction} f_t")]
    NoCohesiveOpening {
        /// The cell size (m).
        cell: f64,
        /// The fraction of the tensile strength that marks the tip.
        fraction: f64,
    },
    /// The run kept no snapshot.
    #[error("the crack tips need snapshots: set the explicit analysis' snapshot_interval")]
    NoSnapshots,
    /// The beam body has no built-in material model.
    #[error("body `{body}` has no built-in material model")]
    NoMaterialModel {
        /// The body.
        body: String,
    },
    /// The snapshots carry no crack openings for the beam.
    #[error(
        "the snapshots hold no crack openings for body `{body}`: only a body whose material keeps \
         a history (microplane concrete) can open a crack"
    )]
    NoCrackOpenings {
        /// The body.
        body: String,
    },
    /// A snapshot's openings do not match the beam's elements.
    #[error("a snapshot holds {openings} openings for the beam's {elements} elements")]
    OpeningCount {
        /// Openings in the snapshot.
        openings: usize,
        /// Elements of the beam.
        elements: usize,
    },
    /// Snapshots and times differ in number.
    #[error("{snapshots} snapshots of openings for {times} times")]
    SnapshotCount {
        /// Snapshots of openings.
        snapshots: usize,
        /// Times.
        times: usize,
    },
}
