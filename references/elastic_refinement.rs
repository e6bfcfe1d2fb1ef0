//! An independent elastic stiffness for a case whose scene is loaded by a prescribed
//! displacement: the same scene solved by the implicit static solver (Newton, conjugate gradients
//! preconditioned by incomplete Cholesky) on a refined mesh, with every body linear elastic at
//! its initial constants.
//!
//! Conjugate gradients rather than the sparse LU of the static paths: the stiffness is symmetric
//! positive definite, and LU's fill-in took 5.8 GB on the 25 mm beam (111 k unknowns), where
//! conjugate gradients keep the matrix and one factor of its pattern. Each solve stops at a
//! relative residual of 1e-10 and Newton's iteration goes on to its own 1e-12, so the stiffness
//! is LU's (the test `conjugate_gradients_give_the_lu_stiffness` checks 1e-6 at 50 mm).
//!
//! This checks the explicit, quasi-static run of the case along two independent paths at once: a
//! different integrator (static equilibrium, no inertia) and a finer discretisation (linear
//! tetrahedra are too stiff on coarse meshes, so the refined value lies below the coarse one).

use crate::error::ReferenceError;
use impact_solver::material::MaterialModel;
use impact_solver::model::TimeFunction;
use impact_solver::scene::{build_problem, Analysis, MaterialSpec, MeshSource, MotionSpec, Scene};
use impact_solver::statics::{solve_static, LinearSolver, StaticSettings};
use serde::{Deserialize, Serialize};

/// What the reference solves: the condition named `condition` prescribes `displacement` (m)
/// along `component` (x, y or z); the first body's box mesh gets `divisions`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticStiffnessSpec {
    /// Name of the scene's boundary condition that prescribes the displacement.
    pub condition: String,
    /// The displacement component the condition prescribes and the reaction is read along.
    pub component: impact_solver::scene::Component,
    /// Cells along `x, y, z` of the first body's box mesh.
    pub divisions: [usize; 3],
    /// The prescribed displacement (m).
    pub displacement: f64,
}

/// Reaction of the condition over its prescribed displacement (N/m), and a line saying how it
/// was computed. Gravity and loads are removed: the stiffness is that of the loading alone.
/// Solved by conjugate gradients ([`LinearSolver::conjugate_gradient`]).
pub fn elastic_stiffness(
    scene: &Scene,
    spec: &ElasticStiffnessSpec,
) -> Result<(f64, String), ReferenceError> {
    let solved = solve_elastic(scene, spec, LinearSolver::conjugate_gradient())?;
    Ok((solved.stiffness, solved.description))
}

/// An elastic refinement solved, with what the solve took.
#[derive(Debug, Clone, PartialEq)]
pub struct ElasticSolve {
    /// Reaction of the condition over its prescribed displacement (N/m).
    pub stiffness: f64,
    /// How it was computed, in a line.
    pub description: String,
    /// Elements of the refined mesh.
    pub elements: usize,
    /// Free displacement components (the unknowns).
    pub unknowns: usize,
    /// Newton iterations of the (single) load step.
    pub newton_iterations: usize,
    /// Conjugate-gradient iterations over them (zero under LU).
    pub linear_iterations: usize,
}

/// [`elastic_stiffness`] with the tangent systems solved by `linear_solver`.
pub fn solve_elastic(
    scene: &Scene,
    spec: &ElasticStiffnessSpec,
    linear_solver: LinearSolver,
) -> Result<ElasticSolve, ReferenceError> {
    let mut elastic = scene.clone();
    elastic.gravity = None;
    elastic.loads.clear();
    elastic.contact.clear();
    elastic.probes.clear();
    for body in &mut elastic.bodies {
        let constants = body.material.model(&body.name)?.constants();
        body.material = MaterialSpec::LinearElastic(constants);
        body.initial_velocity = None;
    }
    let first = elastic.bodies.first_mut().ok_or(ReferenceError::NoBody)?;
    let MeshSource::Box(mesh) = &mut first.mesh else {
        return Err(ReferenceError::NotABox {
            body: first.name.clone(),
        });
    };
    mesh.divisions = spec.divisions;
    let condition = elastic
        .boundary_conditions
        .iter_mut()
        .find(|c| c.name.as_deref() == Some(spec.condition.as_str()))
        .ok_or_else(|| ReferenceError::NoCondition {
            condition: spec.condition.clone(),
        })?;
    condition.motion = MotionSpec::Displacement {
        components: vec![spec.component],
        value: TimeFunction::Constant(spec.displacement),
    };
    let settings = StaticSettings {
        linear_solver,
        ..StaticSettings::default()
    };
    elastic.analysis = Analysis::Static(settings.clone());
    let problem = build_problem(&elastic)?;
    let index = problem
        .constraints
        .iter()
        .position(|c| c.name == spec.condition)
        .ok_or_else(|| ReferenceError::NoConstraint {
            condition: spec.condition.clone(),
        })?;
    let solution = solve_static(&problem, &settings)?;
    let axis = spec.component as usize;
    let reaction = solution.constraint_reaction(&problem, index)[axis];
    let microplane = scene
        .bodies
        .iter()
        .any(|b| matches!(b.material.model(&b.name), Ok(MaterialModel::Microplane(_))));
    let unknowns = problem
        .constraint_map()
        .iter()
        .flatten()
        .filter(|owner| owner.is_none())
        .count();
    Ok(ElasticSolve {
        stiffness: reaction / spec.displacement,
        description: format!(
            "implicit static solver ({}), linear elastic{}, {} x {} x {} cells ({} elements): \
             reaction / prescribed displacement of `{}`",
            match linear_solver {
                LinearSolver::Lu => "sparse LU",
                LinearSolver::ConjugateGradient { .. } => "conjugate gradients",
            },
            if microplane {
                " at the microplane model's initial constants"
            } else {
                ""
            },
            spec.divisions[0],
            spec.divisions[1],
            spec.divisions[2],
            problem.model.element_count(),
            spec.condition
        ),
        elements: problem.model.element_count(),
        unknowns,
        newton_iterations: solution.iterations.iter().sum(),
        linear_iterations: solution.linear_iterations.iter().sum(),
    })
}
