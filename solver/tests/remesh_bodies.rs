//! Remeshing one body of a model with several (issue 21): the other bodies are copied bit for
//! bit under their shifted ids, a microplane body carries its history from each new element's
//! parent (T2) and gets crack bands for its new elements, and contact goes on over the rebuilt
//! surfaces. Expected values come from the definitions (copies are exact; T2 copies the row of
//! the parent) and from the physics of the bars' impact (velocities exchanged).

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_solver::contact::registry::SolverKind;
use impact_solver::dynamics::{ExplicitSettings, RunState};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneMaterial};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::ops::{centroids, MesherOptions};
use impact_solver::mesh::{box_mesh, BoxSpec, Mesh};
use impact_solver::model::Model;
use impact_solver::problem::Problem;
use impact_solver::remesh::{remesh_problem, Remeshed};
use nalgebra::Vector3;

/// Runs `steps` steps from `state` (or from the start), the time step `safety` of the stable one.
fn run(problem: &Problem, state: Option<RunState>, steps: usize) -> RunState {
    let mut settings = ExplicitSettings::new(1.0);
    settings.safety = 0.5;
    run_steps(problem, settings, state, steps)
}

fn remesh(problem: &Problem, state: &RunState, region: &[usize]) -> Remeshed {
    let r = remesh_problem(problem, state, region, &MesherOptions::default(), 0.0).unwrap();
    assert!(
        r.problem.model.element_count() > problem.model.element_count(),
        "the region was refined"
    );
    r
}

fn translated(mut mesh: Mesh, by: [f64; 3]) -> Mesh {
    mesh.nodes.iter_mut().for_each(|x| *x += Vector3::from(by));
    mesh
}

/// Three steel boxes in a row, the outer two moving rigidly, the middle one at rest; the middle
/// one is remeshed. The outer bodies' nodes, masses and velocities are copied bit for bit under
/// their new ids (the third body's shifted by the nodes the middle one gained), the model's
/// momentum and mass are kept to 1e-12, and the run goes on with the rigid motions.
#[test]
fn remeshing_the_middle_of_three_bodies_copies_the_other_two() {
    let m = MaterialModel::SaintVenantKirchhoff(STEEL);
    let cube = |x0: f64, seed| translated(box_body([1.0; 3], [4, 4, 4], 0.2, seed), [x0, 0.0, 0.0]);
    let model = Model::new(vec![
        ("left".into(), cube(0.0, 1), m),
        ("middle".into(), cube(2.0, 2), m),
        ("right".into(), cube(4.0, 3), m),
    ])
    .unwrap();
    let mut p = Problem::new(model);
    let (va, vc) = (Vector3::new(1.0, 2.0, -0.5), Vector3::new(-3.0, 0.25, 1.0));
    for (b, v) in [(0, va), (2, vc)] {
        for n in p.model.bodies[b].nodes.clone() {
            p.initial_velocity[n] = v;
        }
    }
    let state = run(&p, None, 10);
    let region = current_region_near(&p, &state, 1, Vector3::new(2.5, 0.5, 0.5), 0.2);
    let r = remesh(&p, &state, &region);
    let (old, new) = (&p.model, &r.problem.model);
    assert_eq!(new.bodies.len(), 3);
    assert_eq!(new.bodies[0].nodes, old.bodies[0].nodes);
    let gained = new.bodies[1].nodes.len() - old.bodies[1].nodes.len();
    assert!(gained > 0);
    for (b, v) in [(0, va), (2, vc)] {
        let shift = if b == 2 { gained } else { 0 };
        for n in old.bodies[b].nodes.clone() {
            let k = n + shift;
            assert_eq!(new.mass[k], old.mass[n]);
            assert_eq!(r.state.v_full[k], state.v_full[n]);
            assert_eq!(r.state.v_half[k], state.v_half[n]);
            assert_eq!(new.reference[k], old.reference[n] + state.u[n]);
            assert_eq!(r.state.v_full[k], v);
        }
    }
    let rec = r.record;
    let p_scale = rec.before.momentum.norm();
    assert!(
        rec.momentum_jump().norm() < 1e-12 * p_scale,
        "{}",
        rec.summary()
    );
    assert!(((rec.after.mass - rec.before.mass) / rec.before.mass).abs() < 1e-12);
    for n in new.bodies[1].nodes.clone() {
        assert!(
            r.state.v_full[n].norm() < 1e-12,
            "the middle body stays at rest"
        );
    }
    let after = run(&r.problem, Some(r.state), 20);
    for (b, v) in [(0, va), (2, vc)] {
        for n in r.problem.model.bodies[b].nodes.clone() {
            assert!((after.v_full[n] - v).norm() < 1e-12 * v.norm());
        }
    }
}

