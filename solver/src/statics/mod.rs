//! Implicit static analysis: Newton's method with a sparse LU factorisation (`faer`) or, for the
//! symmetric positive definite stiffness of elastic bodies, preconditioned conjugate gradients
//! ([`LinearSolver`]), and load stepping (thesis 3.3.3, (3.64)-(3.68)). Used by patch tests and
//! for elastic references, and, for bodies of materials with a history (microplane concrete), as
//! a path followed increment by increment with step cutting up to its limit point (`path`).

mod conjugate_gradient;
mod inverted;
mod opening_control;
mod path;
mod relaxation;
mod rigid_body;
mod tangent;

pub use opening_control::OpeningControl;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SolverError};
use crate::model::{MaterialHistory, Motion};
use crate::output::HistoryTable;
use crate::problem::Problem;
use tangent::{
    forward_difference_tangents, solve_tangent, solve_tangent_spd, ElementTangent, TangentTerms,
};

/// Settings of a static analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticSettings {
    /// Load steps: prescribed displacements and loads are applied at load factors
    /// `lambda = k / load_steps`, their functions evaluated at time `lambda * end_time`.
    #[serde(default = "default_steps")]
    pub load_steps: usize,
    /// The time (s) of the conditions' functions that load factor 1 stands for: 1 unless set,
    /// so that a scene written for an explicit run (a displacement ramp over seconds) can be
    /// solved statically along the same loading.
    #[serde(default = "default_end_time")]
    pub end_time: f64,
    /// Converged when the out-of-balance force (3.64) on the free components is below
    /// `tolerance` times the largest of the reaction and external force norms; on the loading
    /// path of a material with a history, the largest of them at this or any earlier load step
    /// (a specimen that has softened through is judged on the forces it carried).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// Most Newton iterations per load step (default 25); beyond, the step fails or, for bodies
    /// with a history, is halved (`max_cuts`).
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
    /// Bodies with a history only: how many times a load step that does not converge is halved
    /// before the path stops at its limit point (`path`).
    #[serde(default = "default_cuts")]
    pub max_cuts: u32,
    /// Indirect displacement control: a condition's nodes move together by the displacement
    /// that gives an opening between two probes ([`OpeningControl`]); solved as a path.
    #[serde(default)]
    pub opening_control: Option<OpeningControl>,
    /// How each Newton iteration solves its tangent system: sparse LU unless set.
    #[serde(default)]
    pub linear_solver: LinearSolver,
}

/// The solver of the tangent system `K du = r` of a Newton iteration.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LinearSolver {
    /// Sparse LU (`faer`): any non-singular tangent, symmetric or not (the forward-difference
    /// tangents of a path are not), at the memory of its fill-in (5.8 GB for the 111 k unknowns
    /// of the 25 mm beam).
    #[default]
    Lu,
    /// Conjugate gradients preconditioned by incomplete Cholesky (`conjugate_gradient.rs`) on the
    /// symmetric part of the tangent, for elastic bodies without a history (a path is refused):
    /// memory of the order of the matrix itself. Each solve stops at the relative residual
    /// `tolerance`; Newton's iteration then continues until its own `tolerance` holds, so the
    /// equilibrium found is the one LU finds.
    ConjugateGradient {
        /// Relative residual `|r - K du| / |r|` at which an iteration's solve stops.
        #[serde(default = "default_cg_tolerance")]
        tolerance: f64,
        /// Most iterations of one solve; beyond, the solve fails.
        #[serde(default = "default_cg_iterations")]
        max_iterations: usize,
    },
}

impl LinearSolver {
    /// Conjugate gradients with the default tolerance (1e-10) and iteration limit (20000).
    pub fn conjugate_gradient() -> Self {
        Self::ConjugateGradient {
            tolerance: default_cg_tolerance(),
            max_iterations: default_cg_iterations(),
        }
    }
}

fn default_cg_tolerance() -> f64 {
    1e-10
}
fn default_cg_iterations() -> usize {
    20_000
}

fn default_steps() -> usize {
    1
}
fn default_tolerance() -> f64 {
    1e-12
}
fn default_iterations() -> usize {
    25
}
fn default_end_time() -> f64 {
    1.0
}
fn default_cuts() -> u32 {
    6
}

/// The most load steps a static analysis takes: ten million steps of even a one-element model
/// run for minutes; more is a typo, not a loading.
pub const MAX_LOAD_STEPS: usize = 10_000_000;

