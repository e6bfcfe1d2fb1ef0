//! A remeshing between two steps of an explicit run (thesis 9.2: the analysis pauses, the
//! region is remeshed, the fields are transferred, the analysis goes on), for one-body models of
//! elastic or Saint-Venant-Kirchhoff material.
//!
//! The integrator borrows its [`Problem`], so the remeshing builds a new problem and a new
//! state from the old ones ([`remesh_problem`]) and the run goes on with a new solver over them
//! ([`crate::dynamics::ExplicitSolver::resume`]); [`RemeshPolicy`] says when. The new mesh is
//! the new reference configuration (module `remesh`): the new model's reference coordinates are
//! the current ones, its displacements start at zero, and each element carries the deformation
//! gradient `F_0` reached so far ([`crate::model::CarriedState`]).

use nalgebra::{Matrix3, Vector3};

use super::locate::{Location, Locator};
use super::mesh_check::{check_remeshed, RemeshCheck};
use super::mesher::{remesh_region, MesherOptions, RemeshedRegion};
use super::record::{lumped_masses, momentum, MeshState, RemeshRecord};
use super::transfer::{
    element_volumes, matrices_to_rows, rows_to_matrices, shape_function_transfer,
    transfer_nodal_vectors,
};
use crate::dynamics::RunState;
use crate::error::{Result, SolverError};
use crate::mesh::{boundary_faces_of, Mesh};
use crate::model::{CarriedState, Constraint, MaterialSource, Model, Probe, Problem};

/// When a run remeshes ([`crate::dynamics::ExplicitSolver`] callers check it every
/// `check_every` steps): when the worst collapse ratio `chi` (8.1) passes `collapse_limit`, the
/// distorted elements grown by `layers` layers ([`super::grow_region`]) are remeshed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemeshPolicy {
    /// Steps between two distortion checks.
    pub check_every: usize,
    /// The collapse ratio above which an element is distorted (thesis 8.1: 10).
    pub collapse_limit: f64,
    /// Layers of elements added around the distorted ones, so that their nodes can move.
    pub layers: usize,
    /// The mesher's settings.
    pub mesher: MesherOptions,
}

impl Default for RemeshPolicy {
    fn default() -> Self {
        Self {
            check_every: 100,
            collapse_limit: super::COLLAPSE_RATIO_LIMIT,
            layers: 1,
            mesher: MesherOptions::default(),
        }
    }
}

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

/// T3 of a nodal vector field, then the kept nodes' old values copied bit for bit.
fn nodal_field(
    old: &[Vector3<f64>],
    old_tets: &[[u32; 4]],
    locations: &[Location],
    new: &RemeshedRegion,
) -> Vec<Vector3<f64>> {
    let mut out = transfer_nodal_vectors(old, old_tets, locations);
    for (o, k) in new.kept_nodes.iter().enumerate() {
        if let Some(k) = k {
            out[*k as usize] = old[o];
        }
    }
    out
}

/// A nodal velocity field on the new mesh: [`nodal_field`], then the uniform shift
/// `dv = (p_old - p_new) / M_new` that restores the linear momentum (the smallest correction in
/// the kinetic-energy norm, see [`super::transfer_velocities`]; here the kept nodes are copied
/// before the shift, as the brief of the run asks). Returns the field and the shift.
fn velocity_field(
    old: &[Vector3<f64>],
    old_mass: &[f64],
    old_tets: &[[u32; 4]],
    locations: &[Location],
    new: &RemeshedRegion,
    new_mass: &[f64],
) -> (Vec<Vector3<f64>>, Vector3<f64>) {
    let mut v = nodal_field(old, old_tets, locations, new);
    let total: f64 = new_mass.iter().sum();
    let shift = (momentum(old_mass, old) - momentum(new_mass, &v)) / total;
    v.iter_mut().for_each(|v| *v += shift);
    (v, shift)
}