/// A block of the thesis concrete stretched at a uniform rate, remeshed mid-run. The transfer
/// is checked on histories made distinct per element (each value set to its element's id, as
/// the transfer never reads them): a kept element keeps its row, a new element gets the row of
/// its parent, the old element that holds its centroid (a brute-force search here), bit for
/// bit, so no value is a mix; each new element gets the crack band of its own size. The run with
/// the true history then goes on over the new mesh.
#[test]
fn a_microplane_body_carries_its_history_from_each_new_elements_parent() {
    let mut p = problem(
        box_body([0.2, 0.1, 0.1], [8, 4, 4], 0.2, 5),
        MaterialModel::Microplane(thesis_concrete()),
    );
    let rate = 20.0; // 1/s
    p.initial_velocity = p
        .model
        .reference
        .iter()
        .map(|x| Vector3::new(rate * (x.x - 0.1), 0.0, 0.0))
        .collect();
    let state = run(&p, None, 30);
    let region = current_region_near(&p, &state, 0, Vector3::new(0.1, 0.05, 0.05), 0.03);

    // The transfer, on marked rows.
    let mut marked = state.clone();
    let h = marked.history.bodies[0].as_mut().unwrap();
    let len = h.state_len;
    for (e, row) in h.values.chunks_exact_mut(len).enumerate() {
        row.iter_mut().for_each(|v| *v = e as f32);
    }
    let r = remesh(&p, &marked, &region);
    let x: Vec<Vector3<f64>> = p
        .model
        .reference
        .iter()
        .zip(&state.u)
        .map(|(x, u)| x + u)
        .collect();
    let new_model = &r.problem.model;
    let new_c = centroids(&new_model.reference, &new_model.tets);
    let new_h = r.state.history.bodies[0].as_ref().unwrap();
    let material: &dyn std::any::Any = &*new_model.bodies[0].material;
    let micro = material.downcast_ref::<MicroplaneMaterial>().unwrap();
    let (mut copied, mut transferred) = (0, 0);
    for (e, c) in new_c.iter().enumerate() {
        let row = &new_h.values[e * len..(e + 1) * len];
        let source = row[0] as usize;
        assert!(row.iter().all(|&v| v == row[0]), "a row is one element's");
        // The parent: the old element whose current tetrahedron holds the new centroid
        // (brute force over barycentric coordinates), the one nearest to it if none does.
        let bary_min = |e: usize| {
            let [a, b, cc, d] = p.model.tets[e].map(|n| x[n as usize]);
            let m = nalgebra::Matrix3::from_columns(&[b - a, cc - a, d - a]);
            let l = m.try_inverse().unwrap() * (c - a);
            (1.0 - l.sum()).min(l.min())
        };
        let parent = (0..p.model.element_count())
            .max_by(|&a, &b| bary_min(a).total_cmp(&bary_min(b)))
            .unwrap();
        let kept = (new_model.tets[e].map(|n| new_model.reference[n as usize]))
            == (p.model.tets[source].map(|n| x[n as usize]));
        if kept {
            copied += 1;
        } else {
            transferred += 1;
            assert_eq!(
                source, parent,
                "new element {e}: its history is its parent's"
            );
            let band = micro
                .model
                .crack_band(MicroplaneConcrete::element_size(new_model.volume(e)))
                .unwrap();
            assert_eq!(
                micro.bands[e], band,
                "new element {e} has the band of its own size"
            );
        }
    }
    println!("{copied} elements copied, {transferred} new ones by T2");
    assert!(transferred > 0 && copied > 0);

    // The run goes on with the true history.
    let r = remesh(&p, &state, &region);
    let after = run(&r.problem, Some(r.state), 30);
    assert!(after.energies.kinetic.is_finite() && after.energies.kinetic > 0.0);
}

/// With nu = 0 a bar of any section carries the one-dimensional wave at sqrt(E/rho).
const SOFT: IsotropicElastic = IsotropicElastic {
    density: 1000.0,
    youngs_modulus: 1e9,
    poisson_ratio: 0.0,
};

