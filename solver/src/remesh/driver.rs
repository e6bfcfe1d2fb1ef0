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

use super::apply::remesh_problem;
use super::record::RemeshRecord;
use super::resume::{Checkpointing, RemeshCheckpoint, RemeshStart};
use super::run::RemeshPolicy;
use super::watch::{RemeshWatch, WatchMarks};
use crate::dynamics::{
    CheckpointEvery, ExplicitSettings, ExplicitSolver, OutputSchedule, OutputSettings,
    RestartState, RunState, RunSummary, SegmentEnd,
};
use crate::error::{Result, SolverError};
use crate::mesh::ops::distortion::distortion;
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

impl<'a> Checks<'a> {
    /// The checks of `policy` with the remeshing threshold `threshold`. The time step: the
    /// settings' own, or `safety` times the stable limit, shrunk where the current limit falls
    /// (elements flattened under a penetrator): when the step passes halfway from `safety` to 1
    /// times the current limit, the run pauses and goes on with `safety` times it (without
    /// remeshing; thesis 10.4.1.1 on the falling limit).
    fn new(policy: &'a RemeshPolicy, threshold: f64, settings: &ExplicitSettings) -> Self {
        Self {
            policy,
            threshold,
            adapt: settings.time_step.is_none(),
            trigger: 0.5 * (settings.safety + 1.0),
            safety: settings.safety,
        }
    }

