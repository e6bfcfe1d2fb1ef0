//! An explicit run that remeshes (thesis 9.2, Box 8.1): every `check_every` steps the
//! distortion of the remeshed body's elements is checked; where one passes the limit, the run
//! pauses between two steps, the distorted elements grown by `layers` layers are remeshed
//! ([`remesh_problem`]) and the run goes on over the new mesh
//! ([`crate::dynamics::ExplicitSolver::resume`]). One set of observers and one
//! [`OutputSchedule`] span the whole run, so its history, frames and energy check read as one
//! run's. A run may also pause for a checkpoint (`resume.rs`): the same solver then goes on,
//! and a run resumed from one goes on from it bit for bit.

use std::path::PathBuf;
use std::time::Instant;

use nalgebra::Vector3;

use super::apply::remesh_problem;
use super::distortion::distortion;
use super::record::RemeshRecord;
use super::resume::{Checkpointing, RemeshCheckpoint, RemeshStart};
use super::run::RemeshPolicy;
use super::watch::{RemeshWatch, WatchMarks};
use crate::dynamics::{
    CheckpointEvery, ExplicitSettings, ExplicitSolver, OutputSchedule, OutputSettings, RunState,
    RunSummary, SegmentEnd,
};
use crate::error::{Result, SolverError};
use crate::output::{ObserverSet, Recorder, RunObserver};
use crate::problem::Problem;

/// Why a segment of the run paused.
enum Pause {
    /// It did not (it finished).
    None,
    /// These elements passed the collapse limit.
    Remesh(Vec<usize>),
    /// The stable limit fell: go on with this step (s).
    TimeStep(f64),
    /// A checkpoint fell due: the same solver goes on after it.
    Checkpoint,
}

/// The largest distortion of the elements of body `body` (on the model's reference, which after
/// a remeshing is the current configuration).
fn worst_distortion(model: &crate::model::Model, body: usize) -> f64 {
    model.bodies[body]
        .elements
        .clone()
        .map(|e| distortion(&model.tets[e].map(|n| model.reference[n as usize])))
        .fold(0.0, f64::max)
}

/// A run with remeshing: its summary (as [`ExplicitSolver::run_with`]'s, over the whole run),
/// the problem and state it ended with, and the record of each remeshing.
#[derive(Debug)]
pub struct RemeshingRun {
    /// The whole run's summary: history, snapshots (displacements from the reference of the
    /// mesh they were taken on), energies, timings.
    pub summary: RunSummary,
    /// The problem over the last mesh; `None` when the run never remeshed (it ended on the
    /// problem it was given).
    pub problem: Option<Problem>,
    /// The state at the end, on the last mesh.
    pub state: RunState,
    /// Every remeshing, in time order.
    pub records: Vec<RemeshRecord>,
}

/// Runs `problem` to the end time of `settings` with `observers`, remeshing as `policy` says;
/// `on_remesh` sees each remeshing's record ([`run_remeshing_watched`] without a watch).
pub fn run_remeshing(
    problem: &Problem,
    settings: &ExplicitSettings,
    output: &OutputSettings,
    policy: &RemeshPolicy,
    observers: &mut [&mut dyn RunObserver],
    on_remesh: &mut dyn FnMut(&RemeshRecord),
) -> Result<RemeshingRun> {
    run_remeshing_watched(
        problem,
        settings,
        output,
        policy,
        observers,
        on_remesh,
        &mut (),
    )
}

/// Runs `problem` to the end time of `settings` with `observers`, remeshing as `policy` says:
/// `on_remesh` sees each remeshing's record, and `watch` the start, every step and every
/// remeshing with the problem and state it made ([`RemeshWatch`]).
/// An instability or a halt writes what the observers hold and returns the error; a remeshing
/// that fails returns its error after the observers have written what they hold.
pub fn run_remeshing_watched(
    problem: &Problem,
    settings: &ExplicitSettings,
    output: &OutputSettings,
    policy: &RemeshPolicy,
    observers: &mut [&mut dyn RunObserver],
    on_remesh: &mut dyn FnMut(&RemeshRecord),
    watch: &mut dyn RemeshWatch,
) -> Result<RemeshingRun> {
    run_remeshing_checkpointed(
        problem,
        settings,
        output,
        policy,
        observers,
        RemeshHooks { on_remesh, watch },
        None,
    )
}

