//! A remeshed run's problem goes into a checkpoint and comes back the same: a microplane body
//! (crack bands per element), held on one face and probed on another, is remeshed twice; its
//! problem is written, read back onto the problem built before any remeshing, and the two
//! problems give the same model to the bit and run on to the same displacements, velocities
//! and histories to the bit; the remeshings' records come back to the bit too. A damaged record
//! is refused.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, RunState};
use impact_solver::material::MaterialModel;
use impact_solver::mesh::ops::MesherOptions;
use impact_solver::model::{Constraint, Motion, Probe, ProbeQuantity};
use impact_solver::problem::Problem;
use impact_solver::remesh::remesh_problem;
use impact_solver::restart::bytes::{Reader, Writer};
use impact_solver::restart::problem::{read_problem, write_problem};
use impact_solver::restart::remeshings::{read_remeshings, write_remeshings};
use nalgebra::Vector3;

fn run(problem: &Problem, state: Option<RunState>, steps: usize) -> RunState {
    let mut settings = ExplicitSettings::new(1.0);
    settings.safety = 0.5;
    run_steps(problem, settings, state, steps)
}

/// The stretched microplane block with a held face and a probe, before any remeshing.
fn scene_problem() -> Problem {
    let mut p = problem(
        box_body([0.2, 0.1, 0.1], [8, 4, 4], 0.2, 5),
        MaterialModel::Microplane(thesis_concrete()),
    );
    let on = |axis: usize, value: f64| -> Vec<u32> {
        (0..p.model.node_count() as u32)
            .filter(|&n| (p.model.reference[n as usize][axis] - value).abs() < 1e-9)
            .collect()
    };
    let held = on(0, 0.0);
    let end = on(0, 0.2);
    p.constraints.push(Constraint {
        name: "held".into(),
        nodes: held,
        motion: Motion::Fixed([true, false, false]),
    });
    p.probes.push(Probe {
        name: "end".into(),
        nodes: end,
        quantity: ProbeQuantity::Displacement,
    });
    p.initial_velocity = p
        .model
        .reference
        .iter()
        .map(|x| Vector3::new(20.0 * x.x, 0.0, 0.0))
        .collect();
    p
}

#[test]
fn a_remeshed_problem_is_written_and_read_back_bit_for_bit() {
    let scene = scene_problem();
    let state = run(&scene, None, 30);
    let region = current_region_near(&scene, &state, 0, Vector3::new(0.1, 0.05, 0.05), 0.03);
    let first = remesh_problem(&scene, &state, &region, &MesherOptions::default(), 0.0).unwrap();
    let state = run(&first.problem, Some(first.state), 20);
    let region = current_region_near(
        &first.problem,
        &state,
        0,
        Vector3::new(0.12, 0.05, 0.05),
        0.02,
    );
    let second = remesh_problem(
        &first.problem,
        &state,
        &region,
        &MesherOptions::default(),
        0.0,
    )
    .unwrap();
    let remeshed = &second.problem;
    assert!(remeshed.model.element_count() > scene.model.element_count());

    let mut w = Writer::default();
    write_problem(&mut w, remeshed);
    let mut r = Reader::new(&w.bytes);
    let back = read_problem(&mut r, &scene).unwrap();
    assert_eq!(r.remaining(), 0, "the record is read to its end");

    let (a, b) = (&remeshed.model, &back.model);
    assert_eq!(a.reference, b.reference);
    assert_eq!(a.tets, b.tets);
    assert_eq!(a.kept_elements(), b.kept_elements());
    for e in a.kept_elements() {
        assert_eq!(a.grad_n(e), b.grad_n(e));
        assert_eq!(a.volume(e), b.volume(e));
        assert_eq!(a.min_altitude(e), b.min_altitude(e));
    }
    assert_eq!(a.mass, b.mass);
    assert_eq!(a.mass_scale, b.mass_scale);
    assert_eq!(a.carried, b.carried);
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        assert_eq!(x.nodes, y.nodes);
        assert_eq!(x.elements, y.elements);
        assert_eq!(x.node_sets, y.node_sets);
        let data = x.material.element_data().unwrap();
        assert_eq!(data.len(), 4 * x.elements.len(), "a crack band per element");
        assert_eq!(Some(data), y.material.element_data());
    }
    // The crack bands differ from the scene's: the record carries them, not the scene.
    assert_ne!(
        a.bodies[0].material.element_data(),
        scene.model.bodies[0].material.element_data()
    );
    for (x, y) in remeshed.constraints.iter().zip(&back.constraints) {
        assert_eq!((&x.name, &x.nodes), (&y.name, &y.nodes));
    }
    for (x, y) in remeshed.probes.iter().zip(&back.probes) {
        assert_eq!((&x.name, &x.nodes), (&y.name, &y.nodes));
    }
    assert_eq!(remeshed.initial_velocity, back.initial_velocity);

    // The two remeshings' records come back to the bit, and a cut record is refused.
    let records = [first.record, second.record];
    let mut w = Writer::default();
    write_remeshings(&mut w, &records);
    let mut r = Reader::new(&w.bytes);
    assert_eq!(read_remeshings(&mut r).unwrap(), records);
    assert_eq!(r.remaining(), 0);
    assert!(read_remeshings(&mut Reader::new(&w.bytes[..w.bytes.len() - 1])).is_err());

    // Both go on from the remeshing's state to the same bits.
    let on_original = run(remeshed, Some(second.state.clone()), 40);
    let on_read = run(&back, Some(second.state), 40);
    assert_eq!(on_original.u, on_read.u);
    assert_eq!(on_original.v_full, on_read.v_full);
    assert_eq!(on_original.history, on_read.history);
    assert!(on_original.u.iter().any(|u| u.norm() > 0.0));
}

#[test]
fn a_record_that_does_not_fit_the_scene_is_refused() {
    let scene = scene_problem();
    let state = run(&scene, None, 30);
    let region = current_region_near(&scene, &state, 0, Vector3::new(0.1, 0.05, 0.05), 0.03);
    let remeshed = remesh_problem(&scene, &state, &region, &MesherOptions::default(), 0.0)
        .unwrap()
        .problem;
    let mut w = Writer::default();
    write_problem(&mut w, &remeshed);

    // Cut short: an error saying what was being read, no panic.
    let cut = &w.bytes[..w.bytes.len() / 2];
    assert!(read_problem(&mut Reader::new(cut), &scene).is_err());
    // Onto a scene without the probe.
    let mut other = scene_problem();
    other.probes.clear();
    let e = read_problem(&mut Reader::new(&w.bytes), &other).unwrap_err();
    assert!(e.0.contains("probes"), "{}", e.0);
}
