//! Running one scene file: the `impact-vv scene` command.

use std::fmt;
use std::path::{Path, PathBuf};

use impact_solver::dynamics::{ExplicitSolver, OutputSettings, RunSummary};
use impact_solver::model::field_frame;
use impact_solver::output::PvdWriter;
use impact_solver::scene::{build_problem, Analysis, Scene};
use impact_solver::statics::solve_static;
use impact_solver::SolverError;

use crate::progress::fraction_bar;

/// Why a scene run stopped.
#[derive(Debug, thiserror::Error)]
pub enum SceneRunError {
    /// The input is wrong: exit status 2.
    #[error("{0}")]
    Input(SolverError),
    /// The input is fine but the run failed (instability, no convergence): exit status 1.
    #[error("{0}")]
    Run(SolverError),
}

impl SceneRunError {
    pub fn exit_code(&self) -> u8 {
        match self {
            SceneRunError::Input(_) => 2,
            SceneRunError::Run(_) => 1,
        }
    }
}

impl From<SolverError> for SceneRunError {
    fn from(e: SolverError) -> Self {
        match e {
            SolverError::Unstable(_)
            | SolverError::StaticNotConverged { .. }
            | SolverError::SingularStiffness(_)
            | SolverError::ElementInverted { .. }
            | SolverError::Write { .. } => SceneRunError::Run(e),
            _ => SceneRunError::Input(e),
        }
    }
}

/// What a finished scene run prints.
pub struct SceneReport {
    pub plan: String,
    pub summary: Option<RunSummary>,
    pub written: Vec<PathBuf>,
    pub lines: Vec<String>,
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

/// Reads, builds and runs the scene at `path`, writing its output under `out`.
pub fn run_scene_file(path: &Path, out: &Path, fields: bool) -> Result<SceneReport, SceneRunError> {
    let scene = Scene::from_yaml_file(path)?;
    let problem = build_problem(&scene)?;
    let stem = scene.name.clone();
    let mut lines = Vec::new();
    match &scene.analysis {
        Analysis::Explicit(settings) => {
            let output = OutputSettings { dir: Some(out.to_path_buf()), stem, fields };
            let mut solver = ExplicitSolver::new(&problem, settings.clone(), output)?;
            let plan = solver.plan();
            eprintln!("{plan}");
            let bar = fraction_bar(&scene.name);
            let result = solver.run(&mut |x| bar.set_position((1000.0 * x) as u64));
            bar.finish_and_clear();
            let summary = result?;
            lines.push(format!(
                "done: {} steps in {:.2} s wall; energy balance error at most {:.2e} of the energy scale; \
                 mesh-stability flags {}",
                summary.steps, summary.wall_seconds, summary.max_relative_energy_error, summary.mesh_stability_flags
            ));
            Ok(SceneReport { plan, written: summary.written.clone(), summary: Some(summary), lines })
        }
        Analysis::Static(settings) => {
            let plan = format!(
                "static analysis: {} nodes, {} elements, {} load steps",
                problem.model.node_count(),
                problem.model.element_count(),
                settings.load_steps
            );
            eprintln!("{plan}");
            let solution = solve_static(&problem, settings)?;
            lines.push(format!("converged: Newton iterations per load step {:?}", solution.iterations));
            let mut written = Vec::new();
            if fields {
                let mut pvd = PvdWriter::new(out, &stem)?;
                let points: Vec<_> = problem.model.reference.iter().zip(&solution.u).map(|(x, u)| x + u).collect();
                written.push(pvd.write_frame(&field_frame(&problem.model, &points, &solution.u, None, 1.0))?);
            }
            for (i, c) in problem.constraints.iter().enumerate() {
                let r = solution.constraint_reaction(&problem, i);
                lines.push(format!("reaction `{}`: [{:.6e}, {:.6e}, {:.6e}] N", c.name, r.x, r.y, r.z));
            }
            Ok(SceneReport { plan, summary: None, written, lines })
        }
    }
}
