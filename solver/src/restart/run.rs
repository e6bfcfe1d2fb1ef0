//! An explicit run that writes checkpoints as it goes and can start from one: the step loop of
//! [`crate::dynamics::ExplicitSolver::run_with`], paused between two steps whenever a
//! checkpoint falls due (every so many steps or seconds of wall time), the checkpoint written,
//! and the loop resumed. The pause changes nothing in the run: the same steps are taken with the
//! same numbers, so a run with checkpoints is bitwise the run without, and a resumed run
//! bitwise the one that was never stopped.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::error::{CheckpointError, RestartError};
use super::file::{self, Part};
use super::frames::CheckpointFrames;
use super::inputs::Inputs;
use super::payload::{OutputMarks, Payload};
use super::plan::{check_plan, starting_checkpoint, CheckpointPlan};
use super::ranks::{agree, agreed_start, rank_solver, RankPayload, StartingSolver};
use super::remeshing_run::execute_remeshing;
use crate::analysis::{ExecuteOptions, Execution};
use crate::distributed::Communicator;
use crate::dynamics::{
    ExplicitSettings, ExplicitSolver, OutputSchedule, OutputSettings, SegmentEnd,
};
use crate::output::{
    Deadline, HistoryFile, ObserverSet, Progress, Recorder, RunObserver, StopFlag,
};
use crate::problem::Problem;
use crate::remesh::RemeshSettings;
use crate::scene::{Analysis, ExplicitAnalysis};

/// The observers of a run that checkpoints, owned here so that the checkpoint can read what
/// the output holds between two segments.
struct Observers<'p> {
    history: Option<HistoryFile>,
    frames: Option<CheckpointFrames>,
    deadline: Option<Deadline>,
    stop: Option<StopFlag>,
    progress: Progress<'p>,
    recorder: Recorder,
}

impl<'p> Observers<'p> {
    fn set<'a>(&'a mut self) -> ObserverSet<'a, 'p> {
        let mut all: Vec<&'a mut (dyn RunObserver + 'p)> = Vec::new();
        all.extend(self.history.as_mut().map(|o| o as &mut dyn RunObserver));
        all.extend(self.frames.as_mut().map(|o| o as &mut dyn RunObserver));
        all.extend(self.deadline.as_mut().map(|o| o as &mut dyn RunObserver));
        all.extend(self.stop.as_mut().map(|o| o as &mut dyn RunObserver));
        all.push(&mut self.progress);
        all.push(&mut self.recorder);
        ObserverSet::new(all)
    }

    fn marks(&self) -> OutputMarks {
        let (columns, rows) = match &self.recorder.history {
            Some(h) => (h.columns().to_vec(), h.rows().to_vec()),
            None => (Vec::new(), Vec::new()),
        };
        OutputMarks {
            columns,
            rows,
            frames: self
                .frames
                .as_ref()
                .map(|f| f.frames.clone())
                .unwrap_or_default(),
        }
    }
}

/// Whether this run can be checkpointed: an explicit analysis with an output folder, recording
/// no contact problems, on one process or (without remeshing) over several ranks; its
/// settings, and its remeshing's where it remeshes.
#[allow(clippy::type_complexity)]
fn supported<'a>(
    problem: &Problem,
    analysis: &'a Analysis,
    options: &ExecuteOptions,
) -> Result<(&'a ExplicitSettings, Option<&'a RemeshSettings>), CheckpointError> {
    let unsupported = |what: &str| CheckpointError::Unsupported { what: what.into() };
    let (settings, remeshing) = match analysis {
        Analysis::Explicit(ExplicitAnalysis {
            settings,
            remeshing,
        }) => (settings, remeshing.as_ref()),
        Analysis::Static(_) => return Err(unsupported("a static analysis")),
        Analysis::Release { .. } => return Err(unsupported("a static preload and release")),
    };
    if remeshing.is_some() && options.ranks.is_some_and(|c| c.size() > 1) {
        // `execute` refuses it too: a remeshing run is not distributed.
        return Err(unsupported("a remeshing run over several ranks"));
    }
    if options.out.is_none() {
        return Err(unsupported("a run without an output folder"));
    }
    if problem.contact.iter().any(|p| p.record_every.is_some()) {
        return Err(unsupported(
            "a run recording contact problems (`record_problems_every`)",
        ));
    }
    Ok((settings, remeshing))
}

/// What a checkpoint is written with: where, for which inputs, and by which rank.
struct Writing<'a> {
    folder: PathBuf,
    inputs: &'a Inputs,
    comm: Option<&'a dyn Communicator>,
}