impl StaticSettings {
    /// Checks the settings before a solve: `load_steps` in `1..=`[`MAX_LOAD_STEPS`], a
    /// positive finite `end_time`, a `tolerance` in `(0, 1)`.
    pub fn check(&self) -> Result<()> {
        self.validate("static settings (analysis.static or a release's preload)")
    }

    /// [`Self::check`], naming each key under `prefix` (`analysis.static`).
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let invalid = |key: &str, message: String| SolverError::InvalidScene {
            entity: format!("{prefix}.{key}"),
            message,
        };
        if !(1..=MAX_LOAD_STEPS).contains(&self.load_steps) {
            return Err(invalid(
                "load_steps",
                format!(
                    "load_steps = {} is outside 1..={MAX_LOAD_STEPS}; set the number of load \
                     steps between 1 and {MAX_LOAD_STEPS}",
                    self.load_steps
                ),
            ));
        }
        if !(self.end_time.is_finite() && self.end_time > 0.0) {
            return Err(invalid(
                "end_time",
                format!(
                    "end_time = {} must be a positive finite time (s)",
                    self.end_time
                ),
            ));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(invalid(
                "tolerance",
                format!(
                    "tolerance = {} must lie between 0 and 1 (a relative residual)",
                    self.tolerance
                ),
            ));
        }
        Ok(())
    }
}

impl Default for StaticSettings {
    fn default() -> Self {
        Self {
            load_steps: default_steps(),
            end_time: default_end_time(),
            tolerance: default_tolerance(),
            max_iterations: default_iterations(),
            max_cuts: default_cuts(),
            opening_control: None,
            linear_solver: LinearSolver::Lu,
        }
    }
}

/// The equilibrium found, with the convergence record of each load step.
#[derive(Debug, Clone)]
pub struct StaticSolution {
    /// Displacement of every node at equilibrium under the full load (m).
    pub u: Vec<Vector3<f64>>,
    /// Reaction forces at prescribed components (N): the internal minus external force there.
    pub reaction: Vec<Vector3<f64>>,
    /// Newton iterations per load step.
    pub iterations: Vec<usize>,
    /// Final relative residual per load step.
    pub residuals: Vec<f64>,
    /// Under [`LinearSolver::ConjugateGradient`], its iterations per load step, summed over the
    /// step's Newton iterations; empty under LU.
    pub linear_iterations: Vec<usize>,
    /// Bodies with a history: one row per converged load step (load factor as `time`, probes,
    /// reactions of each condition, as an explicit run's history).
    pub history: Option<HistoryTable>,
    /// Bodies with a history: the history committed at the last converged load step.
    pub material_history: Option<MaterialHistory>,
    /// Why the path stopped before the end of the loading, if it did (its limit point).
    pub stopped: Option<String>,
    /// The load step and the time (load factor times the end time) at whose end a signal
    /// stopped the solution ([`solve_static_stoppable`]): the fields above are the state
    /// converged there.
    pub interrupted_at: Option<(usize, f64)>,
}

impl StaticSolution {
    /// Reaction of constraint `c` of `problem`: the components it owns, summed over its nodes.
    pub fn constraint_reaction(&self, problem: &Problem, c: usize) -> Vector3<f64> {
        let owner = problem.constraint_map();
        let mut sum = Vector3::zeros();
        for &n in &problem.constraints[c].nodes {
            for d in 0..3 {
                if owner[n as usize][d] == Some(c as u16) {
                    sum[d] += self.reaction[n as usize][d];
                }
            }
        }
        sum
    }

    /// Sum of the reactions over `nodes`, all prescribed components.
    pub fn total_reaction(&self, nodes: &[u32]) -> Vector3<f64> {
        nodes
            .iter()
            .fold(Vector3::zeros(), |acc, &n| acc + self.reaction[n as usize])
    }
}

/// Solves `f_int(u) = f_ext` with the constraints of `problem` (velocity constraints are not
/// static conditions and are rejected). A model with bodies whose material has a history, or
/// under an [`OpeningControl`], is followed along its loading path by `path::solve_path`.
pub fn solve_static(problem: &Problem, settings: &StaticSettings) -> Result<StaticSolution> {
    solve_static_with_progress(problem, settings, &mut |_| {})
}

