//! Running a scene's analysis (`Analysis`: explicit dynamics, a static path, or a static
//! preload then release): the one dispatch every caller uses, so a scene runs without the
//! harness. It returns the final state and what was recorded on the way ([`Execution`]).

use std::path::Path;

use crate::contact::problem_file::{ProblemFile, StoredSolution};
use crate::contact::RecordedProblem;
use crate::distributed::Communicator;
use crate::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings, RunSummary, Snapshot};
use crate::model::{ElementFields, MaterialHistory, Model};
use crate::output::{
    field_frame_with_history, Deadline, HistoryTable, Progress, PvdWriter, RunObserver, StopFlag,
};
use crate::problem::Problem;
use crate::remesh::{run_remeshing_watched, RemeshRecord, RemeshSettings};
use crate::scene::{Analysis, ExplicitAnalysis};
use crate::statics::{solve_static_stoppable, solve_static_until, StaticSettings, StaticSolution};
use crate::{SolverError, Vector3};

mod remesh_outputs;
pub use remesh_outputs::RemeshOutputs;

/// The outcome of an analysis: the final state and what was recorded on the way.
pub struct Execution {
    /// One-line description of what ran (analysis, sizes, time step), printed before the run.
    pub plan: String,
    /// Final displacement of every node; empty after an explicit run whose options asked for
    /// no final state ([`ExecuteOptions::final_state`]).
    pub u: Vec<Vector3<f64>>,
    /// Final full-step velocity of every node (explicit runs that return their final state).
    pub v: Option<Vec<Vector3<f64>>>,
    /// The history rows (time, energies, probes, reactions), where the analysis records one.
    pub history: Option<HistoryTable>,
    /// The explicit run's summary (steps, energies, timings); `None` for a static analysis.
    pub summary: Option<RunSummary>,
    /// The static solution: of a static analysis, or the preload of a release.
    pub static_solution: Option<StaticSolution>,
    /// Every file written (history CSV, field frames, collection), in the order written.
    pub written: Vec<std::path::PathBuf>,
    /// Contact problems recorded during the run (pairs with `record_problems_every`).
    pub contact_problems: Vec<RecordedProblem>,
    /// The material histories at the end of an explicit run (microplane bodies): the stresses
    /// of the final state are read from them.
    pub material_history: Option<MaterialHistory>,
    /// Every remeshing of a run that remeshes (`analysis.explicit.remeshing`), in time order;
    /// the problem the caller passed is then the one over the last mesh.
    pub remeshings: Vec<RemeshRecord>,
}

impl Execution {
    /// Stress and strain of every element in the final state, with the stresses of bodies with
    /// a history taken from that history.
    pub fn element_fields(&self, model: &Model) -> ElementFields {
        model.element_fields_with_history(&self.u, self.material_history.as_ref())
    }

    /// Displacement snapshots of an explicit run (`snapshot_interval`), empty otherwise.
    pub fn snapshots(&self) -> &[Snapshot] {
        self.summary
            .as_ref()
            .map_or(&[], |s| s.snapshots.as_slice())
    }
}

/// Options of one execution.
pub struct ExecuteOptions<'a> {
    /// Folder for the output files; `None` keeps everything in memory.
    pub out: Option<&'a Path>,
    /// File stem of the output: `<stem>_history.csv`, `<stem>.pvd`, ...
    pub stem: &'a str,
    /// Whether an explicit run returns the final displacement and velocity of every node
    /// ([`Execution::u`], [`Execution::v`]), which a distributed run gathers whole on every rank
    /// at its end (two vectors of 24 bytes per node of the mesh, beside the rank's own data).
    /// `false` for a caller that reads neither (the scene command): [`Execution::u`] is then
    /// empty and [`Execution::v`] `None`.
    pub final_state: bool,
    /// Write VTU field frames (with `out`).
    pub fields: bool,
    /// Wall-clock limit of an explicit run (s of real time); it stops with
    /// `SolverError::TimeLimit` after writing what it has. `None`: no limit.
    pub time_limit_s: Option<f64>,
    /// Stops an explicit run at the end of the step during which it becomes true (a signal).
    pub stop: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// The ranks of a distributed explicit run (`crate::distributed`), of which this process is
    /// one; only rank 0 writes files. `None` or one rank: the run of one process. A distributed
    /// run without contact leaves each rank with its own elements' connectivity only
    /// ([`crate::dynamics::keeps_own_elements`]; [`crate::dynamics::restore_whole_problem`]
    /// gathers the rest back).
    pub ranks: Option<&'a dyn Communicator>,
    /// Where the run's log lines go (a remeshing's summary), one line per call without its
    /// newline. The caller decides: `impact-vv scene` prints them ([`log_to_stderr`]), the
    /// harness writes them to the case's log file. A sink rather than a global because cases run
    /// side by side on the same threads.
    pub log: &'a (dyn Fn(&str) + Sync),
}

