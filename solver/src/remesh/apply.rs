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

use nalgebra::{Matrix3, Vector3};

use std::sync::Arc;

use super::contact_surface::separate_new_surface_nodes;
use super::kinetic_energy::restore_kinetic_energy;
use super::locate::{centroid, centroids, Locator};
use super::mass_scaling::{add_scaled_mass, mass_scale_factors};
use super::mesh_check::{check_remeshed, RemeshCheck};
use super::mesher::{remesh_region_keeping_edges, MesherOptions};
use super::record::{kinetic_energy, momentum, MeshState, RemeshRecord};
use super::splice::Splice;
use super::transfer::{element_volumes, shape_function_transfer};
use crate::dynamics::RunState;
use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;
use crate::material::RemeshedElements;
use crate::mesh::{boundary_faces_of, Mesh};
use crate::model::{
    light_density_ratio, BodyHistory, BodyMaterial, CarriedState, Constraint, MaterialHistory,
    MaterialSource, Model, Probe,
};
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
    let body = model.element_body[first] as usize;
    if let Some(&e) = region
        .iter()
        .find(|&&e| model.element_body[e] as usize != body)
    {
        return Err(fail(
            "region",
            format!(
                "spans bodies `{}` and `{}` (element {e}): a remeshing refines one body",
                model.bodies[body].name, model.bodies[model.element_body[e] as usize].name
            ),
        ));
    }
    Ok(body)
}

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