/// Two elastic bars meeting head-on, the right one remeshed at its struck end in the middle of
/// the contact: by one-dimensional wave theory they separate after `2 L / c` with their
/// velocities exchanged (Graff 1975, 2.5). Both runs, with and without the remeshing, end with
/// each bar's mean velocity within 5 % of the exchanged one (the bound of `contact_bars`: the
/// discrete bars keep about 1 % of it in vibration), within 1 % of each other, and with the
/// total momentum zero to 1e-8 of a bar's.
#[test]
fn bars_remeshed_during_their_impact_still_exchange_velocities() {
    const LENGTH: f64 = 0.5;
    const WIDTH: f64 = 0.04;
    const GAP: f64 = 2e-4;
    const SPEED: f64 = 1.0;
    // Different sections' divisions, so that no node of one end face sits on a node of the
    // other (coincident nodes are node-to-segment contact's degenerate case: the corners pass
    // each other unseen, and a node a remeshing adds on the face then finds itself inside).
    let bar = |x0: f64, across: usize| {
        box_mesh(&BoxSpec {
            origin: [x0, 0.0, 0.0],
            size: [LENGTH, WIDTH, WIDTH],
            divisions: [40, across, across],
            mirror: Vec::new(),
        })
    };
    let m = MaterialModel::LinearElastic(SOFT);
    let model = Model::new(vec![
        ("left".into(), bar(0.0, 2), m),
        ("right".into(), bar(LENGTH + GAP, 3), m),
    ])
    .unwrap();
    let mut p = Problem::new(model);
    for (b, velocity) in [(0, SPEED), (1, -SPEED)] {
        for n in p.model.bodies[b].nodes.clone() {
            p.initial_velocity[n] = Vector3::new(velocity, 0.0, 0.0);
        }
    }
    p.contact.push(contact_pair(
        "impact",
        0.0,
        tight_solver(SolverKind::GaussSeidelThesis),
    ));
    let c = (SOFT.youngs_modulus / SOFT.density).sqrt();
    let dt = 0.5 * p.model.critical_time_step().0;
    let contact_time = 2.0 * LENGTH / c;
    let at = |t: f64| (t / dt).round() as usize;
    let middle = at(GAP / (2.0 * SPEED) + 0.5 * contact_time);
    let end_time = GAP / (2.0 * SPEED) + 1.5 * contact_time;
    let state = run(&p, None, middle);
    let straight = run(&p, Some(state.clone()), at(end_time) - middle);
    let region = current_region_near(
        &p,
        &state,
        1,
        Vector3::new(LENGTH + GAP, 0.5 * WIDTH, 0.5 * WIDTH),
        0.03,
    );
    let r = remesh(&p, &state, &region);
    println!("{}", r.record.summary());
    // The refined face's edges whose midpoints lie inside the left bar (the bars press into
    // each other by the contact's tolerance) are not split, so no new node starts inside it.
    assert_eq!(
        r.record.separation.moved, 0,
        "no new node of the refined face starts inside the left bar"
    );
    let dt2 = 0.5 * r.problem.model.critical_time_step().0;
    // No kick: the kinetic energy one step after the remeshing stays that of the run on the
    // fixed mesh to within 1 % of the bars' energy (a node left 35 um inside the other bar
    // leaves at 35 um / dt and adds 1.1 J, 140 % of it; the new elements' stresses, their
    // parents', leave forces at the new nodes that add 0.35 %).
    let one = run(&r.problem, Some(r.state.clone()), 1);
    let fixed_one = run(&p, Some(state.clone()), 1);
    let kick = one.energies.kinetic - fixed_one.energies.kinetic;
    let energy = r.record.before.total_energy();
    println!(
        "kinetic energy one step on: {:.4e} J remeshed, {:.4e} J fixed, of {energy:.4e} J",
        one.energies.kinetic, fixed_one.energies.kinetic
    );
    assert!(kick.abs() < 1e-2 * energy, "kick of {kick:e} J");
    let remeshed = run(
        &r.problem,
        Some(r.state),
        ((end_time - state.time) / dt2).round() as usize,
    );
    let mean_velocity = |model: &Model, s: &RunState, b: usize| {
        let nodes = model.bodies[b].nodes.clone();
        let mass: f64 = nodes.clone().map(|n| model.mass[n]).sum();
        nodes.map(|n| model.mass[n] * s.v_full[n].x).sum::<f64>() / mass
    };
    let mut means = Vec::new();
    for (model, s, what) in [
        (&p.model, &straight, "fixed mesh"),
        (&r.problem.model, &remeshed, "remeshed"),
    ] {
        let (left, right) = (mean_velocity(model, s, 0), mean_velocity(model, s, 1));
        println!(
            "{what}: left {left:.5} m/s, right {right:.5} m/s at t = {:.4e} s",
            s.time
        );
        assert!(
            (left + SPEED).abs() < 0.05 * SPEED,
            "{what}: left bar {left}"
        );
        assert!(
            (right - SPEED).abs() < 0.05 * SPEED,
            "{what}: right bar {right}"
        );
        let total: f64 = (0..model.node_count())
            .map(|n| model.mass[n] * s.v_full[n].x)
            .sum();
        let bar_momentum = SOFT.density * LENGTH * WIDTH * WIDTH * SPEED;
        // Measured: 1.3e-12 of a bar's on the fixed mesh, 1.4e-9 after the remeshing (which
        // restores each body's momentum to 1e-16 of it): a drift after the resume whose source
        // is not found yet (issue 21's closing note). Bound 1e-8.
        println!(
            "{what}: total momentum {:e} of a bar's",
            total / bar_momentum
        );
        assert!(
            total.abs() < 1e-8 * bar_momentum,
            "{what}: momentum {total}"
        );
        means.push((left, right));
    }
    let (a, b) = (means[0], means[1]);
    assert!(
        (a.0 - b.0).abs() < 0.01 * SPEED && (a.1 - b.1).abs() < 0.01 * SPEED,
        "the remeshed run ends with {b:?} m/s, the fixed mesh with {a:?} m/s"
    );
}