/// A log sink that prints each line to standard error, indented under the run's own lines.
pub fn log_to_stderr(line: &str) {
    eprintln!("  {line}");
}

/// Runs `analysis` on `problem`, reporting progress in `[0, 1]`.
pub fn execute(
    problem: &mut Problem,
    analysis: &Analysis,
    options: &ExecuteOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, SolverError> {
    let distributed = options.ranks.is_some_and(|c| c.size() > 1);
    if distributed && !matches!(analysis, Analysis::Explicit(a) if a.remeshing.is_none()) {
        return Err(SolverError::InvalidScene {
            entity: "analysis".into(),
            message: "only an explicit analysis without remeshing runs over several ranks; run \
                      this scene on one (without mpirun, or without a case variant's `ranks`)"
                .into(),
        });
    }
    if let Some(c) = options
        .ranks
        .filter(|c| c.size() > problem.model.tets.len())
    {
        return Err(SolverError::InvalidScene {
            entity: "ranks".into(),
            message: format!(
                "{} ranks for {} elements: each rank needs at least one element; use at most {}",
                c.size(),
                problem.model.tets.len(),
                problem.model.tets.len()
            ),
        });
    }
    if let Some(limit) = options
        .time_limit_s
        .filter(|t| !(*t > 0.0 && t.is_finite()))
    {
        return Err(SolverError::InvalidScene {
            entity: "time limit".into(),
            message: format!("must be a positive, finite number of seconds, got {limit}"),
        });
    }
    match analysis {
        Analysis::Explicit(ExplicitAnalysis {
            settings,
            remeshing: Some(remeshing),
        }) => explicit_remeshing(problem, settings, remeshing, options, progress),
        // A rank's solver keeps its part of the element data itself, once it has freed what it
        // does not need (`ExplicitSolver::new_rank_keeping_own_elements`).
        Analysis::Explicit(a) => explicit(problem, &a.settings, None, options, progress),
        Analysis::Static(settings) => statics(problem, settings, options, progress),
        Analysis::Release {
            preload,
            explicit: settings,
        } => {
            // The preload stops on a signal as a static analysis does, and reports its load
            // factor as progress; the explicit run then reports its own from 0.
            let loaded = solve_static_until(problem, preload, progress, options.stop.as_deref())?;
            problem.loads.clear();
            let mut run = explicit(
                problem,
                &settings.settings,
                Some(&loaded.u),
                options,
                progress,
            )?;
            run.plan = format!(
                "static preload ({} load steps), then release: {}",
                preload.load_steps, run.plan
            );
            run.static_solution = Some(loaded);
            Ok(run)
        }
    }
}

/// The observers every explicit run of an execution has besides its output files: the
/// wall-time limit, the stop flag and the progress report.
struct Watchers<'p> {
    deadline: Option<Deadline>,
    stop: Option<StopFlag>,
    progress: Progress<'p>,
}

impl<'p> Watchers<'p> {
    fn new(options: &ExecuteOptions, progress: &'p mut dyn FnMut(f64)) -> Self {
        Self {
            deadline: options.time_limit_s.map(Deadline::after),
            stop: options.stop.clone().map(StopFlag),
            progress: Progress(progress),
        }
    }

    /// The output files' observers, then these.
    fn with<'a>(&'a mut self, files: &'a mut [Box<dyn RunObserver>]) -> Vec<&'a mut dyn RunObserver>
    where
        'p: 'a,
    {
        let mut observers: Vec<&mut dyn RunObserver> = files
            .iter_mut()
            .map(|o| &mut **o as &mut dyn RunObserver)
            .collect();
        observers.extend(self.deadline.as_mut().map(|d| d as &mut dyn RunObserver));
        observers.extend(self.stop.as_mut().map(|s| s as &mut dyn RunObserver));
        observers.push(&mut self.progress);
        observers
    }
}