/// [`solve_static`], reporting the load factor reached in `[0, 1]`.
pub fn solve_static_with_progress(
    problem: &Problem,
    settings: &StaticSettings,
    progress: &mut dyn FnMut(f64),
) -> Result<StaticSolution> {
    solve_static_until(problem, settings, progress, None)
}

/// [`solve_static_with_progress`] that leaves with [`SolverError::Interrupted`] at the end of
/// the load step during which `stop` becomes true (a signal), whether the problem is followed as
/// a path or not: a linear problem's load steps can be many too.
pub fn solve_static_until(
    problem: &Problem,
    settings: &StaticSettings,
    progress: &mut dyn FnMut(f64),
    stop: Option<&std::sync::atomic::AtomicBool>,
) -> Result<StaticSolution> {
    let solution = solve_static_stoppable(problem, settings, progress, stop)?;
    match solution.interrupted_at {
        Some((step, time)) => Err(SolverError::Interrupted { step, time }),
        None => Ok(solution),
    }
}

/// [`solve_static_until`] that hands back, when `stop` ends it early, the state converged at
/// the end of that load step, with [`StaticSolution::interrupted_at`] set: the caller writes
/// what was computed (the history rows so far, the last state) before it reports the
/// interruption, as an interrupted explicit run does.
pub fn solve_static_stoppable(
    problem: &Problem,
    settings: &StaticSettings,
    progress: &mut dyn FnMut(f64),
    stop: Option<&std::sync::atomic::AtomicBool>,
) -> Result<StaticSolution> {
    settings.check()?;
    let model = &problem.model;
    let (equation, free) = free_equations(problem)?;
    let free_pieces = rigid_body::free_pieces(problem, &problem.constraint_map());
    if model.has_history() || settings.opening_control.is_some() {
        if settings.linear_solver != LinearSolver::Lu {
            return Err(SolverError::InvalidScene {
                entity: "static settings".into(),
                message: "conjugate gradients need a symmetric tangent, and a path's \
                          forward-difference tangents are not symmetric: use `linear_solver: lu`"
                    .into(),
            });
        }
        return path::solve_path(
            problem,
            settings,
            &equation,
            free,
            &free_pieces,
            progress,
            stop,
        );
    }
    let n = model.node_count();
    let constraint_of = problem.constraint_map();
    // No body keeps a history here: this is the empty one the element loops take.
    let history = model.initial_history();
    let mut u = vec![Vector3::zeros(); n];
    let mut f_int = vec![Vector3::zeros(); n];
    let mut f_ext = vec![Vector3::zeros(); n];
    let mut iterations = Vec::new();
    let mut residuals = Vec::new();
    let mut linear_iterations = Vec::new();
    let steps = settings.load_steps;
    let mut interrupted_at = None;
    for step in 1..=steps {
        let time = step as f64 / steps as f64 * settings.end_time;
        prescribe(problem, &constraint_of, time, &mut u);
        if !problem.external_forces(time, &mut f_ext) {
            f_ext.iter_mut().for_each(|f| *f = Vector3::zeros());
        }
        rigid_body::check_loaded(&free_pieces, &f_ext)?;
        let mut converged = None;
        let mut last_residual = f64::INFINITY;
        let mut step_linear_iterations = 0;
        for iteration in 0..=settings.max_iterations {
            if let Some(e) = model.internal_forces(&u, &mut f_int)? {
                return Err(SolverError::ElementInverted {
                    element: e,
                    det: model.deformation_gradient(e, &u).determinant(),
                });
            }
            let (residual, scale) = free_residual(&f_int, &f_ext, &equation, free);
            let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            last_residual = if scale > 0.0 { norm / scale } else { norm };
            if norm <= settings.tolerance * scale || norm == 0.0 {
                converged = Some(iteration);
                break;
            }
            if iteration == settings.max_iterations {
                break;
            }
            let tangents = forward_difference_tangents(problem, &u, &history);
            let (du, taken) =
                linear_step(problem, settings, &u, &equation, free, &residual, &tangents)?;
            step_linear_iterations += taken;
            for i in 0..n {
                for d in 0..3 {
                    if equation[i][d] != usize::MAX {
                        u[i][d] -= du[equation[i][d]];
                    }
                }
            }
        }
        match converged {
            Some(it) => {
                iterations.push(it);
                residuals.push(last_residual);
                if settings.linear_solver != LinearSolver::Lu {
                    linear_iterations.push(step_linear_iterations);
                }
                progress(step as f64 / steps as f64);
                if stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed)) {
                    interrupted_at = Some((step, time));
                    break;
                }
            }
            None => {
                return Err(SolverError::StaticNotConverged {
                    step,
                    steps,
                    iterations: settings.max_iterations,
                    residual: last_residual,
                    tolerance: settings.tolerance,
                })
            }
        }
    }
    let reaction = (0..n)
        .map(|i| {
            let mut r = Vector3::zeros();
            for d in 0..3 {
                if constraint_of[i][d].is_some() {
                    r[d] = f_int[i][d] - f_ext[i][d];
                }
            }
            r
        })
        .collect();
    Ok(StaticSolution {
        u,
        reaction,
        iterations,
        residuals,
        linear_iterations,
        history: None,
        material_history: None,
        stopped: None,
        interrupted_at,
    })
}

