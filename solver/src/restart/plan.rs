//! What a run does with checkpoints ([`CheckpointPlan`]), checked before anything is read, and
//! the checkpoint a run starts from: shared by the plain explicit run (`run.rs`) and the run
//! that remeshes (`remeshing_run.rs`).

use std::path::{Path, PathBuf};

use super::error::RestartError;
use super::file;
use super::inputs::Inputs;
use crate::analysis::ExecuteOptions;
use crate::dynamics::CheckpointEvery;

/// What a run does with checkpoints.
#[derive(Debug, Clone, Default)]
pub struct CheckpointPlan {
    /// When a checkpoint falls due; nothing set: none is written.
    pub every: CheckpointEvery,
    /// Start from the newest good checkpoint in the output folder (from the beginning when there
    /// is none).
    pub resume: bool,
    /// The inputs the run reads, stored in each checkpoint and compared on a resume.
    pub inputs: Inputs,
}

/// The checkpoint interval and the run's time limit, checked before anything is read.
pub(super) fn check_plan(
    plan: &CheckpointPlan,
    options: &ExecuteOptions,
) -> Result<(), RestartError> {
    plan.every
        .check()
        .map_err(|message| crate::SolverError::InvalidScene {
            entity: "checkpoint".into(),
            message,
        })?;
    if let Some(limit) = options
        .time_limit_s
        .filter(|t| !(*t > 0.0 && t.is_finite()))
    {
        return Err(crate::SolverError::InvalidScene {
            entity: "time limit".into(),
            message: format!("must be a positive, finite number of seconds, got {limit}"),
        }
        .into());
    }
    Ok(())
}

/// The checkpoint the run starts from: with `plan.resume` the newest good one in `folder`
/// (refusals of damaged ones go to the log); `None` to start from the beginning, after removing
/// any earlier run's checkpoints so that none is resumed by mistake.
pub(super) fn starting_checkpoint(
    folder: &Path,
    plan: &CheckpointPlan,
    options: &ExecuteOptions,
) -> Result<Option<(PathBuf, Vec<u8>)>, RestartError> {
    let start = if plan.resume {
        let (found, refused) = file::newest_good(folder, &plan.inputs)?;
        refused.iter().for_each(|line| (options.log)(line));
        found
    } else {
        None
    };
    if start.is_none() {
        if plan.resume {
            (options.log)(&format!(
                "no checkpoint in `{}`: the run starts from the beginning",
                folder.display()
            ));
        }
        file::remove_earlier(folder, file::Part::ALONE)?;
    }
    Ok(start)
}
