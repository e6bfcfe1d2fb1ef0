//! A remeshing between two steps of an explicit run (thesis 9.2: the analysis pauses, the
//! region is remeshed, the fields are transferred, the analysis goes on): one body of the model
//! remeshed, the others copied.
//!
//! The integrator borrows its [`Problem`], so the remeshing builds a new problem and a new
//! state from the old ones ([`remesh_problem`]) and the run goes on with a new solver over them
//! ([`crate::dynamics::ExplicitSolver::resume`]); [`super::RemeshPolicy`] says when. The new mesh is
//! the new reference configuration (module `remesh`): the new model's reference coordinates are
//! the current ones, its displacements start at zero, and each element carries the deformation
//! gradient `F_0` reached so far ([`crate::model::CarriedState`]).

mod fields;
mod generate;
mod new_problem;

use nalgebra::{Matrix3, Vector3};

use self::fields::{
    carried_displacement, transferred_histories, transferred_masses, transferred_velocities,
    OldMasses, Velocities,
};
use self::generate::{
    boundary_nodes, check_loads, field_sources, generate, partner_locators, OldBody,
};
use self::new_problem::{new_model, remapped_conditions, remesh_record};
use super::contact_surface::separate_new_surface_nodes;
use super::mesh_check::{check_remeshed, RemeshCheck};
use super::record::RemeshRecord;
use super::splice::Splice;
use super::transfer::element_volumes;
use crate::dynamics::RunState;
use crate::error::{Result, SolverError};
use crate::mesh::ops::locate::Locator;
use crate::mesh::ops::mesher::MesherOptions;
use crate::model::Model;
use crate::problem::Problem;

/// The largest factor on a region's velocity fluctuations that gives back the kinetic energy
/// its transfer lost ([`restore_kinetic_energy`]): a bound against a region whose nodes move
/// nearly together, where a small loss would take a large factor. In the nail run the factors
/// stay within 0.94-1.27 (docs/remeshing.md, "The nail case").
const MAX_FLUCTUATION_SCALE: f64 = 2.0;

/// What [`remesh_problem`] returns: the problem and state the run goes on with, the record of
/// the remeshing (energies and momentum before and after) and the mesher's check.
#[derive(Debug)]
pub struct Remeshed {
    /// The problem over the new mesh.
    pub problem: Problem,
    /// The run's state on the new mesh (displacements zero: the new reference is the current
    /// configuration).
    pub state: RunState,
    /// Energies and momentum before and after.
    pub record: RemeshRecord,
    /// The new mesh's validity, volume and quality ([`check_remeshed`]).
    pub check: RemeshCheck,
}

fn fail(entity: &str, message: String) -> SolverError {
    SolverError::Remesh {
        entity: entity.to_string(),
        message,
    }
}

/// The one body that holds every element of `region`; an error for an empty region, one across
/// bodies, or a model with material regions (bodies without nodes of their own, whose elements
/// use a parent's nodes: the splice of one body's mesh does not rebuild them yet).
fn region_body(model: &Model, region: &[usize]) -> Result<usize> {
    if let Some(b) = model.bodies.iter().find(|b| b.nodes.is_empty()) {
        return Err(fail(
            &format!("body `{}`", b.name),
            "is a material region of another body: remeshing does not rebuild regions yet".into(),
        ));
    }
    let Some(&first) = region.first() else {
        return Err(fail("region", "is empty: nothing to remesh".into()));
    };
    if let Some(&e) = region.iter().find(|&&e| e >= model.element_count()) {
        return Err(fail(
            "region",
            format!(
                "names element {e} of a model with {}",
                model.element_count()
            ),
        ));
    }
    let body = model.body_of(first);
    if let Some(&e) = region.iter().find(|&&e| model.body_of(e) != body) {
        return Err(fail(
            "region",
            format!(
                "spans bodies `{}` and `{}` (element {e}): a remeshing refines one body",
                model.bodies[body].name,
                model.bodies[model.body_of(e)].name
            ),
        ));
    }
    Ok(body)
}

