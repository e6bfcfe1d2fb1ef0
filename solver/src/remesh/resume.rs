//! What a run that remeshes hands to a checkpoint between two steps, and what it goes on from
//! after one ([`super::run_remeshing_checkpointed`]). Besides the integrator's state, the run
//! stands on what its remeshings made: the problem over the current mesh, their records, the
//! distortion that triggers the next one, the time step the stable limit forced since the last
//! one, and what its watches hold. The checkpoint pauses the run inside a stretch of steps on
//! one mesh without ending it: the same solver goes on, and a resumed run rebuilds that solver
//! with the segment's own time origin ([`crate::dynamics::ExplicitSolver::restored`]), so its
//! arithmetic is the run's that was never stopped.

use super::record::RemeshRecord;
use super::watch::WatchMarks;
use crate::dynamics::{CheckpointEvery, RestartState};
use crate::output::RunObserver;
use crate::problem::Problem;

/// A run that remeshes, between two steps, as a checkpoint stores it (borrowed from the run).
#[derive(Debug)]
pub struct RemeshCheckpoint<'a> {
    /// The problem over the current mesh; `None` before the first remeshing (the scene's).
    pub problem: Option<&'a Problem>,
    /// Every remeshing so far, in time order.
    pub records: &'a [RemeshRecord],
    /// The distortion that triggers the next remeshing ([`super::RemeshPolicy::threshold_after`]).
    pub threshold: f64,
    /// The time step the current stretch runs with where the stable limit fell since the last
    /// remeshing (s); `None`: the settings' own.
    pub step_now: Option<f64>,
    /// The integrator's state and the output schedule.
    pub state: RestartState,
    /// The history's columns.
    pub columns: &'a [String],
    /// Every history row written so far.
    pub rows: &'a [Vec<f64>],
    /// What the watches hold.
    pub watches: WatchMarks,
}

/// What [`RemeshCheckpoint`] stored, read back: the run goes on from it.
#[derive(Debug)]
pub struct RemeshStart {
    /// The problem over the current mesh; `None` before the first remeshing.
    pub problem: Option<Problem>,
    /// Every remeshing so far.
    pub records: Vec<RemeshRecord>,
    /// See [`RemeshCheckpoint::threshold`].
    pub threshold: f64,
    /// See [`RemeshCheckpoint::step_now`].
    pub step_now: Option<f64>,
    /// The integrator's state and the output schedule.
    pub state: RestartState,
    /// The history's columns when the checkpoint was written.
    pub columns: Vec<String>,
    /// Every history row written up to the checkpoint: written again, the file rebuilt.
    pub rows: Vec<Vec<f64>>,
    /// What the watches held.
    pub watches: WatchMarks,
}

/// Writes the checkpoints of a run that remeshes.
pub trait RemeshCheckpoints {
    /// An observer of the run's output whose marks the checkpoint stores (the field frames),
    /// shown every step with the run's own observers.
    fn observer(&mut self) -> Option<&mut dyn RunObserver>;

    /// Writes a checkpoint of the run at `at`; false when that failed: the writer keeps the
    /// error to report, and the run stops.
    fn write(&mut self, at: RemeshCheckpoint<'_>) -> bool;
}

/// A run's checkpoints: when they fall due, where the run starts, who writes them.
pub struct Checkpointing<'a> {
    /// When a checkpoint falls due (wall time since the last, or steps).
    pub every: CheckpointEvery,
    /// The checkpoint the run goes on from; `None`: from the beginning.
    pub start: Option<RemeshStart>,
    /// Writes each checkpoint.
    pub writer: &'a mut dyn RemeshCheckpoints,
}
