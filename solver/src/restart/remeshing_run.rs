//! A run that remeshes, with checkpoints: the remeshing driver
//! ([`crate::remesh::run_remeshing_checkpointed`]) pauses between two steps whenever a
//! checkpoint falls due, inside a stretch of steps on one mesh as well as between two, and
//! this module writes the checkpoint ([`super::remeshing_payload`]) and goes on; a resume reads
//! the newest good one back onto the scene's problem and the driver goes on from it. The
//! remeshing CSV is rewritten from the records, the near-tip CSV from its lines, the section
//! pictures and field frames written before the checkpoint stay and later ones follow.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::error::{CheckpointError, RestartError};
use super::file;
use super::frames::CheckpointFrames;
use super::inputs::Inputs;
use super::plan::{check_plan, starting_checkpoint, CheckpointPlan};
use super::remeshing_payload::{decode, encode};
use crate::analysis::{ExecuteOptions, Execution, RemeshOutputs};
use crate::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use crate::output::{Deadline, HistoryFile, Progress, RunObserver, StopFlag};
use crate::problem::Problem;
use crate::remesh::{
    run_remeshing_checkpointed, Checkpointing, RemeshCheckpoint, RemeshCheckpoints, RemeshHooks,
    RemeshSettings, RemeshStart,
};

/// Writes the checkpoints of a run that remeshes into its folder, with the field frames whose
/// list each checkpoint stores.
struct Writer<'o> {
    folder: PathBuf,
    inputs: &'o Inputs,
    frames: Option<CheckpointFrames>,
    log: &'o (dyn Fn(&str) + Sync),
    count: usize,
    seconds: f64,
    error: Option<CheckpointError>,
}

impl RemeshCheckpoints for Writer<'_> {
    fn observer(&mut self) -> Option<&mut dyn RunObserver> {
        self.frames.as_mut().map(|f| f as &mut dyn RunObserver)
    }

    fn write(&mut self, at: RemeshCheckpoint<'_>) -> bool {
        let clock = Instant::now();
        let (step, time) = (at.state.step, at.state.time);
        let frames = self
            .frames
            .as_ref()
            .map(|f| f.frames.clone())
            .unwrap_or_default();
        let payload = encode(at, frames);
        match file::write(&self.folder, step, self.inputs, &payload) {
            Ok(path) => {
                let took = clock.elapsed().as_secs_f64();
                self.count += 1;
                self.seconds += took;
                (self.log)(&format!(
                    "checkpoint `{}`: step {step}, t = {time:.6e} s, {:.1} MB in {took:.3} s",
                    path.display(),
                    payload.len() as f64 / 1e6
                ));
                true
            }
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

/// Where the run starts: the checkpoint `start` read back onto `problem` (the scene's), with
/// its field frames and a line for the plan; nothing for a run from the beginning.
#[allow(clippy::type_complexity)]
fn read_start(
    problem: &Problem,
    start: Option<(PathBuf, Vec<u8>)>,
) -> Result<(Option<RemeshStart>, Vec<(f64, String)>, String), CheckpointError> {
    let Some((path, bytes)) = start else {
        return Ok((None, Vec::new(), String::new()));
    };
    let (at, frames) = decode(&bytes, problem).map_err(|e| CheckpointError::Mismatch {
        path: path.clone(),
        detail: format!("its payload does not read back: {}", e.0),
    })?;
    let line = format!(
        "; resumed from `{}` at step {} after {} remeshings",
        path.display(),
        at.state.step,
        at.records.len()
    );
    Ok((Some(at), frames, line))
}

/// [`super::execute_checkpointed`] for an explicit run that remeshes as `remeshing` says: as
/// [`crate::analysis::execute`] runs it, with checkpoints, `problem` replaced by the problem
/// over the last mesh.
pub(super) fn execute_remeshing(
    problem: &mut Problem,
    settings: &ExplicitSettings,
    remeshing: &RemeshSettings,
    options: &ExecuteOptions,
    plan: &CheckpointPlan,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, RestartError> {
    check_plan(plan, options)?;
    let policy = remeshing.policy(problem)?;
    if let Some(spec) = &remeshing.section {
        spec.check()?;
    }
    if let Some(spec) = &remeshing.near_tip {
        spec.probe_index(problem)?;
    }
    let out = options.out.unwrap_or(Path::new("."));
    let folder = file::folder(out, options.stem);
    let output = OutputSettings {
        dir: Some(out.to_path_buf()),
        stem: options.stem.to_string(),
        fields: options.fields,
    };
    let start = starting_checkpoint(&folder, plan, options)?;
    let (start, frames, resumed_line) = read_start(problem, start)?;
    let mut plan_text = format!(
        "{}; remeshing body `{}` where an element's collapse ratio passes {} (checked every {} \
         steps)",
        ExplicitSolver::new(problem, settings.clone(), output.clone())?.plan(),
        remeshing.body,
        policy.collapse_limit,
        policy.check_every
    );
    plan_text += &resumed_line;
    if let Some(s) = plan.every.every_s {
        plan_text += &format!("; a checkpoint every {s} s of wall time");
    }
    if let Some(n) = plan.every.every_steps {
        plan_text += &format!("; a checkpoint every {n} steps");
    }

    let started = Instant::now();
    let mut writer = Writer {
        folder,
        inputs: &plan.inputs,
        frames: if options.fields {
            Some(CheckpointFrames::new(out, options.stem, &frames)?)
        } else {
            None
        },
        log: options.log,
        count: 0,
        seconds: 0.0,
        error: None,
    };
    let mut history = HistoryFile::new(out.join(format!("{}_history.csv", options.stem)));
    let mut deadline = options.time_limit_s.map(Deadline::after);
    let mut stop = options.stop.clone().map(StopFlag);
    let mut progress = Progress(progress);
    let mut observers: Vec<&mut dyn RunObserver> = vec![&mut history];
    observers.extend(deadline.as_mut().map(|o| o as &mut dyn RunObserver));
    observers.extend(stop.as_mut().map(|o| o as &mut dyn RunObserver));
    observers.push(&mut progress);
    let mut outputs = RemeshOutputs::new(problem, remeshing, &policy, options)?;
    let outcome = run_remeshing_checkpointed(
        problem,
        settings,
        &output,
        &policy,
        &mut observers,
        RemeshHooks {
            on_remesh: &mut |record| (options.log)(&record.summary()),
            watch: &mut outputs.watches(),
        },
        Some(Checkpointing {
            every: plan.every,
            start,
            writer: &mut writer,
        }),
    );
    let end = outcome
        .as_ref()
        .ok()
        .map(|run| (run.problem.as_ref().unwrap_or(problem), &run.state));
    let (written, _recorded) = outputs.close(end);
    if let Some(e) = writer.error.take() {
        return Err(e.into());
    }
    let run = outcome?;
    if writer.count > 0 {
        (options.log)(&format!(
            "{} checkpoints written in {:.3} s of the run's {:.3} s of wall time",
            writer.count,
            writer.seconds,
            started.elapsed().as_secs_f64()
        ));
    }
    let mut summary = run.summary;
    summary.written.extend(written?);
    if let Some(p) = run.problem {
        *problem = p;
    }
    Ok(Execution {
        plan: plan_text,
        u: run.state.u.clone(),
        v: Some(run.state.v_full.clone()),
        history: Some(summary.history.clone()),
        written: summary.written.clone(),
        summary: Some(summary),
        static_solution: None,
        contact_problems: Vec::new(),
        material_history: Some(run.state.history),
        remeshings: run.records,
    })
}
