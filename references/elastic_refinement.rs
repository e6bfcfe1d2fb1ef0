//! An independent elastic stiffness for a case whose scene is loaded by a prescribed
//! displacement: the same scene solved by the implicit static solver (Newton, sparse LU) on a
//! refined mesh, with every body linear elastic at its initial constants.
//!
//! This checks the explicit, quasi-static run of the case along two independent paths at once: a
//! different integrator (static equilibrium, no inertia) and a finer discretisation (linear
//! tetrahedra are too stiff on coarse meshes, so the refined value lies below the coarse one).

use impact_solver::material::MaterialModel;
use impact_solver::model::TimeFunction;
use impact_solver::scene::{build_problem, Analysis, MaterialSpec, MeshSource, MotionSpec, Scene};
use impact_solver::statics::{solve_static, StaticSettings};
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
pub fn elastic_stiffness(
    scene: &Scene,
    spec: &ElasticStiffnessSpec,
) -> Result<(f64, String), String> {
    let mut elastic = scene.clone();
    elastic.gravity = None;
    elastic.loads.clear();
    elastic.contact.clear();
    elastic.probes.clear();
    for body in &mut elastic.bodies {
        let constants = body
            .material
            .model(&body.name)
            .map_err(|e| e.to_string())?
            .constants();
        body.material = MaterialSpec::LinearElastic(constants);
        body.initial_velocity = None;
    }
    let first = elastic.bodies.first_mut().ok_or("the scene has no body")?;
    let MeshSource::Box(mesh) = &mut first.mesh else {
        return Err(format!(
            "body `{}` is not a box mesh: the elastic refinement reference refines box meshes only",
            first.name
        ));
    };
    mesh.divisions = spec.divisions;
    let condition = elastic
        .boundary_conditions
        .iter_mut()
        .find(|c| c.name.as_deref() == Some(spec.condition.as_str()))
        .ok_or_else(|| format!("the scene has no boundary condition `{}`", spec.condition))?;
    condition.motion = MotionSpec::Displacement {
        components: vec![spec.component],
        value: TimeFunction::Constant(spec.displacement),
    };
    let settings = StaticSettings::default();
    elastic.analysis = Analysis::Static(settings.clone());
    let problem = build_problem(&elastic).map_err(|e| e.to_string())?;
    let index = problem
        .constraints
        .iter()
        .position(|c| c.name == spec.condition)
        .ok_or_else(|| format!("no constraint `{}` in the built problem", spec.condition))?;
    let solution = solve_static(&problem, &settings).map_err(|e| e.to_string())?;
    let axis = spec.component as usize;
    let reaction = solution.constraint_reaction(&problem, index)[axis];
    let microplane = scene
        .bodies
        .iter()
        .any(|b| matches!(b.material.model(&b.name), Ok(MaterialModel::Microplane(_))));
    Ok((
        reaction / spec.displacement,
        format!(
            "implicit static solver, linear elastic{}, {} x {} x {} cells ({} elements): \
             reaction / prescribed displacement of `{}`",
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
    ))
}
