//! Checkpoint and restart of an explicit run: every so many steps or seconds of wall time the
//! whole state the next step reads (displacements, velocities, the last increment, the energy
//! ledger, every element's material history, the step and time with their segment's origin,
//! the output schedule and what the output holds) is written to a versioned, checksummed file,
//! atomically, and the last two are kept. A later process resumes from the newest good one and
//! goes on bit for bit as the run that was never stopped: the history CSV is rebuilt from the
//! checkpoint's rows and appended, the field frames and their collection follow.
//!
//! - [`bytes`]: the little-endian writer and reader, FNV-1a 64;
//! - [`file`](mod@file): the header, the atomic write, the newest good checkpoint;
//! - [`inputs`]: the hashes of the scene, mesh and material files;
//! - [`payload`]: the state's layout;
//! - [`problem`]: a remeshed run's problem;
//! - [`ranks`]: the checkpoints of a run over several ranks, each rank's part and the ranks'
//!   agreement on the step written and the step resumed from;
//! - [`remeshings`]: the remeshings a run made so far;
//! - [`remeshing_payload`]: the checkpoint of a run that remeshes;
//! - `remeshing_run`: the run that remeshes, writing them and resuming from one;
//! - `plan`: what a run does with checkpoints, the one it starts from;
//! - [`run`]: the run that writes them and resumes from one.

pub mod bytes;
mod error;
pub mod file;
mod frames;
pub mod inputs;
pub mod payload;
mod plan;
pub mod problem;
pub mod ranks;
pub mod remeshing_payload;
mod remeshing_run;
pub mod remeshings;
pub mod run;

pub use error::{CheckpointError, RestartError};
pub use inputs::{Input, Inputs};
pub use plan::CheckpointPlan;
pub use run::execute_checkpointed;