/// The new node ids of a node set: each kept node mapped, and each new node that lies on the
/// new mesh's outer boundary with every old node of its support in the set. The support of a
/// new node is the old nodes with a barycentric weight above 1e-9 in the old element that holds
/// it: a midpoint of an old boundary edge has the edge's two ends, a point inside an old
/// boundary face its three nodes. So a node inserted on a constrained face joins the face's
/// set, and one inside the body or on another face does not. (An edge whose ends are both in
/// the set but which does not lie on the set's faces would wrongly add its midpoint; this
/// cannot happen for a set that is all the nodes of a planar face.)
fn remap_set(
    set: &[u32],
    old_node_count: usize,
    old_tets: &[[u32; 4]],
    locations: &[Location],
    new: &RemeshedRegion,
    on_boundary: &[bool],
) -> Vec<u32> {
    let mut member = vec![false; old_node_count];
    for &n in set {
        member[n as usize] = true;
    }
    let mut out: Vec<u32> = set
        .iter()
        .filter_map(|&n| new.kept_nodes[n as usize])
        .collect();
    for n in new.new_nodes() {
        let l = &locations[n as usize];
        let support = old_tets[l.element]
            .iter()
            .zip(l.barycentric)
            .filter(|(_, w)| *w > 1e-9);
        if on_boundary[n as usize] && support.clone().all(|(&o, _)| member[o as usize]) {
            out.push(n);
        }
    }
    out.sort_unstable();
    out
}

