//! The fields a remeshing carries to the new mesh: the element masses and nodal masses (with
//! selective mass scaling, [`transferred_masses`]), the material histories
//! ([`transferred_histories`]) and the nodal velocities with the body's momentum and kinetic
//! energy restored ([`transferred_velocities`]).

use nalgebra::Vector3;

use super::generate::OldBody;
use super::MAX_FLUCTUATION_SCALE;
use crate::dynamics::RunState;
use crate::error::Result;
use crate::mesh::ops::locate::Location;
use crate::mesh::ops::mesher::RemeshedRegion;
use crate::model::{light_density_ratio, Body, BodyHistory, MaterialHistory, Model};
use crate::remesh::record::{kinetic_energy, momentum};
use crate::remesh::splice::Splice;
use crate::remesh::transfer::{
    add_scaled_mass, element_volumes, mass_scale_factors, restore_kinetic_energy,
    shape_function_transfer, KineticRestore,
};

/// The masses of the new model ([`transferred_masses`]).
pub(super) struct Masses {
    /// Every element's mass (kg), what it gives its nodes (a quarter each).
    pub element_mass: Vec<f64>,
    /// The new model's nodal masses (kg), the scaled mass included.
    pub nodal: Vec<f64>,
    /// The remeshed body's elements' mass-scaling factors `s_e >= 1`.
    pub body_scale: Vec<f64>,
    /// The mass selective mass scaling added (kg).
    pub added_mass: f64,
    /// The new mesh's element volumes, on its final reference (m^3).
    pub new_volumes: Vec<f64>,
}

/// The old body's element volumes and every old element's mass: what the transfers read.
pub(super) struct OldMasses {
    /// The body's element volumes in the current configuration (m^3).
    pub volumes: Vec<f64>,
    /// Every element's mass in the old model (kg).
    pub element_mass: Vec<f64>,
}

impl OldMasses {
    pub fn of(model: &Model, old: &OldBody, local_tets: &[[u32; 4]]) -> Self {
        Self {
            volumes: element_volumes(old.x(), local_tets),
            element_mass: model.element_masses(),
        }
    }
}

/// Element masses copied, or the parent's current density times the new volume as generated,
/// scaled so that the new elements' mass is exactly that of the old elements they replace (the
/// smoothing changes volumes) and the body's mass is kept; then the nodal masses, with the
/// mass selective mass scaling adds where an element's stable step falls below
/// `critical_step` (`transfer/mass_scaling.rs`).
#[allow(clippy::too_many_arguments)]
pub(super) fn transferred_masses(
    model: &Model,
    body: &Body,
    old: &OldBody,
    old_masses: &OldMasses,
    splice: &Splice<'_>,
    parents: &[usize],
    generated_volumes: &[f64],
    critical_step: f64,
) -> Masses {
    let new = splice.new;
    let (nodes, elements) = (&old.nodes, &old.elements);
    let local_tets = &splice.local_tets;
    let (old_volumes, old_element_mass) = (&old_masses.volumes, &old_masses.element_mass);
    // The current density of the body's elements, mass over current volume.
    let old_rho: Vec<f64> = (0..local_tets.len())
        .map(|e| old_element_mass[elements.start + e] / old_volumes[e])
        .collect();
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
    let element_mass = splice.elements(old_element_mass, |e| {
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
    let mut nodal = Vec::with_capacity(splice.node_count());
    nodal.extend_from_slice(&model.mass[..nodes.start]);
    nodal.extend(body_mass);
    nodal.extend_from_slice(&model.mass[nodes.end..]);
    Masses {
        element_mass,
        nodal,
        body_scale,
        added_mass,
        new_volumes,
    }
}

/// The new model's histories: the other bodies' copied, the remeshed body's built by
/// [`remeshed_history`] with the Cauchy stress of its new elements by T1 (8.9).
pub(super) fn transferred_histories(
    state: &RunState,
    old: &OldBody,
    old_masses: &OldMasses,
    splice: &Splice<'_>,
    locations: &[Location],
    parents: &[usize],
) -> Result<MaterialHistory> {
    let b = old.b;
    let new = splice.new;
    let history = state.history.bodies.get(b).and_then(Option::as_ref);
    // The other bodies' histories are copied; the remeshed body's is built below (not copied
    // first: a microplane body's history is the largest thing a remeshing moves).
    let mut histories = MaterialHistory {
        bodies: (state.history.bodies.iter().enumerate())
            .map(|(i, h)| if i == b { None } else { h.clone() })
            .collect(),
    };
    if let Some(h) = history {
        let cauchy: Vec<f64> = h.cauchy.iter().flatten().copied().collect();
        let cauchy = shape_function_transfer(
            &cauchy,
            6,
            &splice.local_tets,
            &old_masses.volumes,
            old.nodes.len(),
            locations,
            &new.tets,
        )?;
        histories.bodies[b] = Some(remeshed_history(h, &new.element_origin, parents, &cauchy));
    }
    Ok(histories)
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
        first: 0,
        values,
        cauchy: stresses,
    }
}

/// The new model's nodal velocities ([`transferred_velocities`]).
pub(super) struct Velocities {
    /// The full-step velocities `v_n` (m/s).
    pub v_full: Vec<Vector3<f64>>,
    /// The half-step velocities `v_{n-1/2}` (m/s).
    pub v_half: Vec<Vector3<f64>>,
    /// The uniform shift that restored the body's momentum in `v_full` (m/s).
    pub shift: Vector3<f64>,
    /// The kinetic energy `v_full` lost in the transfer (J).
    pub full_deficit: f64,
    /// What [`restore_kinetic_energy`] gave back of it.
    pub restored: KineticRestore,
}

/// Nodal velocities copied, or by T3 (8.10); each field (`v_{n-1/2}` and `v_n`) of the
/// remeshed body then gets the uniform shift that restores the body's momentum, and the
/// region's nodes the kinetic energy the transfer lost, momentum kept (module
/// `kinetic_energy`).
pub(super) fn transferred_velocities(
    model: &Model,
    state: &RunState,
    old: &OldBody,
    splice: &Splice<'_>,
    mass: &[f64],
) -> Velocities {
    let new: &RemeshedRegion = splice.new;
    let nodes = &old.nodes;
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
    // new elements, the new nodes and the kept ones whose masses they changed.
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
        mass,
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
        mass,
        &region_nodes,
        half_deficit,
        MAX_FLUCTUATION_SCALE,
    );
    Velocities {
        v_full,
        v_half,
        shift,
        full_deficit,
        restored,
    }
}

/// The displacement since the original configuration, on the new mesh: the carried one plus
/// the state's, copied or by T3. It travels as the new model's carried displacement (for the
/// prescribed motions); the state's displacement restarts at 0.
pub(super) fn carried_displacement(
    model: &Model,
    state: &RunState,
    splice: &Splice<'_>,
) -> Vec<Vector3<f64>> {
    let old_total: Vec<Vector3<f64>> = match &model.carried {
        Some(c) => c
            .displacement
            .iter()
            .zip(&state.u)
            .map(|(a, b)| a + b)
            .collect(),
        None => state.u.clone(),
    };
    splice.nodal(&old_total)
}
