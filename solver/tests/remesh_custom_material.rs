//! A constitutive model with a history, added from outside the solver in this one file, is
//! remeshed without any change to the remeshing: its history is carried to each new element
//! from the old element it continues or from its parent (T2), the body keeps its material, and
//! the run goes on.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, RunState};
use impact_solver::material::{
    Deformation, ElementState, IsotropicElastic, LinearElastic, Material,
};
use impact_solver::mesh::ops::{centroids, grow_region, MesherOptions};
use impact_solver::model::{BodyMaterial, Model};
use impact_solver::problem::Problem;
use impact_solver::remesh::remesh_problem;
use nalgebra::{Matrix3, Vector3};

/// Linear elasticity that records, per element, the largest volume change `|det F - 1|` it has
/// seen: one `f32` of history.
#[derive(Debug)]
struct PeakDilatation {
    elastic: LinearElastic,
}

impl Material for PeakDilatation {
    fn name(&self) -> &'static str {
        "peak_dilatation"
    }

    fn constants(&self) -> IsotropicElastic {
        self.elastic.constants()
    }

    fn history_len(&self) -> usize {
        1
    }

    fn update(&self, element: usize, d: &Deformation, state: ElementState) -> Option<Matrix3<f64>> {
        let seen = state.history[0].max((d.det - 1.0).abs() as f32);
        state.history[0] = seen;
        self.elastic.update(element, d, ElementState::stateless())
    }
}

fn run(problem: &Problem, state: Option<RunState>, steps: usize) -> RunState {
    run_steps(problem, ExplicitSettings::new(1.0), state, steps)
}

#[test]
fn a_history_model_from_outside_is_remeshed_with_its_history() {
    let material: Arc<dyn BodyMaterial> = Arc::new(PeakDilatation {
        elastic: LinearElastic::new(STEEL),
    });
    let mesh = box_body([0.2, 0.1, 0.1], [8, 4, 4], 0.2, 5);
    let model = Model::new(vec![("block".to_string(), mesh, material)]).unwrap();
    let mut p = Problem::new(model);
    // A stretching block: every element dilates, more where it is first reached.
    p.initial_velocity = p
        .model
        .reference
        .iter()
        .map(|x| Vector3::new(20.0 * (x.x - 0.1), 0.0, 0.0))
        .collect();
    let state = run(&p, None, 20);
    let h = state.history.bodies[0].as_ref().unwrap();
    assert_eq!(h.state_len, 1);
    assert!(
        h.values.iter().all(|&v| v > 0.0),
        "every element has dilated"
    );

    let x: Vec<Vector3<f64>> = p
        .model
        .reference
        .iter()
        .zip(&state.u)
        .map(|(x, u)| x + u)
        .collect();
    let seed: Vec<usize> = centroids(&x, &p.model.tets)
        .iter()
        .enumerate()
        .filter(|(_, c)| (*c - Vector3::new(0.1, 0.05, 0.05)).norm() < 0.03)
        .map(|(e, _)| e)
        .collect();
    let region = grow_region(&p.model.tets, &seed, 1);
    let r = remesh_problem(&p, &state, &region, &MesherOptions::default(), 0.0).unwrap();
    let new_model = &r.problem.model;
    assert!(
        new_model.element_count() > p.model.element_count(),
        "refined"
    );
    let any: &dyn std::any::Any = &*new_model.bodies[0].material;
    assert!(
        any.downcast_ref::<PeakDilatation>().is_some(),
        "the body keeps its own material"
    );
    // Every new element's history is one of the old elements' values (copied, or its parent's).
    let new_h = r.state.history.bodies[0].as_ref().unwrap();
    let old: Vec<u32> = h.values.iter().map(|v| v.to_bits()).collect();
    assert!(new_h.values.iter().all(|v| old.contains(&v.to_bits())));

    let after = run(&r.problem, Some(r.state), 20);
    let h_after = after.history.bodies[0].as_ref().unwrap();
    assert_eq!(h_after.values.len(), new_model.element_count());
    assert!(after.energies.kinetic.is_finite() && after.energies.kinetic > 0.0);
}
