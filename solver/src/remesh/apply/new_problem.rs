//! The last steps of a remeshing: the new model ([`new_model`]), the conditions remapped onto it
//! ([`remapped_conditions`]) and the remeshing's record ([`remesh_record`]).

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};

use super::fail;
use super::fields::{Masses, Velocities};
use super::generate::OldBody;
use crate::dynamics::RunState;
use crate::error::Result;
use crate::kinematics::signed_volume;
use crate::material::RemeshedElements;
use crate::mesh::ops::locate::centroids;
use crate::mesh::ops::mesher::RemeshedRegion;
use crate::mesh::Mesh;
use crate::model::{
    BodyMaterial, CarriedState, Constraint, MaterialSource, Model, NodalLoad, Probe,
};
use crate::problem::Problem;
use crate::remesh::contact_surface::SurfaceSeparation;
use crate::remesh::record::{MeshState, RemeshRecord};
use crate::remesh::splice::Splice;

/// The remeshed body's material ([`crate::material::Material::remeshed`]): the same for a model
/// without data per element, rebuilt by the model for the new elements otherwise (microplane
/// concrete: the crack band of each new element's size). An error names the body and the new
/// element.
fn remeshed_material(
    material: &Arc<dyn BodyMaterial>,
    body: &str,
    elements: &RemeshedElements<'_>,
    first_element: usize,
) -> Result<Arc<dyn BodyMaterial>> {
    match material.remeshed_material(elements) {
        Ok(Some(rebuilt)) => Ok(rebuilt),
        Ok(None) => Ok(material.clone()),
        Err((e, message)) => Err(fail(
            &format!("body `{body}` new element {}", first_element + e),
            message,
        )),
    }
}

/// The new model: every body over its current configuration, the remeshed one over its new
/// mesh (node sets in each body's own ids, remapped by `remap`), with the transferred masses,
/// the mass-scaling factors, and the deformation `new_f` and `displacement` carried from before
/// the remeshing.
#[allow(clippy::too_many_arguments)]
pub(super) fn new_model(
    model: &Model,
    old: &OldBody,
    splice: &Splice<'_>,
    remap: &dyn Fn(&[u32]) -> Vec<u32>,
    masses: Masses,
    new_f: Vec<Matrix3<f64>>,
    displacement: Vec<Vector3<f64>>,
) -> Result<Model> {
    let new: &RemeshedRegion = splice.new;
    let b = old.b;
    let mut parts = Vec::with_capacity(model.bodies.len());
    for (i, other) in model.bodies.iter().enumerate() {
        let (mesh_nodes, tets, material) = if i == b {
            let material = remeshed_material(
                &other.material,
                &other.name,
                &RemeshedElements {
                    origin: &new.element_origin,
                    volumes: &masses.new_volumes,
                    // On the final reference, after the surface nodes moved apart, as the volumes.
                    centroids: &centroids(&new.nodes, &new.tets),
                },
                old.elements.start,
            )?;
            (new.nodes.clone(), new.tets.clone(), material)
        } else {
            let local: Vec<[u32; 4]> = model.tets[other.elements.clone()]
                .iter()
                .map(|t| t.map(|n| n - other.nodes.start as u32))
                .collect();
            (
                old.x_all[other.nodes.clone()].to_vec(),
                local,
                other.material.clone(),
            )
        };
        let start = if i == b {
            old.nodes.start
        } else {
            splice.node(other.nodes.start).unwrap_or(0)
        };
        let node_sets = other
            .node_sets
            .iter()
            .map(|(k, v)| {
                let set = remap(v).into_iter().map(|n| n - start as u32).collect();
                (k.clone(), set)
            })
            .collect();
        let mesh = Mesh {
            nodes: mesh_nodes,
            tets,
            node_sets,
        };
        parts.push((other.name.clone(), mesh, MaterialSource::Prepared(material)));
    }
    let mut new_model = Model::new(parts)?;
    new_model.crack_indicator = model.crack_indicator;
    new_model.mass = masses.nodal.into();
    if masses.added_mass > 0.0 {
        let mut scale = vec![1.0; new_model.element_count()];
        scale[new_model.bodies[b].elements.clone()].copy_from_slice(&masses.body_scale);
        new_model.mass_scale = Some(scale);
    }
    new_model.carried = Some(CarriedState::new(new_f, displacement, masses.element_mass)?);
    Ok(new_model)
}

/// The problem's conditions on the new mesh: constraint node sets remapped by `remap` (new
/// nodes on a constrained face join it), loads and probes on their kept nodes only (a probe is
/// a mean over the nodes it was given).
pub(super) fn remapped_conditions(
    problem: &Problem,
    splice: &Splice<'_>,
    remap: &dyn Fn(&[u32]) -> Vec<u32>,
) -> (Vec<Constraint>, Vec<NodalLoad>, Vec<Probe>) {
    let constraints = problem
        .constraints
        .iter()
        .map(|c| Constraint {
            name: c.name.clone(),
            nodes: remap(&c.nodes),
            motion: c.motion.clone(),
        })
        .collect();
    let mut loads = problem.loads.clone();
    loads
        .iter_mut()
        .for_each(|l| l.nodes = splice.kept(&l.nodes));
    let probes = problem
        .probes
        .iter()
        .map(|p| Probe {
            name: p.name.clone(),
            nodes: splice.kept(&p.nodes),
            quantity: p.quantity,
        })
        .collect();
    (constraints, loads, probes)
}

/// The remeshing's record, at the last full step `t_n - dt`, where the state holds both the
/// velocity (`v_full`) and, one increment back, the displacement: kinetic and stored energy of
/// one instant, so that their sum is the run's energy (at `t_n` the velocity is not known
/// yet).
#[allow(clippy::too_many_arguments)]
pub(super) fn remesh_record(
    model: &Model,
    new_model: &Model,
    state: &RunState,
    old: &OldBody,
    region_elements: usize,
    new: &RemeshedRegion,
    velocities: &Velocities,
    du_prev: &[Vector3<f64>],
    separation: SurfaceSeparation,
    added_mass: f64,
) -> RemeshRecord {
    let back = |u: &[Vector3<f64>], du: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
        u.iter().zip(du).map(|(u, du)| u - du).collect()
    };
    let stored_before = model.stored_energy(&back(&state.u, &state.du_prev));
    let zero = vec![Vector3::zeros(); du_prev.len()];
    let stored_after = new_model.stored_energy(&back(&zero, du_prev));
    RemeshRecord {
        time: state.time,
        region_elements,
        before: MeshState::measure(
            &old.x_all,
            &model.tets,
            &model.mass,
            &state.v_full,
            stored_before,
        ),
        after: MeshState::measure(
            &new_model.reference,
            &new_model.tets,
            &new_model.mass,
            &velocities.v_full,
            stored_after,
        ),
        velocity_shift: velocities.shift,
        separation,
        peeled: new.peeled.len(),
        peeled_volume: new
            .peeled
            .iter()
            .map(|(corners, _)| signed_volume(corners).abs())
            .sum(),
        surface_collapses: new.surface_collapses,
        surface_volume_change: new.surface_volume_change,
        added_mass,
        kinetic_restored: velocities.full_deficit - velocities.restored.left,
        fluctuation_scale: velocities.restored.scale,
    }
}
