//! Running one scene file: the `impact-vv scene` command.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use impact_solver::scene::{build_problem_on_rank, Scene};
use impact_solver::SolverError;

use crate::progress::fraction_bar;
use crate::scene_restart::{run_with_checkpoints, RestartRequest};
use impact_solver::analysis::{execute, log_to_stderr, ExecuteOptions};
use impact_solver::distributed::Communicator;
use impact_solver::dynamics::StopWhen;
use impact_solver::restart::RestartError;
use impact_solver::scene::Analysis;

/// Why a scene run stopped.
#[derive(Debug, thiserror::Error)]
pub enum SceneRunError {
    /// The input is wrong: exit status 2.
    #[error("{0}")]
    Input(SolverError),
    /// The input is fine but the run failed (instability, no convergence): exit status 1.
    #[error("{0}")]
    Run(SolverError),
    /// A signal (SIGINT, SIGTERM) stopped the run, which wrote what it had: exit status 130.
    #[error("{0}")]
    Interrupted(SolverError),
    /// A checkpoint could not be written, or none could be resumed from: exit status 2 (1 when
    /// the disk failed).
    #[error("{0}")]
    Checkpoint(impact_solver::restart::CheckpointError),
}

impl SceneRunError {
    /// The process exit status for the error: 2 input, 1 failed run, 130 interrupted.
    pub fn exit_code(&self) -> u8 {
        match self {
            SceneRunError::Input(_) => 2,
            SceneRunError::Run(_) => 1,
            SceneRunError::Interrupted(_) => 130,
            SceneRunError::Checkpoint(impact_solver::restart::CheckpointError::Io { .. }) => 1,
            SceneRunError::Checkpoint(_) => 2,
        }
    }
}

/// Whether an error is the input's fault (as opposed to a run that went wrong).
pub fn is_input_error(e: &SolverError) -> bool {
    !matches!(
        e,
        SolverError::Unstable(_)
            | SolverError::StaticNotConverged { .. }
            | SolverError::SingularStiffness(_)
            | SolverError::ElementInverted { .. }
            | SolverError::TimeLimit { .. }
            | SolverError::Interrupted { .. }
            | SolverError::Write { .. }
    )
}

impl From<SolverError> for SceneRunError {
    fn from(e: SolverError) -> Self {
        if matches!(e, SolverError::Interrupted { .. }) {
            SceneRunError::Interrupted(e)
        } else if is_input_error(&e) {
            SceneRunError::Input(e)
        } else {
            SceneRunError::Run(e)
        }
    }
}

/// What a finished scene run prints.
pub struct SceneReport {
    /// The lines printed after the run: the plan, the explicit summary (steps, wall time,
    /// energy balance, time per phase) and the static iterations and reactions.
    pub lines: Vec<String>,
    /// Every file the run wrote.
    pub written: Vec<PathBuf>,
}

impl fmt::Display for SceneReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for line in &self.lines {
            writeln!(f, "{line}")?;
        }
        writeln!(f, "written:")?;
        for p in &self.written {
            writeln!(f, "  {}", p.display())?;
        }
        Ok(())
    }
}

/// The explicit run's own end condition, if the analysis has one.
fn explicit_stop(analysis: &Analysis) -> Option<&StopWhen> {
    match analysis {
        Analysis::Explicit(s) | Analysis::Release { explicit: s, .. } => {
            s.settings.stop_when.as_ref()
        }
        Analysis::Static(_) => None,
    }
}

/// An input error found after the scene was read (building its model, checking its analysis)
/// with the scene file's path before the entity it names, as the reader's own errors have it.
fn in_file(path: &Path, e: SolverError) -> SolverError {
    match e {
        SolverError::InvalidScene { entity, message }
            if !entity.starts_with(&*path.to_string_lossy()) =>
        {
            SolverError::InvalidScene {
                entity: format!("{}: {entity}", path.display()),
                message,
            }
        }
        other => other,
    }
}

/// Whether the YAML file at `path` is a catalogue case (top-level `id` and `scene`) rather than a
/// scene: then `impact-vv scene` runs the case's scene as written (its variants and metrics are
/// the catalogue's business, `impact-vv run`).
fn is_case_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| {
            serde_norway::from_str::<serde_norway::Value>(
                impact_solver::scene::without_byte_order_mark(&text),
            )
            .ok()
        })
        .is_some_and(|doc| doc.get("id").is_some() && doc.get("scene").is_some())
}