/// Remeshes the elements `region` of the one body of `problem` at the running state `state`,
/// and transfers the fields (module `remesh` for which field goes through which operator):
///
/// * elements: kept elements copy their deformation gradient `F` (with the carried `F_0`), new
///   ones take T1 (8.9) of it, which becomes their `F_0`; the current density `rho_0 / det F`
///   goes alike, and the lumped masses are that density times the new (current) volumes;
/// * nodes: kept nodes copy their velocities and displacements, new ones take T3 (8.10);
///   each velocity field (`v_{n-1/2}` and `v_n`) then gets the uniform shift that restores its
///   momentum. The displacement since the original configuration travels as the model's
///   carried displacement (for the prescribed motions); the state's displacement restarts at 0;
/// * conditions: constraint and mesh node sets are remapped ([`remap_set`]: new nodes on a
///   constrained face join it); probes keep their kept nodes only (a probe is a mean over the
///   nodes it was given); a load on a node of the region is an error (a force per node would
///   change its resultant on a refined face), as are contact pairs and materials with history;
/// * the energy ledger takes the stored-energy jump into its internal work (which is stored
///   plus dissipated energy) and the total jump into its remeshing term, so its balance holds
///   across the remeshing; the record reports both jumps.
///
/// The stable time step of the new mesh is computed when the run resumes (the new model's
/// smallest altitudes, in the current configuration).
pub fn remesh_problem(
    problem: &Problem,
    state: &RunState,
    region: &[usize],
    options: &MesherOptions,
) -> Result<Remeshed> {
    let model = &problem.model;
    if model.bodies.len() != 1 {
        return Err(fail(
            "model",
            format!(
                "has {} bodies: remeshing runs on one-body models so far",
                model.bodies.len()
            ),
        ));
    }
    let body = &model.bodies[0];
    if body.material.history_len() > 0 {
        return Err(fail(
            &format!("body `{}`", body.name),
            "its material has a history: the transfer T2 is not wired into the run yet".into(),
        ));
    }
    if !problem.contact.is_empty() {
        return Err(fail(
            "problem",
            "has contact pairs: their surfaces are not rebuilt yet".into(),
        ));
    }
    let old_tets = &model.tets;
    let n_old = model.node_count();
    let x: Vec<Vector3<f64>> = model
        .reference
        .iter()
        .zip(&state.u)
        .map(|(x, u)| x + u)
        .collect();
    let new = remesh_region(&x, old_tets, region, options)?;
    let check = check_remeshed(&x, old_tets, region, &new)?;
    let mut in_region_node = vec![false; n_old];
    for (o, k) in new.kept_nodes.iter().enumerate() {
        in_region_node[o] = k.is_none();
    }
    for load in &problem.loads {
        if let Some(n) = load.nodes.iter().find(|&&n| in_region_node[n as usize]) {
            return Err(fail(
                &format!("load `{}`", load.name),
                format!("acts on node {n}, which the remeshing replaces"),
            ));
        }
    }
    let size = x
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.amax()))
        .max(f64::MIN_POSITIVE);
    let locations = Locator::new(&x, old_tets)?.locate_all(&new.nodes, 1e-9 * size)?;

    // Element fields: F since the stress-free configuration, and the current density.
    let old_f: Vec<Matrix3<f64>> = (0..old_tets.len())
        .map(|e| model.deformation_gradient(e, &state.u))
        .collect();
    let rho0 = body.material.constants().density;
    let old_rho: Vec<f64> = old_f.iter().map(|f| rho0 / f.determinant()).collect();
    let old_volumes = element_volumes(&x, old_tets);
    let t1_f = rows_to_matrices(&shape_function_transfer(
        &matrices_to_rows(&old_f),
        9,
        old_tets,
        &old_volumes,
        n_old,
        &locations,
        &new.tets,
    )?);
    let t1_rho = shape_function_transfer(
        &old_rho,
        1,
        old_tets,
        &old_volumes,
        n_old,
        &locations,
        &new.tets,
    )?;
    let mut f0 = Vec::with_capacity(new.tets.len());
    let mut rho = Vec::with_capacity(new.tets.len());
    for (e, origin) in new.element_origin.iter().enumerate() {
        let (f, r) = match origin {
            Some(o) => (old_f[*o as usize], old_rho[*o as usize]),
            None => (t1_f[e], t1_rho[e]),
        };
        if !(f.determinant() > 0.0) {
            return Err(fail(
                &format!("new element {e}"),
                format!("carried det F_0 = {:e} is not positive", f.determinant()),
            ));
        }
        f0.push(f);
        rho.push(r);
    }
    let new_volumes = element_volumes(&new.nodes, &new.tets);
    let new_mass = lumped_masses(&new.tets, &new_volumes, &rho, new.nodes.len());

    // Nodal fields.
    let (v_full, shift) = velocity_field(
        &state.v_full,
        &model.mass,
        old_tets,
        &locations,
        &new,
        &new_mass,
    );
    let (v_half, _) = velocity_field(
        &state.v_half,
        &model.mass,
        old_tets,
        &locations,
        &new,
        &new_mass,
    );
    let du_prev = nodal_field(&state.du_prev, old_tets, &locations, &new);
    let old_total: Vec<Vector3<f64>> = match &model.carried {
        Some(c) => c
            .displacement
            .iter()
            .zip(&state.u)
            .map(|(a, b)| a + b)
            .collect(),
        None => state.u.clone(),
    };
    let displacement = nodal_field(&old_total, old_tets, &locations, &new);

    // Conditions and node sets.
    let mut on_boundary = vec![false; new.nodes.len()];
    for f in boundary_faces_of(&new.tets) {
        for n in f.nodes {
            on_boundary[n as usize] = true;
        }
    }
    let remap = |set: &[u32]| remap_set(set, n_old, old_tets, &locations, &new, &on_boundary);
    let node_sets = body
        .node_sets
        .iter()
        .map(|(k, v)| (k.clone(), remap(v)))
        .collect();
    let mesh = Mesh {
        nodes: new.nodes.clone(),
        tets: new.tets.clone(),
        node_sets,
    };
    let source = MaterialSource::Prepared(body.material.clone());
    let mut new_model = Model::new(vec![(body.name.clone(), mesh, source)])?;
    new_model.crack_indicator = model.crack_indicator;
    new_model.mass = new_mass;
    new_model.carried = Some(CarriedState::new(f0, displacement)?);
    let keep = |nodes: &[u32]| -> Vec<u32> {
        nodes
            .iter()
            .filter_map(|&n| new.kept_nodes[n as usize])
            .collect()
    };
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
    loads.iter_mut().for_each(|l| l.nodes = keep(&l.nodes));
    let probes = problem
        .probes
        .iter()
        .map(|p| Probe {
            name: p.name.clone(),
            nodes: keep(&p.nodes),
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
    let stored_after =
        new_model.stored_energy(&back(&vec![Vector3::zeros(); du_prev.len()], &du_prev));
    let record = RemeshRecord {
        time: state.time,
        before: MeshState::measure(&x, old_tets, &model.mass, &state.v_full, stored_before),
        after: MeshState::measure(
            &new.nodes,
            &new.tets,
            &new_model.mass,
            &v_full,
            stored_after,
        ),
        velocity_shift: shift,
    };
    let mut energies = state.energies;
    energies.internal_work += record.stored_jump();
    energies.remesh_work += record.total_energy_jump();
    let new_state = RunState {
        u: vec![Vector3::zeros(); new.nodes.len()],
        v_half,
        v_full: v_full.clone(),
        du_prev,
        step: state.step,
        time_step: state.time_step,
        time: state.time,
        energies,
        pending: state.pending,
    };
    let mut new_problem = Problem::new(new_model);
    new_problem.constraints = constraints;
    new_problem.loads = loads;
    new_problem.gravity = problem.gravity;
    new_problem.initial_velocity = v_full;
    new_problem.probes = probes;
    Ok(Remeshed {
        problem: new_problem,
        state: new_state,
        record,
        check,
    })
}

/// Runs `steps` steps of `problem` from its start with a remeshing whenever `policy` asks
/// (every `check_every` steps, [`super::check_distortion`] over the current coordinates; the
/// region is the elements above the limit grown by `policy.layers`), each step a plain
/// [`crate::dynamics::ExplicitSolver::step`]. Returns the problem and state the run ended with
/// and the record of each remeshing. The solver is rebuilt after each remeshing (it borrows its
/// problem): [`crate::dynamics::ExplicitSolver::resume`] over the new problem.
pub fn run_with_remeshing(
    mut problem: Problem,
    settings: crate::dynamics::ExplicitSettings,
    steps: usize,
    policy: &RemeshPolicy,
) -> Result<(Problem, RunState, Vec<RemeshRecord>)> {
    use crate::dynamics::{ExplicitSolver, OutputSettings};
    let mut records = Vec::new();
    let mut state: Option<RunState> = None;
    loop {
        let (now, region) = {
            let mut solver = match state.take() {
                Some(s) => ExplicitSolver::resume(
                    &problem,
                    settings.clone(),
                    OutputSettings::default(),
                    s,
                )?,
                None => ExplicitSolver::new(&problem, settings.clone(), OutputSettings::default())?,
            };
            let mut region = Vec::new();
            while solver.step < steps {
                solver.step()?;
                if solver.step % policy.check_every.max(1) != 0 {
                    continue;
                }
                let m = &problem.model;
                let x: Vec<Vector3<f64>> = m
                    .reference
                    .iter()
                    .zip(&solver.u)
                    .map(|(x, u)| x + u)
                    .collect();
                if !super::check_distortion(&x, &m.tets, policy.collapse_limit).remesh {
                    continue;
                }
                let distorted: Vec<usize> = (0..m.tets.len())
                    .filter(|&e| {
                        super::collapse_ratio(&m.tets[e].map(|n| x[n as usize]))
                            > policy.collapse_limit
                    })
                    .collect();
                region = super::grow_region(&m.tets, &distorted, policy.layers);
                break;
            }
            (solver.state(), region)
        };
        if region.is_empty() {
            return Ok((problem, now, records));
        }
        let r = remesh_problem(&problem, &now, &region, &policy.mesher)?;
        records.push(r.record);
        problem = r.problem;
        state = Some(r.state);
    }
}