/// An explicit run of `problem`. A distributed run without contact keeps each rank's own
/// elements' connectivity only ([`crate::dynamics::keeps_own_elements`]), and leaves it so: what
/// reads the whole problem afterwards (a case's measures) first gathers it back with
/// [`crate::dynamics::restore_whole_problem`], on every rank whatever the outcome (it is
/// collective).
fn explicit(
    problem: &mut Problem,
    settings: &ExplicitSettings,
    initial_u: Option<&[Vector3<f64>]>,
    options: &ExecuteOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, SolverError> {
    // In a distributed run rank 0 writes the history, every rank its piece of the field frames
    // (`ExplicitSolver::output_observers`).
    let output = OutputSettings {
        dir: options.out.map(Path::to_path_buf),
        stem: options.stem.to_string(),
        fields: options.fields,
    };
    let ranks = options.ranks.filter(|c| c.size() > 1);
    // A rank allocates the material history of its own elements only.
    let mut solver = match ranks {
        Some(comm) => {
            ExplicitSolver::new_rank_keeping_own_elements(problem, settings.clone(), output, comm)?
        }
        None => ExplicitSolver::new(problem, settings.clone(), output)?,
    };
    let problem = solver.problem();
    if let Some(u0) = initial_u {
        solver.set_initial_displacement(u0);
    }
    let mut plan = solver.plan();
    if ranks.is_some() {
        plan += &ranks_plan(&solver, problem.model.node_count());
    }
    let mut files = solver.output_observers()?;
    let mut watchers = Watchers::new(options, progress);
    let mut observers = watchers.with(&mut files);
    let outcome = solver.run_with(&mut observers);
    // Recorded problems are written whether or not the run completed: they are results too.
    let contact_problems = solver.take_recorded_problems();
    let mut written_problems = match options.out {
        // Every rank records the same problems; rank 0 writes them.
        Some(dir) if !contact_problems.is_empty() && solver.rank().0 == 0 => {
            write_contact_problems(dir, options.stem, &contact_problems)?
        }
        _ => Vec::new(),
    };
    let mut summary = outcome?;
    summary.written.append(&mut written_problems);
    let (u, v) = final_state(&mut solver, options);
    Ok(Execution {
        plan,
        u,
        v,
        history: Some(summary.history.clone()),
        written: summary.written.clone(),
        summary: Some(summary),
        static_solution: None,
        contact_problems,
        material_history: Some(solver.take_history()),
        remeshings: Vec::new(),
    })
}

/// The final displacement and velocity of every node, where `options` asks for them
/// ([`ExecuteOptions::final_state`]; collective in a distributed run): empty otherwise.
pub(crate) fn final_state(
    solver: &mut ExplicitSolver,
    options: &ExecuteOptions,
) -> (Vec<Vector3<f64>>, Option<Vec<Vector3<f64>>>) {
    if !options.final_state {
        return (Vec::new(), None);
    }
    let (u, v) = solver.final_nodes();
    (u, Some(v))
}

/// The plan's line on the ranks of a distributed solver: how many, the nodes exchanged and what
/// travels each step.
pub(crate) fn ranks_plan(solver: &ExplicitSolver, node_count: usize) -> String {
    let counts = solver.exchange_counts();
    let shared = solver.shared_nodes();
    // Compact ranges share about a cross-section; a quarter of all nodes means scattered ones.
    let hint = if 4 * shared > node_count {
        ": the ranges are scattered through the mesh, a body's `numbering: spatial` makes \
         them compact"
    } else {
        ""
    };
    format!(
        "; {} ranks (elements in consecutive ranges, each rank integrating their nodes; {} \
         nodes exchanged, {shared} of them shared by two ranks' elements{hint}), each step \
         an all-gather of those nodes' force contributions ({} to {} values of 8 B sent per \
         rank, {:.1} KB in all), one of the energy sums' leaf shares and two all-reduces",
        counts.len(),
        solver.exchanged_nodes(),
        counts.iter().min().unwrap_or(&0),
        counts.iter().max().unwrap_or(&0),
        counts.iter().sum::<usize>() as f64 * 8e-3,
    )
}

/// An explicit run that remeshes as `remeshing` says
/// ([`crate::remesh::run_remeshing_watched`]): the observers of
/// [`explicit`] over the whole run, a line per remeshing to `options.log`, and `problem`
/// replaced by the problem over the last mesh. With an output folder, the records go to
/// `<stem>_remeshing.csv` as the remeshings are made, the scene's `section` pictures to
/// `<stem>_mesh_<k>.json` and its `near_tip` stresses to `<stem>_near_tip.csv`, all of them
/// written whether the run completes, fails or is stopped (module `remesh`, `watch.rs`).
fn explicit_remeshing(
    problem: &mut Problem,
    settings: &ExplicitSettings,
    remeshing: &RemeshSettings,
    options: &ExecuteOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, SolverError> {
    let policy = remeshing.policy(problem)?;
    if let Some(spec) = &remeshing.section {
        spec.check()?;
    }
    if let Some(spec) = &remeshing.near_tip {
        spec.probe_index(problem)?;
    }
    let output = OutputSettings {
        dir: options.out.map(Path::to_path_buf),
        stem: options.stem.to_string(),
        fields: options.fields,
    };
    let probe = ExplicitSolver::new(problem, settings.clone(), output.clone())?;
    let plan = format!(
        "{}; remeshing body `{}` where an element's collapse ratio passes {} (checked every {} \
         steps)",
        probe.plan(),
        remeshing.body,
        policy.collapse_limit,
        policy.check_every
    );
    let mut files = probe.output_observers()?;
    drop(probe);
    let mut outputs = RemeshOutputs::new(problem, remeshing, &policy, options)?;
    let mut watchers = Watchers::new(options, progress);
    let mut observers = watchers.with(&mut files);
    let outcome = run_remeshing_watched(
        problem,
        settings,
        &output,
        &policy,
        &mut observers,
        &mut |record| (options.log)(&record.summary()),
        &mut outputs.watches(),
    );
    // The watches' files are closed (and the last picture taken) whether or not the run
    // completed; the run's own error comes first.
    let end = outcome
        .as_ref()
        .ok()
        .map(|run| (run.problem.as_ref().unwrap_or(problem), &run.state));
    let (written, contact_problems) = outputs.close(end);
    // Recorded problems are written whether or not the run completed: they are results too.
    let written_problems = match options.out {
        Some(dir) if !contact_problems.is_empty() => {
            write_contact_problems(dir, options.stem, &contact_problems)
        }
        _ => Ok(Vec::new()),
    };
    let run = outcome?;
    let mut summary = run.summary;
    summary.written.extend(written?);
    summary.written.extend(written_problems?);
    if let Some(p) = run.problem {
        *problem = p;
    }
    Ok(Execution {
        plan,
        u: run.state.u.clone(),
        v: Some(run.state.v_full.clone()),
        history: Some(summary.history.clone()),
        written: summary.written.clone(),
        summary: Some(summary),
        static_solution: None,
        contact_problems,
        material_history: Some(run.state.history),
        remeshings: run.records,
    })
}

fn statics(
    problem: &Problem,
    settings: &StaticSettings,
    options: &ExecuteOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<Execution, SolverError> {
    let path = if problem.model.has_history() {
        format!(
            " from the committed history (forward-difference tangent of microplane elements), \
             steps halved up to {} times, stopping at the limit point",
            settings.max_cuts
        )
    } else {
        String::new()
    };
    let plan = format!(
        "static analysis: {} nodes, {} elements, {} load steps, Newton with sparse LU{path}",
        problem.model.node_count(),
        problem.model.element_count(),
        settings.load_steps
    );
    // A signal ends the path at a converged step: what was computed is written below, and
    // then the interruption is reported.
    let solution = solve_static_stoppable(problem, settings, progress, options.stop.as_deref())?;
    let plan = match &solution.stopped {
        Some(reason) => format!("{plan}; stopped: {reason}"),
        None => plan,
    };
    let mut written = Vec::new();
    if let (Some(dir), Some(history)) = (options.out, &solution.history) {
        // The same file an explicit run writes: one row per converged load step.
        let path = dir.join(format!("{}_history.csv", options.stem));
        history.write_csv(&path)?;
        written.push(path);
    }
    if let (Some(dir), true) = (options.out, options.fields) {
        let mut pvd = PvdWriter::new(dir, options.stem)?;
        let points = problem.model.positions(&solution.u);
        written.push(pvd.write_frame(&field_frame_with_history(
            &problem.model,
            solution.material_history.as_ref(),
            &points,
            &solution.u,
            None,
            1.0,
        ))?);
    }
    if let Some((step, time)) = solution.interrupted_at {
        return Err(SolverError::Interrupted { step, time });
    }
    Ok(Execution {
        plan,
        u: solution.u.clone(),
        v: None,
        history: solution.history.clone(),
        summary: None,
        material_history: solution.material_history.clone(),
        static_solution: Some(solution),
        remeshings: Vec::new(),
        written,
        contact_problems: Vec::new(),
    })
}

/// Writes each recorded contact problem as `contact-problem/1` JSON, with the multipliers the
/// run's solver returned, into `<dir>/<stem>-contact-problems/`.
fn write_contact_problems(
    dir: &Path,
    stem: &str,
    problems: &[RecordedProblem],
) -> Result<Vec<std::path::PathBuf>, SolverError> {
    let folder = dir.join(format!("{stem}-contact-problems"));
    std::fs::create_dir_all(&folder).map_err(|source| SolverError::Write {
        path: folder.clone(),
        source,
    })?;
    problems
        .iter()
        .map(|p| {
            let path = folder.join(format!(
                "step{:07}-{}-pass{}.json",
                p.step,
                p.pair
                    .replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "_"),
                p.pass
            ));
            let solution = StoredSolution {
                solver: p.solver.clone(),
                r: p.r.clone(),
            };
            ProblemFile::from_problem(&p.problem, vec![solution])
                .write(&path)
                .map_err(|message| SolverError::Write {
                    path: path.clone(),
                    source: std::io::Error::other(message),
                })?;
            Ok(path)
        })
        .collect()
}