/// What sees a remeshing run go: `on_remesh` each remeshing's record, `watch` the start, every
/// step and every remeshing.
pub struct RemeshHooks<'a> {
    /// Sees each remeshing's record.
    pub on_remesh: &'a mut dyn FnMut(&RemeshRecord),
    /// Sees the start, every step and every remeshing ([`RemeshWatch`]).
    pub watch: &'a mut dyn RemeshWatch,
}

/// The observers of one stretch of steps: the caller's, the checkpoint writer's, the recorder,
/// with the files written so far.
macro_rules! observer_set {
    ($observers:expr, $checkpointing:expr, $recorder:expr, $written:expr) => {{
        let mut all: Vec<&mut dyn RunObserver> = $observers
            .iter_mut()
            .map(|o| &mut **o as &mut dyn RunObserver)
            .collect();
        all.extend($checkpointing.as_mut().and_then(|c| c.writer.observer()));
        all.push(&mut $recorder);
        let mut set = ObserverSet::new(all);
        set.written = std::mem::take(&mut $written);
        set
    }};
}

/// The checks after each step that pause a stretch for a remeshing or a shorter time step.
struct Checks<'a> {
    policy: &'a RemeshPolicy,
    /// The distortion that triggers a remeshing.
    threshold: f64,
    /// Whether the time step follows the stable limit (none set in the settings).
    adapt: bool,
    /// The fraction of the current stable limit past which the step is shortened.
    trigger: f64,
    /// The settings' safety factor on the stable limit.
    safety: f64,
}

impl Checks<'_> {
    /// Why the run pauses after the step `s` on `problem` has just made; `None`: it goes on.
    fn pause(&self, problem: &Problem, s: &ExplicitSolver<'_>) -> Option<Pause> {
        let policy = self.policy;
        if s.step % policy.check_every.max(1) != 0 {
            return None;
        }
        let m = &problem.model;
        let x: Vec<Vector3<f64>> = m.reference.iter().zip(&s.u).map(|(x, u)| x + u).collect();
        let region = policy.region(problem, &x, self.threshold);
        if !region.is_empty() {
            // With erosion, every element past the limit is offered to the remesher (the
            // regrowth threshold only decides when): one the last remeshing left collapsed,
            // below the threshold, would otherwise stay outside the region and never be
            // reshaped or eroded.
            return Some(Pause::Remesh(if policy.mesher.erode {
                let mut offered = policy.region(problem, &x, policy.collapse_limit);
                offered.extend(policy.torn(problem, &s.u));
                offered.sort_unstable();
                offered.dedup();
                offered
            } else {
                region
            }));
        }
        if self.adapt {
            let (limit, _) = m.current_critical_time_step(&s.u);
            // An element turned inside out since the last step has a negative altitude: the
            // next step's forces stop the run on it, naming the element (a step from it would
            // be negative, and the error would blame the step).
            if limit > 0.0 && s.time_step() > self.trigger * limit {
                return Some(Pause::TimeStep(self.safety * limit));
            }
        }
        None
    }
}

/// Whether a checkpoint falls due after step `step`, the last written at `since`.
fn checkpoint_due(every: Option<CheckpointEvery>, step: usize, since: Instant) -> bool {
    every.is_some_and(|e| {
        e.every_steps.is_some_and(|n| step % n == 0)
            || e.every_s
                .is_some_and(|t| since.elapsed().as_secs_f64() >= t)
    })
}