impl Writing<'_> {
    fn part(&self) -> Part {
        self.comm.map_or(Part::ALONE, |c| Part {
            rank: c.rank(),
            size: c.size(),
        })
    }

    /// Writes the checkpoint of `solver`'s state now, with the output `marks`: the whole state
    /// on one process, this rank's part in a distributed run (every rank writes at the same
    /// step and all stop if one fails). Returns the path written and the payload's length.
    fn write(
        &self,
        solver: &ExplicitSolver,
        schedule: &OutputSchedule,
        marks: OutputMarks,
    ) -> Result<(PathBuf, usize), RestartError> {
        let payload = Payload {
            state: solver.rank_restart_state(schedule),
            marks,
        };
        let Some(comm) = self.comm else {
            let bytes = payload.encode();
            let path = file::write(&self.folder, solver.step, self.inputs, &bytes)?;
            return Ok((path, bytes.len()));
        };
        let bytes = RankPayload {
            elements: solver.rank_elements().unwrap_or_default(),
            nodes: solver.active_nodes().to_vec(),
            payload,
        }
        .encode();
        let written = file::write_part(&self.folder, solver.step, self.part(), self.inputs, &bytes);
        let what = format!("writing the checkpoint of step {}", solver.step);
        let path = agree(comm, written, &what)?;
        Ok((path, bytes.len()))
    }
}

/// The solver this run starts with, new or restored from the checkpoint `plan` resumes from
/// (on one process, or this rank's part, agreed by all ranks), with its output schedule, the
/// output marks and the plan's line about it.
fn starting_solver<'a>(
    problem: &'a Problem,
    settings: &ExplicitSettings,
    output: OutputSettings,
    folder: &Path,
    plan: &CheckpointPlan,
    options: &ExecuteOptions<'a>,
) -> Result<StartingSolver<'a>, RestartError> {
    match options.ranks.filter(|c| c.size() > 1) {
        None => {
            let start = starting_checkpoint(folder, plan, options)?;
            restored_or_new(problem, settings, output, start)
        }
        Some(comm) => {
            let start = agreed_start(folder, plan, options, comm)?;
            let solver = rank_solver(problem, settings, output, comm, start);
            let (solver, schedule, marks, line) = agree(comm, solver, "restoring their part")?;
            let ranks = crate::analysis::ranks_plan(&solver, problem.model.node_count());
            Ok((solver, schedule, marks, ranks + &line))
        }
    }
}