/// The fields written after a remeshing read the deformation reached before it: an element
/// the remeshing left as it was has, on the new mesh at the moment of the remeshing, the
/// Green-Lagrange strain, largest principal strain and Cauchy stress it had on the old mesh, and every
/// node of it the displacement from the original configuration. (They were computed from the
/// displacement since the remeshing alone, so a remeshed body's frames showed it unstrained.)
#[test]
fn fields_after_a_remeshing_read_the_deformation_reached_before_it() {
    let m = MaterialModel::SaintVenantKirchhoff(STEEL);
    let model = Model::new(vec![(
        "cube".into(),
        box_body([1.0; 3], [4, 4, 4], 0.2, 7),
        m,
    )])
    .unwrap();
    let mut p = Problem::new(model);
    // A stretch along x and a shear in y, growing with time.
    for (n, x) in p.model.reference.clone().iter().enumerate() {
        p.initial_velocity[n] = Vector3::new(40.0 * x.x, 15.0 * x.x, 0.0);
    }
    let state = run(&p, None, 40);
    let region = current_region_near(&p, &state, 0, Vector3::new(0.5, 0.5, 0.5), 0.2);
    let r = remesh(&p, &state, &region);
    let (old, new) = (&p.model, &r.problem.model);
    let before = old.element_fields(&state.u);
    let after = new.element_fields(&r.state.u);
    let frame = |model: &Model, u: &[Vector3<f64>]| {
        let points: Vec<Vector3<f64>> = model.reference.iter().zip(u).map(|(x, u)| x + u).collect();
        let f = impact_solver::output::field_frame(model, &points, u, None, 0.0);
        match &f.point_data[0] {
            (name, impact_solver::output::vtu::FieldData::Vector(d)) if name == "displacement" => {
                d.clone()
            }
            _ => panic!("the first point field is the displacement"),
        }
    };
    let (d_old, d_new) = (frame(old, &state.u), frame(new, &r.state.u));
    // Old elements by their current corners (the new reference is the old current
    // configuration, computed the same way, so a kept element's corners match bit for bit).
    let key = |x: [Vector3<f64>; 4]| {
        let mut k: Vec<[u64; 3]> = x.iter().map(|p| p.map(f64::to_bits).into()).collect();
        k.sort_unstable();
        k
    };
    let old_by_corners: std::collections::HashMap<_, usize> = (0..old.element_count())
        .map(|e| {
            (
                key(old.tets[e].map(|n| old.reference[n as usize] + state.u[n as usize])),
                e,
            )
        })
        .collect();
    let (mut kept, mut strain_seen) = (0, 0.0f64);
    for e in 0..new.element_count() {
        let corners = new.tets[e].map(|n| new.reference[n as usize]);
        let Some(&o) = old_by_corners.get(&key(corners)) else {
            continue;
        };
        kept += 1;
        let scale = before.green_lagrange[o]
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        strain_seen = strain_seen.max(scale);
        for i in 0..6 {
            assert!(
                (after.green_lagrange[e][i] - before.green_lagrange[o][i]).abs() < 1e-12 * scale,
                "element {e} (was {o}): E {:?} against {:?}",
                after.green_lagrange[e],
                before.green_lagrange[o]
            );
            let s = before.cauchy[o].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!((after.cauchy[e][i] - before.cauchy[o][i]).abs() < 1e-9 * s);
        }
        let eps_1 = before.max_principal_strain[o];
        assert!((after.max_principal_strain[e] - eps_1).abs() < 1e-12 * scale);
        for &n in &new.tets[e] {
            // The node of the old mesh at the same place.
            let x = new.reference[n as usize];
            let q = old.tets[o]
                .iter()
                .find(|&&q| old.reference[q as usize] + state.u[q as usize] == x)
                .unwrap();
            let (a, b) = (d_new[n as usize], d_old[*q as usize]);
            for i in 0..3 {
                assert!(
                    (a[i] - b[i]).abs() < 1e-15 + 1e-12 * b[i].abs(),
                    "{a:?} {b:?}"
                );
            }
        }
    }
    assert!(kept > 100, "most elements are kept ({kept})");
    assert!(strain_seen > 1e-4, "the body is strained ({strain_seen:e})");
}