/// [`run_remeshing_watched`] with checkpoints: with `checkpointing`, the run pauses between
/// two steps whenever a checkpoint falls due, hands its whole state to the writer, and goes on
/// with the same solver; with its `start`, the run goes on from that checkpoint (the history
/// rows written again through the observers, the watches told, the solver restored with its
/// segment's origin) instead of from the beginning.
pub fn run_remeshing_checkpointed(
    problem: &Problem,
    settings: &ExplicitSettings,
    output: &OutputSettings,
    policy: &RemeshPolicy,
    observers: &mut [&mut dyn RunObserver],
    hooks: RemeshHooks<'_>,
    mut checkpointing: Option<Checkpointing<'_>>,
) -> Result<RemeshingRun> {
    let RemeshHooks { on_remesh, watch } = hooks;
    let started = Instant::now();
    let mut recorder = Recorder::default();
    let mut written: Vec<PathBuf> = Vec::new();
    let mut schedule = OutputSchedule::default();
    let every = checkpointing.as_ref().map(|c| c.every);
    let start = checkpointing.as_mut().and_then(|c| c.start.take());
    let mut restored: Option<(crate::dynamics::RestartState, Vec<String>, Vec<Vec<f64>>)> = None;
    let mut watch_marks = WatchMarks::default();
    let (mut owned, mut records, mut threshold, mut step_now) = match start {
        Some(RemeshStart {
            problem,
            records,
            threshold,
            step_now,
            state,
            columns,
            rows,
            watches,
        }) => {
            restored = Some((state, columns, rows));
            watch_marks = watches;
            (problem, records, threshold, step_now)
        }
        None => (None, Vec::new(), policy.collapse_limit, None),
    };
    let mut state: Option<RunState> = None;
    // The time step: the settings' own, or `safety` times the stable limit, shrunk where the
    // current limit falls (elements flattened under a penetrator): when the step passes
    // halfway from `safety` to 1 times the current limit, the run pauses and goes on with
    // `safety` times it (without remeshing; thesis 10.4.1.1 on the falling limit).
    let adapt = settings.time_step.is_none();
    let trigger = 0.5 * (settings.safety + 1.0);
    if restored.is_none() {
        watch.start(problem);
    }
    let mut last_checkpoint = Instant::now();
    let (summary, last_state) = loop {
        let current = owned.as_ref().unwrap_or(problem);
        let mut resumed = settings.clone();
        resumed.time_step = resumed.time_step.or(step_now);
        let checks = Checks {
            policy,
            threshold,
            adapt,
            trigger,
            safety: settings.safety,
        };
        let (end, now, pause, summary) = {
            let problem = current;
            let mut solver = match (restored.take(), state.take()) {
                (Some((at, columns, rows)), _) => {
                    let (solver, restored_schedule) =
                        ExplicitSolver::restored(problem, resumed, output.clone(), at)?;
                    if columns != solver.history_columns() {
                        return Err(SolverError::InvalidScene {
                            entity: "checkpoint".into(),
                            message: "its history columns differ from this scene's".into(),
                        });
                    }
                    schedule = restored_schedule;
                    let mut set = observer_set!(observers, checkpointing, recorder, written);
                    set.history_columns(&columns)?;
                    for row in &rows {
                        set.history_row(row)?;
                    }
                    written = std::mem::take(&mut set.written);
                    watch.resumed(problem, &solver, &records, &watch_marks);
                    solver
                }
                (None, Some(s)) => ExplicitSolver::resume(problem, resumed, output.clone(), s)?,
                (None, None) => {
                    let solver = ExplicitSolver::new(problem, resumed, output.clone())?;
                    let mut set = observer_set!(observers, checkpointing, recorder, written);
                    set.history_columns(&solver.history_columns())?;
                    written = std::mem::take(&mut set.written);
                    solver
                }
            };
            let (end, pause) = loop {
                let mut set = observer_set!(observers, checkpointing, recorder, written);
                let mut pause = Pause::None;
                let since = last_checkpoint;
                let end = solver.run_segment(&mut set, &mut schedule, &mut |s| {
                    watch.step(problem, s);
                    pause = match checks.pause(problem, s) {
                        Some(p) => p,
                        None if checkpoint_due(every, s.step, since) => Pause::Checkpoint,
                        None => return false,
                    };
                    true
                });
                written = std::mem::take(&mut set.written);
                drop(set);
                let (Pause::Checkpoint, Ok(SegmentEnd::Paused), Some(c)) =
                    (&pause, &end, checkpointing.as_mut())
                else {
                    break (end, pause);
                };
                let mut watches = WatchMarks::default();
                watch.marks(&mut watches);
                let history = recorder.history.as_ref();
                let at = RemeshCheckpoint {
                    problem: owned.as_ref(),
                    records: &records,
                    threshold,
                    step_now,
                    state: solver.restart_state(&schedule),
                    columns: history.map_or(&[], |h| h.columns()),
                    rows: history.map_or(&[], |h| h.rows()),
                    watches,
                };
                if !c.writer.write(at) {
                    let mut set = observer_set!(observers, checkpointing, recorder, written);
                    let _ = set.finish();
                    return Err(SolverError::Interrupted {
                        step: solver.step,
                        time: solver.time,
                    });
                }
                last_checkpoint = Instant::now();
            };
            watch.contact_problems(&solver.take_recorded_problems());
            let end = end?;
            let summary = (end == SegmentEnd::Finished)
                .then(|| solver.summary(&schedule, started, Recorder::default(), Vec::new()));
            (end, solver.into_state(), pause, summary)
        };
        if let (SegmentEnd::Finished, Some(summary)) = (end, summary) {
            break (summary, now);
        }
        let region = match pause {
            Pause::TimeStep(dt) => {
                step_now = Some(dt);
                state = Some(now);
                continue;
            }
            Pause::Remesh(region) => region,
            Pause::None | Pause::Checkpoint => Vec::new(),
        };
        let mut set = observer_set!(observers, checkpointing, recorder, written);
        // A signal that came during the last steps stops the run here rather than after a
        // remeshing that may take seconds.
        if let Some(crate::output::Halt::Interrupted) = set.poll(None) {
            set.finish()?;
            return Err(SolverError::Interrupted {
                step: now.step,
                time: now.time,
            });
        }
        if records.len() >= policy.max_remeshings {
            let _ = set.finish();
            return Err(too_many_remeshings(policy, now.time));
        }
        // The stable limit that gives the step `mass_scaling_step` at the run's safety.
        let critical_step = policy.mass_scaling_step / settings.safety;
        let remeshed = match remesh_problem(current, &now, &region, &policy.mesher, critical_step) {
            Ok(r) => r,
            Err(e) => {
                let _ = set.finish();
                return Err(e);
            }
        };
        written = std::mem::take(&mut set.written);
        drop(set);
        threshold = policy.threshold_after(worst_distortion(&remeshed.problem.model, policy.body));
        on_remesh(&remeshed.record);
        records.push(remeshed.record);
        owned = Some(remeshed.problem);
        state = Some(remeshed.state);
        // The new mesh's reference is the current configuration: its own limit applies.
        step_now = None;
        if let (Some(record), Some(p), Some(s)) = (records.last(), &owned, &state) {
            watch.remeshed(record, p, s);
        }
    };
    let mut set = observer_set!(observers, checkpointing, recorder, written);
    set.finish()?;
    let written = std::mem::take(&mut set.written);
    drop(set);
    let mut summary = summary;
    summary.history = recorder
        .history
        .unwrap_or_else(|| crate::output::HistoryTable::new(Vec::new()));
    summary.snapshots = recorder.snapshots;
    summary.written = written;
    summary.wall_seconds = started.elapsed().as_secs_f64();
    Ok(RemeshingRun {
        summary,
        problem: owned,
        state: last_state,
        records,
    })
}

/// The error of a run that needs more remeshings than `policy` allows, at time `time` (s).
fn too_many_remeshings(policy: &RemeshPolicy, time: f64) -> SolverError {
    SolverError::Remesh {
        entity: "run".to_string(),
        message: format!(
            "needs more than the {} remeshings allowed (at t = {time:.6e} s)",
            policy.max_remeshings
        ),
    }
}