/// Runs `analysis` on `problem` as [`crate::analysis::execute`] does, writing checkpoints as
/// `plan` says into `<out>/<stem>-checkpoints/` and, with `plan.resume`, starting from the
/// newest good one there. Refusals of damaged checkpoints (an older one is then used) and each
/// checkpoint written go to `options.log`. A run that remeshes ends with `problem` replaced by
/// the problem over its last mesh, as [`crate::analysis::execute`] leaves it. In a distributed
/// run (`options.ranks`) each rank writes its own part (`ranks.rs`).
pub fn execute_checkpointed(
    problem: &mut Problem,
    analysis: &Analysis,
    options: &ExecuteOptions,
    plan: &CheckpointPlan,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, RestartError> {
    let (settings, remeshing) = supported(problem, analysis, options)?;
    if let Some(remeshing) = remeshing {
        return execute_remeshing(problem, settings, remeshing, options, plan, progress);
    }
    check_plan(plan, options)?;
    crate::dynamics::keep_rank_element_data(&mut problem.model, options.ranks);
    let problem = &*problem;
    let out = options.out.unwrap_or(Path::new("."));
    let writing = Writing {
        folder: file::folder(out, options.stem),
        inputs: &plan.inputs,
        comm: options.ranks.filter(|c| c.size() > 1),
    };
    let output = OutputSettings {
        dir: Some(out.to_path_buf()),
        stem: options.stem.to_string(),
        fields: options.fields,
    };
    let (mut solver, mut schedule, marks, mut plan_line) =
        starting_solver(problem, settings, output, &writing.folder, plan, options)?;
    let marks = marks.unwrap_or_default();
    if let Some(s) = plan.every.every_s {
        plan_line += &format!("; a checkpoint every {s} s of wall time");
    }
    if let Some(n) = plan.every.every_steps {
        plan_line += &format!("; a checkpoint every {n} steps");
    }
    let plan_text = solver.plan() + &plan_line;
    let part = writing.part();

    let started = Instant::now();
    let mut observers = Observers {
        history: (part.rank == 0)
            .then(|| HistoryFile::new(out.join(format!("{}_history.csv", options.stem)))),
        frames: match (options.fields, solver.rank_elements()) {
            (false, _) => None,
            (true, None) => Some(CheckpointFrames::new(out, options.stem, &marks.frames)?),
            (true, Some(cells)) => Some(CheckpointFrames::pieces(
                out,
                options.stem,
                (part.rank, part.size),
                cells,
                &marks.frames,
            )?),
        },
        deadline: options.time_limit_s.map(Deadline::after),
        stop: options.stop.clone().map(StopFlag),
        progress: Progress(progress),
        recorder: Recorder::default(),
    };
    let mut written = Vec::new();
    {
        // The history file is rewritten from the checkpoint's rows, which are the rows the
        // stopped run wrote up to its checkpoint, whatever of them reached the disk.
        let mut set = observers.set();
        set.history_columns(&solver.history_columns())?;
        for row in &marks.rows {
            set.history_row(row)?;
        }
    }
    let (mut count, mut seconds) = (0usize, 0.0f64);
    let mut last = Instant::now();
    loop {
        let mut set = observers.set();
        set.written = std::mem::take(&mut written);
        let every = plan.every;
        let since = last;
        let end = solver.run_segment(&mut set, &mut schedule, &mut |s| {
            every.every_steps.is_some_and(|n| s.step % n == 0)
                || every.every_s.is_some_and(|t| {
                    // One rank's clock decides for all: every rank writes the same step.
                    s.on_any_rank(since.elapsed().as_secs_f64() >= t)
                })
        })?;
        if end == SegmentEnd::Finished {
            set.finish()?;
            written = std::mem::take(&mut set.written);
            break;
        }
        written = std::mem::take(&mut set.written);
        drop(set);
        let clock = Instant::now();
        let (path, bytes) = writing.write(&solver, &schedule, observers.marks())?;
        let took = clock.elapsed().as_secs_f64();
        count += 1;
        seconds += took;
        if part.rank == 0 {
            let ranks = if part.size > 1 {
                format!(
                    " (rank 0's part; each of the {} ranks writes its own)",
                    part.size
                )
            } else {
                String::new()
            };
            (options.log)(&format!(
                "checkpoint `{}`: step {}, t = {:.6e} s, {:.1} MB in {took:.3} s{ranks}",
                path.display(),
                solver.step,
                solver.time,
                bytes as f64 / 1e6
            ));
        }
        last = Instant::now();
    }
    if count > 0 && part.rank == 0 {
        (options.log)(&format!(
            "{count} checkpoints written in {seconds:.3} s of the run's {:.3} s of wall time",
            started.elapsed().as_secs_f64()
        ));
    }
    let recorder = std::mem::take(&mut observers.recorder);
    let summary = solver.summary(&schedule, started, recorder, written);
    let (u, v) = crate::analysis::final_state(&mut solver, options);
    Ok(Execution {
        plan: plan_text,
        u,
        v,
        history: Some(summary.history.clone()),
        written: summary.written.clone(),
        summary: Some(summary),
        static_solution: None,
        contact_problems: Vec::new(),
        material_history: Some(solver.take_history()),
        remeshings: Vec::new(),
    })
}

/// The solver and output schedule restored from the checkpoint `start` (with the output marks
/// it stored and a line for the plan), or new ones for a run from the beginning.
fn restored_or_new<'a>(
    problem: &'a Problem,
    settings: &ExplicitSettings,
    output: OutputSettings,
    start: Option<(PathBuf, Vec<u8>)>,
) -> Result<StartingSolver<'a>, RestartError> {
    let Some((path, bytes)) = start else {
        return Ok((
            ExplicitSolver::new(problem, settings.clone(), output)?,
            OutputSchedule::default(),
            None,
            String::new(),
        ));
    };
    let payload = Payload::decode(&bytes).map_err(|e| CheckpointError::Mismatch {
        path: path.clone(),
        detail: format!("its payload does not read back: {}", e.0),
    })?;
    let step = payload.state.step;
    let (solver, schedule) =
        ExplicitSolver::restored(problem, settings.clone(), output, payload.state).map_err(
            |e| CheckpointError::Mismatch {
                path: path.clone(),
                detail: e.to_string(),
            },
        )?;
    if payload.marks.columns != solver.history_columns() {
        return Err(CheckpointError::Mismatch {
            path,
            detail: "its history columns differ from this scene's".into(),
        }
        .into());
    }
    let line = format!("; resumed from `{}` at step {step}", path.display());
    Ok((solver, schedule, Some(payload.marks), line))
}