/// The residual `f_int - f_ext` at the free components (by equation number) and the force
/// scale of the convergence test: the larger of the reactions' norm and the external forces'.
fn free_residual(
    f_int: &[Vector3<f64>],
    f_ext: &[Vector3<f64>],
    equation: &[[usize; 3]],
    free: usize,
) -> (Vec<f64>, f64) {
    let mut residual = vec![0.0; free];
    let (mut reaction_sq, mut external_sq) = (0.0, 0.0);
    for i in 0..f_int.len() {
        for d in 0..3 {
            let r = f_int[i][d] - f_ext[i][d];
            external_sq += f_ext[i][d] * f_ext[i][d];
            match equation[i][d] {
                usize::MAX => reaction_sq += r * r,
                k => residual[k] = r,
            }
        }
    }
    (residual, reaction_sq.sqrt().max(external_sq.sqrt()))
}

/// The Newton correction for `residual` at `u` with the settings' linear solver, and the
/// conjugate-gradient iterations it took (0 with LU).
fn linear_step(
    problem: &Problem,
    settings: &StaticSettings,
    u: &[Vector3<f64>],
    equation: &[[usize; 3]],
    free: usize,
    residual: &[f64],
    tangents: &[Vec<ElementTangent>],
) -> Result<(Vec<f64>, usize)> {
    Ok(match settings.linear_solver {
        LinearSolver::Lu => (
            solve_tangent(
                problem,
                u,
                equation,
                free,
                residual,
                tangents,
                TangentTerms::default(),
            )?
            .0,
            0,
        ),
        LinearSolver::ConjugateGradient {
            tolerance,
            max_iterations,
        } => solve_tangent_spd(
            problem,
            u,
            equation,
            free,
            residual,
            tangents,
            tolerance,
            max_iterations,
        )?,
    })
}

/// Equation numbers of the free components (consecutive; `usize::MAX` where a condition
/// prescribes the component) and their count. Velocity conditions have no static meaning and are
/// refused.
fn free_equations(problem: &Problem) -> Result<(Vec<[usize; 3]>, usize)> {
    for c in &problem.constraints {
        if matches!(
            c.motion,
            Motion::Velocity(..) | Motion::AffineVelocity { .. }
        ) {
            return Err(SolverError::InvalidScene {
                entity: format!("constraint `{}`", c.name),
                message: "a velocity condition has no meaning in a static analysis; prescribe a \
                          displacement instead"
                    .into(),
            });
        }
    }
    let constraint_of = problem.constraint_map();
    let mut equation = vec![[usize::MAX; 3]; constraint_of.len()];
    let mut free = 0;
    for (i, owner) in constraint_of.iter().enumerate() {
        for d in 0..3 {
            if owner[d].is_none() {
                equation[i][d] = free;
                free += 1;
            }
        }
    }
    Ok((equation, free))
}

/// Sets the prescribed components of `u` to their values at `time`.
fn prescribe(
    problem: &Problem,
    constraint_of: &[[Option<u16>; 3]],
    time: f64,
    u: &mut [Vector3<f64>],
) {
    for (i, owner) in constraint_of.iter().enumerate() {
        for d in 0..3 {
            if let Some(c) = owner[d] {
                let motion = &problem.constraints[c as usize].motion;
                u[i][d] = motion
                    .displacement(&problem.model.reference[i], time)
                    .expect("velocity conditions are refused")[d];
            }
        }
    }
}