    /// Why the run pauses after the step `s` on `problem` has just made; `None`: it goes on.
    fn pause(&self, problem: &Problem, s: &ExplicitSolver<'_>) -> Option<Pause> {
        let policy = self.policy;
        if s.step % policy.check_every.max(1) != 0 {
            return None;
        }
        let m = &problem.model;
        let u = s.whole(&s.u);
        let x = m.positions(&u);
        let region = policy.region(problem, &x, self.threshold);
        if !region.is_empty() {
            // With erosion, every element past the limit is offered to the remesher (the
            // regrowth threshold only decides when): one the last remeshing left collapsed,
            // below the threshold, would otherwise stay outside the region and never be
            // reshaped or eroded.
            return Some(Pause::Remesh(if policy.mesher.erode {
                let mut offered = policy.region(problem, &x, policy.collapse_limit);
                offered.extend(policy.torn(problem, &u));
                offered.sort_unstable();
                offered.dedup();
                offered
            } else {
                region
            }));
        }
        if self.adapt {
            let (limit, _) = m.current_critical_time_step(&u);
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
    let (mut owned, mut records, mut threshold, mut step_now, mut restored, watch_marks) =
        unpack(start, policy);
    let mut state: Option<RunState> = None;
    if restored.is_none() {
        watch.start(problem);
    }
    let mut last_checkpoint = Instant::now();
    let (summary, last_state) = loop {
        let current = owned.as_ref().unwrap_or(problem);
        let mut resumed = settings.clone();
        resumed.time_step = resumed.time_step.or(step_now);
        let checks = Checks::new(policy, threshold, settings);
        let (end, now, pause, summary) = {
            let problem = current;
            let resuming = restored.is_some();
            let mut solver = {
                let mut set = observer_set!(observers, checkpointing, recorder, written);
                let solver = segment_solver(
                    (problem, resumed, output),
                    restored.take(),
                    state.take(),
                    &mut set,
                    &mut schedule,
                )?;
                written = std::mem::take(&mut set.written);
                solver
            };
            if resuming {
                watch.resumed(problem, &solver, &records, &watch_marks);
            }
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
                let at = Stand {
                    owned: owned.as_ref(),
                    records: &records,
                    threshold,
                    step_now,
                };
                if !write_checkpoint(c, at, &solver, &schedule, &recorder, &*watch) {
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
        let remeshed = remesh(
            current,
            &now,
            &region,
            (policy, settings),
            &mut set,
            &records,
        )?;
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

/// Where a run stands besides its solver: the problem over the current mesh (`None`: the
/// scene's), the remeshings so far, the next one's threshold, the time step forced since the
/// last.
struct Stand<'a> {
    owned: Option<&'a Problem>,
    records: &'a [RemeshRecord],
    threshold: f64,
    step_now: Option<f64>,
}

/// Hands the run at `at`, with `solver`'s state, the output `schedule`, the history rows the
/// `recorder` holds and what `watch` holds, to the checkpoint writer; false when it failed.
fn write_checkpoint(
    c: &mut Checkpointing<'_>,
    at: Stand<'_>,
    solver: &ExplicitSolver<'_>,
    schedule: &OutputSchedule,
    recorder: &Recorder,
    watch: &dyn RemeshWatch,
) -> bool {
    let mut watches = WatchMarks::default();
    watch.marks(&mut watches);
    let history = recorder.history.as_ref();
    c.writer.write(RemeshCheckpoint {
        problem: at.owned,
        records: at.records,
        threshold: at.threshold,
        step_now: at.step_now,
        state: solver.restart_state(schedule),
        columns: history.map_or(&[], |h| h.columns()),
        rows: history.map_or(&[], |h| h.rows()),
        watches,
    })
}

/// What a run starts from: the checkpoint `start`'s problem, records, threshold, time step,
/// solver state with its history, and watches' marks; or the beginning.
#[allow(clippy::type_complexity)]
fn unpack(
    start: Option<RemeshStart>,
    policy: &RemeshPolicy,
) -> (
    Option<Problem>,
    Vec<RemeshRecord>,
    f64,
    Option<f64>,
    Option<(RestartState, Vec<String>, Vec<Vec<f64>>)>,
    WatchMarks,
) {
    match start {
        Some(RemeshStart {
            problem,
            records,
            threshold,
            step_now,
            state,
            columns,
            rows,
            watches,
        }) => (
            problem,
            records,
            threshold,
            step_now,
            Some((state, columns, rows)),
            watches,
        ),
        None => (
            None,
            Vec::new(),
            policy.collapse_limit,
            None,
            None,
            WatchMarks::default(),
        ),
    }
}

/// The solver of the next stretch of steps over `problem` with the settings `resumed`: restored
/// from a checkpoint's state `restored` (its history rows written again through `set`, the
/// output schedule restored), going on from a remeshing's or a pause's `state`, or new (the
/// history's columns announced).
#[allow(clippy::type_complexity)]
fn segment_solver<'p>(
    (problem, resumed, output): (&'p Problem, ExplicitSettings, &OutputSettings),
    restored: Option<(RestartState, Vec<String>, Vec<Vec<f64>>)>,
    state: Option<RunState>,
    set: &mut ObserverSet,
    schedule: &mut OutputSchedule,
) -> Result<ExplicitSolver<'p>> {
    match (restored, state) {
        (Some((at, columns, rows)), _) => {
            let (solver, restored_schedule) =
                ExplicitSolver::restored(problem, resumed, output.clone(), at)?;
            if columns != solver.history_columns() {
                return Err(SolverError::InvalidScene {
                    entity: "checkpoint".into(),
                    message: "its history columns differ from this scene's".into(),
                });
            }
            *schedule = restored_schedule;
            set.history_columns(&columns)?;
            for row in &rows {
                set.history_row(row)?;
            }
            Ok(solver)
        }
        (None, Some(s)) => ExplicitSolver::resume(problem, resumed, output.clone(), s),
        (None, None) => {
            let solver = ExplicitSolver::new(problem, resumed, output.clone())?;
            set.history_columns(&solver.history_columns())?;
            Ok(solver)
        }
    }
}

/// Remeshes `region` of `current` at the state `now`, unless a signal came during the last
/// steps (the run stops here rather than after a remeshing that may take seconds) or the
/// remeshings `records` already reach the policy's largest number; on every error the
/// observers of `set` first write what they hold.
fn remesh(
    current: &Problem,
    now: &RunState,
    region: &[usize],
    (policy, settings): (&RemeshPolicy, &ExplicitSettings),
    set: &mut ObserverSet,
    records: &[RemeshRecord],
) -> Result<super::Remeshed> {
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
    remesh_problem(current, now, region, &policy.mesher, critical_step).inspect_err(|_| {
        let _ = set.finish();
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