/// The remeshed body's history: kept elements copy theirs; new ones copy the history of their
/// parent (`sources`, the old element holding the new centroid: the thesis' T2 with the parent
/// for the closest Gauss point, which it is wherever the region is refined), so damage does not
/// diffuse, and take the Cauchy stress of the output by T1 (`cauchy`, six per new element).
fn remeshed_history(
    old: &BodyHistory,
    origin: &[Option<u32>],
    sources: &[usize],
    cauchy: &[f64],
) -> BodyHistory {
    let n = old.state_len;
    let mut values = Vec::with_capacity(origin.len() * n);
    let mut stresses = Vec::with_capacity(origin.len());
    for (e, o) in origin.iter().enumerate() {
        let (row, stress) = match o {
            Some(o) => (*o as usize, old.cauchy[*o as usize]),
            None => {
                let mut s = [0.0; 6];
                s.copy_from_slice(&cauchy[6 * e..6 * e + 6]);
                (sources[e], s)
            }
        };
        values.extend_from_slice(&old.values[row * n..(row + 1) * n]);
        stresses.push(stress);
    }
    BodyHistory {
        state_len: n,
        values,
        cauchy: stresses,
    }
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
/// brings it up to `critical_step` (selective mass scaling, `mass_scaling.rs`): in the new
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
    let (nodes, elements) = (body.nodes.clone(), body.elements.clone());
    let x_all: Vec<Vector3<f64>> = model
        .reference
        .iter()
        .zip(&state.u)
        .map(|(x, u)| x + u)
        .collect();
    let x = &x_all[nodes.clone()];
    let local_tets: Vec<[u32; 4]> = model.tets[elements.clone()]
        .iter()
        .map(|t| t.map(|n| n - nodes.start as u32))
        .collect();
    let local_region: Vec<usize> = region.iter().map(|e| e - elements.start).collect();
    let partners: Vec<usize> = problem
        .contact
        .iter()
        .filter_map(|pair| match pair.bodies {
            [p, q] if p == b => Some(q),
            [p, q] if q == b => Some(p),
            _ => None,
        })
        .collect();
    // An edge whose midpoint lies inside a partner is not split: its new node would have to be
    // moved out, by the chord's sagitta, and can invert the element behind it.
    let partners = partners
        .into_iter()
        .map(|o| {
            let tets = &model.tets[model.bodies[o].elements.clone()];
            Ok((o, Locator::new(&x_all, tets)?))
        })
        .collect::<Result<Vec<_>>>()?;
    let inside_partner = |a: u32, c: u32| {
        let mid = 0.5 * (x[a as usize] + x[c as usize]);
        partners.iter().any(|(_, l)| l.holds_strictly(&mid))
    };
    let locator = Locator::new(x, &local_tets)?;
    // Element fields: F since the stress-free configuration (carried below), and the current
    // density.
    let old_f: Vec<Matrix3<f64>> = (0..model.element_count())
        .map(|e| model.deformation_gradient(e, &state.u))
        .collect();
    let local_f = &old_f[elements.clone()];
    // Failed material (`MesherOptions::erode_stretch`): the old elements whose carried
    // deformation stretches past the limit; a region element lying in one is eroded.
    let torn: Vec<bool> = if options.erode && options.erode_stretch > 0.0 {
        local_f
            .iter()
            .map(|f| largest_stretch(f) > options.erode_stretch)
            .collect()
    } else {
        Vec::new()
    };
    let failed = |corners: &[Vector3<f64>; 4]| {
        !torn.is_empty() && torn[locator.locate(&centroid(corners)).element]
    };
    let mut new = remesh_region_keeping_edges(
        x,
        &local_tets,
        &local_region,
        options,
        &inside_partner,
        &failed,
    )?;
    let mut on_boundary = vec![false; new.nodes.len()];
    for f in boundary_faces_of(&new.tets) {
        for n in f.nodes {
            on_boundary[n as usize] = true;
        }
    }
    let candidates: Vec<u32> = new
        .new_nodes()
        .into_iter()
        .filter(|&n| on_boundary[n as usize])
        .collect();
    let check = check_remeshed(x, &local_tets, &local_region, &new)?;
    // The masses are those of the mesh as generated: moving a surface node out of a partner
    // changes the volumes a little, not the mass.
    let generated_volumes = element_volumes(&new.nodes, &new.tets);
    // Fields are located at the nodes as generated (a moved node takes the values of where it
    // was generated, on the old surface).
    let size = x
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.amax()))
        .max(f64::MIN_POSITIVE);
    // The remesher may move a curved part of the surface by up to `surface_deviation`, outward
    // too (a node sliding on the old surface bends the faces around it off it), and an inner
    // node smoothed next to it may follow: such a node lies that far outside the old mesh at
    // most, and takes the fields of the nearest old element, extrapolated over that distance
    // (1.2 um in the nail run at 63 us, where this stopped the run).
    let outside = (1e-9 * size).max(options.surface_deviation);
    let locations = locator.locate_remeshed_nodes(&local_tets, &new, outside)?;
    // The old element each new one lies in (its centroid's): the parent of a refined element.
    // A copied element is its own parent (its centroid lies in it); only new ones are searched.
    let parents: Vec<usize> = centroids(&new.nodes, &new.tets)
        .iter()
        .zip(&new.element_origin)
        .map(|(c, origin)| match origin {
            Some(o) => *o as usize,
            None => locator.locate(c).element,
        })
        .collect();
    let separation = separate_new_surface_nodes(
        model,
        &x_all,
        &partners,
        &mut new.nodes,
        &new.tets,
        &candidates,
    );
    for load in &problem.loads {
        if let Some(n) = load.nodes.iter().find(|&&n| {
            nodes.contains(&(n as usize)) && new.kept_nodes[n as usize - nodes.start].is_none()
        }) {
            return Err(fail(
                &format!("load `{}`", load.name),
                format!("acts on node {n}, which the remeshing replaces"),
            ));
        }
    }
    let splice = Splice {
        old_nodes: nodes.clone(),
        old_elements: elements.clone(),
        local_tets,
        new: &new,
        locations: &locations,
        old_node_count: model.node_count(),
        old_element_count: model.element_count(),
    };
    let local_tets = &splice.local_tets;

    // Element masses: what each element gives its nodes (a quarter each), kept exactly.
    let old_element_mass = model.element_masses();
    let old_volumes = element_volumes(x, local_tets);
    let t1 = |values: &[f64], width: usize| {
        shape_function_transfer(
            values,
            width,
            local_tets,
            &old_volumes,
            nodes.len(),
            &locations,
            &new.tets,
        )
    };
    // The current density of the body's elements, mass over current volume.
    let old_rho: Vec<f64> = (0..local_tets.len())
        .map(|e| old_element_mass[elements.start + e] / old_volumes[e])
        .collect();
    let history = state.history.bodies.get(b).and_then(Option::as_ref);
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
    let new_f: Vec<Matrix3<f64>> = splice.elements(&old_f, |e| local_f[parents[e]]);
    // Densities likewise; then scaled so that the new elements' mass is exactly that of the
    // old elements they replace (the smoothing changes volumes), and the body's mass is kept.
    let mut copied = vec![false; local_tets.len()];
    for o in new.element_origin.iter().flatten() {
        copied[*o as usize] = true;
    }
    let replaced_mass: f64 = (0..local_tets.len())
        .filter(|&e| !copied[e])
        .map(|e| old_element_mass[elements.start + e])
        .sum();
    let new_mass: f64 = (0..new.tets.len())
        .filter(|&e| new.element_origin[e].is_none())
        .map(|e| old_rho[parents[e]] * generated_volumes[e])
        .sum();
    let density_scale = if new_mass > 0.0 {
        replaced_mass / new_mass
    } else {
        1.0
    };
    let element_mass = splice.elements(&old_element_mass, |e| {
        old_rho[parents[e]] * density_scale * generated_volumes[e]
    });
    let new_volumes = element_volumes(&new.nodes, &new.tets);
    let mut body_mass = vec![0.0; new.nodes.len()];
    for (tet, m) in new.tets.iter().zip(&element_mass[splice.new_elements()]) {
        for &n in tet {
            body_mass[n as usize] += 0.25 * m;
        }
    }
    let rho_0 = body.material.constants().density;
    let lightness: Vec<f64> = (element_mass[splice.new_elements()].iter())
        .zip(&new_volumes)
        .map(|(&m, &v)| light_density_ratio(m, rho_0, v))
        .collect();
    let body_scale = mass_scale_factors(
        &new.nodes,
        &new.tets,
        &lightness,
        body.material.constants().dilatational_wave_speed(),
        critical_step,
    );
    let added_mass = add_scaled_mass(
        &mut body_mass,
        &new.tets,
        &element_mass[splice.new_elements()],
        &body_scale,
    );
    let mut mass = Vec::with_capacity(splice.node_count());
    mass.extend_from_slice(&model.mass[..nodes.start]);
    mass.extend(body_mass);
    mass.extend_from_slice(&model.mass[nodes.end..]);
    // The other bodies' histories are copied; the remeshed body's is built below (not copied
    // first: a microplane body's history is the largest thing a remeshing moves).
    let mut histories = MaterialHistory {
        bodies: (state.history.bodies.iter().enumerate())
            .map(|(i, h)| if i == b { None } else { h.clone() })
            .collect(),
    };
    if let Some(h) = history {
        let cauchy: Vec<f64> = h.cauchy.iter().flatten().copied().collect();
        let cauchy = t1(&cauchy, 6)?;
        histories.bodies[b] = Some(remeshed_history(h, &new.element_origin, &parents, &cauchy));
    }

    // Nodal fields: copied, or T3 and the body's momentum restored.
    let body_range = splice.new_nodes();
    let restore = |v: &mut Vec<Vector3<f64>>, old: &[Vector3<f64>]| -> Vector3<f64> {
        let old_p = momentum(&model.mass[nodes.clone()], &old[nodes.clone()]);
        let new_p = momentum(&mass[body_range.clone()], &v[body_range.clone()]);
        let total: f64 = mass[body_range.clone()].iter().sum();
        let shift = (old_p - new_p) / total;
        v[body_range.clone()].iter_mut().for_each(|v| *v += shift);
        shift
    };
    let mut v_full = splice.nodal(&state.v_full);
    let shift = restore(&mut v_full, &state.v_full);
    // The kinetic energy the transfer lost (T3 averages) goes back to the nodes of the region's
    // new elements, the new nodes and the kept ones whose masses they changed, momentum kept
    // (module `kinetic_energy`).
    let mut in_region = vec![false; new.nodes.len()];
    for (tet, origin) in new.tets.iter().zip(&new.element_origin) {
        if origin.is_none() {
            tet.iter().for_each(|&n| in_region[n as usize] = true);
        }
    }
    let region_nodes: Vec<usize> = (0..new.nodes.len())
        .filter(|&n| in_region[n])
        .map(|n| body_range.start + n)
        .collect();
    let body_kinetic_deficit = |old: &[Vector3<f64>], new_v: &[Vector3<f64>]| {
        kinetic_energy(&model.mass[nodes.clone()], &old[nodes.clone()])
            - kinetic_energy(&mass[body_range.clone()], &new_v[body_range.clone()])
    };
    let full_deficit = body_kinetic_deficit(&state.v_full, &v_full);
    let restored = restore_kinetic_energy(
        &mut v_full,
        &mass,
        &region_nodes,
        full_deficit,
        MAX_FLUCTUATION_SCALE,
    );
    let mut v_half = splice.nodal(&state.v_half);
    restore(&mut v_half, &state.v_half);
    // The half-step velocities the run goes on with, likewise.
    let half_deficit = body_kinetic_deficit(&state.v_half, &v_half);
    restore_kinetic_energy(
        &mut v_half,
        &mass,
        &region_nodes,
        half_deficit,
        MAX_FLUCTUATION_SCALE,
    );
    let du_prev = splice.nodal(&state.du_prev);
    let old_total: Vec<Vector3<f64>> = match &model.carried {
        Some(c) => c
            .displacement
            .iter()
            .zip(&state.u)
            .map(|(a, b)| a + b)
            .collect(),
        None => state.u.clone(),
    };
    let displacement = splice.nodal(&old_total);

    // The new model: every body over its current configuration, the remeshed one over its new
    // mesh; node sets in each body's own ids.
    let remap = |set: &[u32]| splice.node_set(set, &on_boundary);
    let mut parts = Vec::with_capacity(model.bodies.len());
    for (i, other) in model.bodies.iter().enumerate() {
        let (mesh_nodes, tets, material) = if i == b {
            let material = remeshed_material(
                &other.material,
                &other.name,
                &RemeshedElements {
                    origin: &new.element_origin,
                    volumes: &new_volumes,
                    // On the final reference, after the surface nodes moved apart, as the volumes.
                    centroids: &centroids(&new.nodes, &new.tets),
                },
                elements.start,
            )?;
            (new.nodes.clone(), new.tets.clone(), material)
        } else {
            let local: Vec<[u32; 4]> = model.tets[other.elements.clone()]
                .iter()
                .map(|t| t.map(|n| n - other.nodes.start as u32))
                .collect();
            (
                x_all[other.nodes.clone()].to_vec(),
                local,
                other.material.clone(),
            )
        };
        let start = if i == b {
            nodes.start
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
    new_model.mass = mass;
    if added_mass > 0.0 {
        let mut scale = vec![1.0; new_model.element_count()];
        scale[new_model.bodies[b].elements.clone()].copy_from_slice(&body_scale);
        new_model.mass_scale = Some(scale);
    }
    new_model.carried = Some(CarriedState::new(new_f, displacement, element_mass)?);
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

    // The record, at the last full step t_n - dt, where the state holds both the velocity
    // (`v_full`) and, one increment back, the displacement: kinetic and stored energy of one
    // instant, so that their sum is the run's energy (at t_n the velocity is not known yet).
    let back = |u: &[Vector3<f64>], du: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
        u.iter().zip(du).map(|(u, du)| u - du).collect()
    };
    let stored_before = model.stored_energy(&back(&state.u, &state.du_prev));
    let zero = vec![Vector3::zeros(); du_prev.len()];
    let stored_after = new_model.stored_energy(&back(&zero, &du_prev));
    let record = RemeshRecord {
        time: state.time,
        region_elements: region.len(),
        before: MeshState::measure(
            &x_all,
            &model.tets,
            &model.mass,
            &state.v_full,
            stored_before,
        ),
        after: MeshState::measure(
            &new_model.reference,
            &new_model.tets,
            &new_model.mass,
            &v_full,
            stored_after,
        ),
        velocity_shift: shift,
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
        kinetic_restored: full_deficit - restored.left,
        fluctuation_scale: restored.scale,
    };
    let mut energies = state.energies;
    energies.internal_work += record.stored_jump();
    energies.remesh_work += record.total_energy_jump();
    let new_state = RunState {
        u: zero,
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
    new_problem.initial_velocity = v_full;
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