/// Remeshes the elements `region` (all of one body) of `problem` at the running state `state`,
/// and transfers the fields (module `remesh` for which field goes through which operator). The
/// other bodies are copied: their nodes, elements, masses and histories unchanged, their
/// current configuration their new reference like the remeshed body's.
///
/// * elements: copied elements keep their deformation gradient `F` (with the carried `F_0`);
///   a new element takes its parent's (the old element holding its centroid), and a new
///   microplane element its parent's history too (T2), its Cauchy stress by T1; `F` becomes
///   the new model's `F_0`. Element masses are copied, or the parent's density times the new
///   volume, scaled so that the remeshed body's mass is kept; the other bodies' nodal masses
///   are copied;
/// * nodes: copied nodes keep their velocities and displacements, new ones take T3 (8.10);
///   each velocity field (`v_{n-1/2}` and `v_n`) of the remeshed body then gets the uniform
///   shift that restores the body's momentum, and the region's nodes the kinetic energy the
///   transfer lost (`restore_kinetic_energy`). The displacement since the original
///   configuration travels as the model's carried displacement (for the prescribed motions);
///   the state's displacement restarts at 0;
/// * conditions: constraint and mesh node sets are remapped (`Splice::node_set`: new nodes on
///   a constrained face join it); probes keep their kept nodes only (a probe is a mean over the
///   nodes it was given); a load on a node of the region is an error (a force per node would
///   change its resultant on a refined face); contact pairs stay (their surfaces are rebuilt
///   from the new boundary when the run resumes);
/// * the energy ledger takes the stored-energy jump into its internal work (which is stored
///   plus dissipated energy) and the total jump into its remeshing term, so its balance holds
///   across the remeshing; the record reports both jumps. Stored energy is counted where the
///   material has a potential (the elastic bodies); a microplane body's stored energy is in the
///   run's internal work, and what the transfer changes of it is not measured.
///
/// The stable time step of the new mesh is computed when the run resumes (the new model's
/// smallest altitudes, in the current configuration). With `critical_step` > 0 (s), the
/// remeshed body's elements whose stable step falls below it get mass on their nodes that
/// brings it up to `critical_step` (selective mass scaling, `transfer/mass_scaling.rs`): in the new
/// model's nodal masses and [`Model::mass_scale`], before the momentum is restored, so the
/// record's energy and momentum jumps include it; 0 scales nothing.
pub fn remesh_problem(
    problem: &Problem,
    state: &RunState,
    region: &[usize],
    options: &MesherOptions,
    critical_step: f64,
) -> Result<Remeshed> {
    let model = &problem.model;
    let b = region_body(model, region)?;
    let body = &model.bodies[b];
    let old = OldBody::at(problem, state, b, region);
    let partners = partner_locators(problem, &old)?;
    let locator = Locator::new(old.x(), &old.local_tets)?;
    let mut new = generate(&old, &partners, &locator, options)?;
    let (on_boundary, candidates) = boundary_nodes(&new);
    let check = check_remeshed(old.x(), &old.local_tets, &old.local_region, &new)?;
    // The masses are those of the mesh as generated: moving a surface node out of a partner
    // changes the volumes a little, not the mass.
    let generated_volumes = element_volumes(&new.nodes, &new.tets);
    let (locations, parents) = field_sources(&old, &locator, &new, options)?;
    let separation = separate_new_surface_nodes(
        model,
        &old.x_all,
        &partners,
        &mut new.nodes,
        &new.tets,
        &candidates,
    );
    check_loads(problem, &old, &new)?;
    let splice = Splice {
        old_nodes: old.nodes.clone(),
        old_elements: old.elements.clone(),
        local_tets: old.local_tets.clone(),
        new: &new,
        locations: &locations,
        old_node_count: model.node_count(),
        old_element_count: model.element_count(),
    };
    let old_masses = OldMasses::of(model, &old, &splice.local_tets);
    // F and the history of a new element are those of its parent (the old element holding its
    // centroid), so a field constant per element, as F and the history are, is carried exactly
    // where the region is refined: the stored energy of a refined element is its parent's.
    // The thesis' T1 (8.9) would smooth F: at a nail's tip, where the strain is concentrated in
    // a few elements, it lost 48 % of the model's stored energy in one remeshing (7.9 of
    // 16.4 J, elastic block). A new element whose nodes the smoothing moved takes its parent's
    // F on its own, slightly different, shape. (F from the nodes' T3 displacements, which is
    // compatible, was tried: a new element spanning old elements of very different F near the
    // tip came out nearly flat in the original configuration, with entries of F up to 60, and
    // the stored energy went from 16 J to 9e4 J.)
    let new_f: Vec<Matrix3<f64>> = splice.elements(&old.old_f, |e| old.local_f()[parents[e]]);
    let masses = transferred_masses(
        model,
        body,
        &old,
        &old_masses,
        &splice,
        &parents,
        &generated_volumes,
        critical_step,
    );
    let histories = transferred_histories(state, &old, &old_masses, &splice, &locations, &parents)?;
    let velocities = transferred_velocities(model, state, &old, &splice, &masses.nodal);
    let du_prev = splice.nodal(&state.du_prev);
    let displacement = carried_displacement(model, state, &splice);
    let remap = |set: &[u32]| splice.node_set(set, &on_boundary);
    let added_mass = masses.added_mass;
    let new_model = new_model(model, &old, &splice, &remap, masses, new_f, displacement)?;
    let (constraints, loads, probes) = remapped_conditions(problem, &splice, &remap);
    let record = remesh_record(
        model,
        &new_model,
        state,
        &old,
        region.len(),
        &new,
        &velocities,
        &du_prev,
        separation,
        added_mass,
    );
    let mut energies = state.energies;
    energies.internal_work += record.stored_jump();
    energies.remesh_work += record.total_energy_jump();
    let Velocities { v_full, v_half, .. } = velocities;
    let new_state = RunState {
        u: vec![Vector3::zeros(); du_prev.len()],
        v_half,
        v_full: v_full.clone(),
        du_prev,
        step: state.step,
        time_step: state.time_step,
        time: state.time,
        energies,
        pending: state.pending,
        history: histories,
        phases: state.phases,
        contact_totals: state.contact_totals,
    };
    let mut new_problem = Problem::new(new_model);
    new_problem.constraints = constraints;
    new_problem.loads = loads;
    new_problem.gravity = problem.gravity;
    new_problem.initial_velocity = v_full.into();
    new_problem.probes = probes;
    new_problem.contact = problem.contact.clone();
    Ok(Remeshed {
        problem: new_problem,
        state: new_state,
        record,
        check,
    })
}

/// The largest principal stretch of `f`: the square root of the largest eigenvalue of
/// `C = F^T F`.
pub fn largest_stretch(f: &Matrix3<f64>) -> f64 {
    (f.transpose() * f)
        .symmetric_eigenvalues()
        .max()
        .max(0.0)
        .sqrt()
}