/// Reads, builds and runs the scene at `path` (a scene file, or a case file's `scene`), writing
/// its output under `out`; `stop` (set by a signal handler) ends an explicit run at the end of the
/// current step. With `ranks` (a run under `mpirun`), this process is one rank of a distributed
/// run: every rank computes the same history, rank 0 writes it and shows the progress.
pub fn run_scene_file(
    path: &Path,
    out: &Path,
    fields: bool,
    stop: Option<Arc<AtomicBool>>,
    ranks: Option<&dyn Communicator>,
) -> Result<SceneReport, SceneRunError> {
    run_scene_file_with(path, out, fields, stop, ranks, &RestartRequest::default())
}

/// [`run_scene_file`] with the checkpoints and resume of `restart`
/// ([`crate::scene_restart`]).
pub fn run_scene_file_with(
    path: &Path,
    out: &Path,
    fields: bool,
    stop: Option<Arc<AtomicBool>>,
    ranks: Option<&dyn Communicator>,
    restart: &RestartRequest,
) -> Result<SceneReport, SceneRunError> {
    let scene = if is_case_file(path) {
        Scene::from_yaml_file_entry(path, "scene")?
    } else {
        Scene::from_yaml_file(path)?
    };
    let mut problem = build_problem_on_rank(&scene, ranks.map(|c| (c.rank(), c.size())))
        .map_err(|e| in_file(path, e))?;
    let bar = fraction_bar(&scene.name);
    if ranks.is_some_and(|c| c.rank() > 0) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let options = ExecuteOptions {
        out: Some(out),
        stem: &scene.name,
        final_state: false,
        fields,
        time_limit_s: None,
        stop,
        ranks,
        // As a scene run always has: each remeshing's summary on stderr, the bar kept whole.
        log: &|line| bar.suspend(|| log_to_stderr(line)),
    };
    let mut progress = |x: f64| bar.set_position((1000.0 * x) as u64);
    let checkpointed =
        run_with_checkpoints(path, &scene, &mut problem, &options, restart, &mut progress);
    let run = match checkpointed {
        Some(result) => {
            bar.finish_and_clear();
            result.map_err(|e| match e {
                RestartError::Run(e) => SceneRunError::from(in_file(path, e)),
                RestartError::Checkpoint(e) => SceneRunError::Checkpoint(e),
            })?
        }
        None => {
            let result = execute(&mut problem, &scene.analysis, &options, &mut progress);
            bar.finish_and_clear();
            result.map_err(|e| in_file(path, e))?
        }
    };
    // Collective: every rank reads its own high-water mark, rank 0 prints them all.
    let memory = crate::memory::peak_resident_mib_per_rank(ranks);
    let mut lines = vec![run.plan.clone(), crate::memory::peak_memory_line(&memory)];
    if let Some(s) = &run.summary {
        lines.push(format!(
            "done: {} steps in {:.2} s wall ({:.0} % in contact); energy balance error at most \
             {:.2e} of the energy scale; mesh-stability flags {}",
            s.steps,
            s.wall_seconds,
            100.0 * s.contact_seconds / s.wall_seconds.max(f64::MIN_POSITIVE),
            s.max_relative_energy_error,
            s.mesh_stability_flags
        ));
        if let (Some(t), Some(stop)) = (s.stopped_when_at, explicit_stop(&scene.analysis)) {
            lines.push(format!(
                "ended at t = {t:.4e} s, the first history row where `{}` reached {}",
                stop.column, stop.level
            ));
        }
        lines.push(format!("time per phase: {}", s.phase_seconds.line()));
        if let Some(share) = run
            .material_history
            .as_ref()
            .and_then(|h| problem.model.fast_update_share(h, s.steps))
        {
            lines.push(format!(
                "microplane elastic path: {:.1} % of the element updates",
                100.0 * share
            ));
        }
    }
    if let Some(s) = &run.static_solution {
        lines.push(format!(
            "static: Newton iterations per load step {:?}",
            s.iterations
        ));
        for (i, c) in problem.constraints.iter().enumerate() {
            let r = s.constraint_reaction(&problem, i);
            lines.push(format!(
                "reaction `{}`: [{:.6e}, {:.6e}, {:.6e}] N",
                c.name, r.x, r.y, r.z
            ));
        }
    }
    Ok(SceneReport {
        lines,
        written: run.written,
    })
}
