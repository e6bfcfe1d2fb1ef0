//! Checkpoints and resume of `impact-vv scene`: the command line's `--checkpoint-every`,
//! `--checkpoint-every-steps` and `--resume` over the scene's `analysis.explicit.checkpoint`,
//! and the run through [`impact_solver::restart`].

use std::path::Path;

use impact_solver::analysis::{ExecuteOptions, Execution};
use impact_solver::dynamics::CheckpointEvery;
use impact_solver::restart::{execute_checkpointed, CheckpointPlan, Inputs, RestartError};
use impact_solver::scene::{Analysis, Scene};
use impact_solver::Problem;

/// What the command line asks of checkpoints.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RestartRequest {
    /// `--checkpoint-every SECONDS` (wall time).
    pub every_s: Option<f64>,
    /// `--checkpoint-every-steps N`.
    pub every_steps: Option<usize>,
    /// `--resume`: go on from the newest good checkpoint in the output folder.
    pub resume: bool,
}

/// The checkpoints a scene run writes: the command line's when it sets any, else the scene's
/// `analysis.explicit.checkpoint`.
fn every(scene: &Scene, request: &RestartRequest) -> CheckpointEvery {
    let asked = CheckpointEvery {
        every_s: request.every_s,
        every_steps: request.every_steps,
    };
    if asked.is_set() {
        return asked;
    }
    match &scene.analysis {
        Analysis::Explicit(a) | Analysis::Release { explicit: a, .. } => {
            a.settings.checkpoint.unwrap_or_default()
        }
        Analysis::Static(_) => CheckpointEvery::default(),
    }
}

/// The run of `scene` (read from `path`) with checkpoints, or `None` when neither the command
/// line nor the scene asks for checkpoints or a resume (the run is then the plain one). A run
/// that remeshes leaves `problem` over its last mesh.
pub fn run_with_checkpoints(
    path: &Path,
    scene: &Scene,
    problem: &mut Problem,
    options: &ExecuteOptions,
    request: &RestartRequest,
    progress: &mut dyn FnMut(f64),
) -> Option<Result<Execution, RestartError>> {
    let every = every(scene, request);
    if !every.is_set() && !request.resume {
        return None;
    }
    let inputs = match Inputs::of_scene_file(path, scene) {
        Ok(i) => i,
        Err(e) => return Some(Err(RestartError::Checkpoint(e))),
    };
    let plan = CheckpointPlan {
        every,
        resume: request.resume,
        inputs,
    };
    Some(execute_checkpointed(
        problem,
        &scene.analysis,
        options,
        &plan,
        progress,
    ))
}
