//! Dynamic patch test (CATALOGUE `patch/dynamic-linear-velocity`): with the boundary moving with
//! a linear velocity field and the body starting with the same field, the interior must follow it
//! exactly (uniform stress gives zero force at interior nodes), and the stress stays uniform.

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::MaterialModel;
use impact_solver::model::{Constraint, Motion};
use nalgebra::{Matrix3, Vector3};

#[test]
fn linear_velocity_field_stays_linear_for_100_steps() {
    const SIZE: [f64; 3] = [1.0, 1.0, 1.0];
    for material in [
        MaterialModel::SaintVenantKirchhoff(STEEL),
        MaterialModel::LinearElastic(STEEL),
    ] {
        let mut p = problem(box_body(SIZE, [4, 4, 4], 0.25, 11), material);
        let l = Matrix3::new(2.0, -1.0, 0.5, 0.3, -1.5, 1.0, -0.4, 0.8, 1.2);
        let t0 = Vector3::new(0.1, -0.2, 0.3);
        let field = |x: &Vector3<f64>| t0 + l * x;
        p.initial_velocity = p.model.reference.iter().map(field).collect();
        let boundary = box_boundary_nodes(&p.model, SIZE);
        p.constraints.push(Constraint {
            name: "boundary".into(),
            nodes: boundary.clone(),
            motion: Motion::AffineVelocity {
                translation: t0,
                gradient: l,
                center: Vector3::zeros(),
            },
        });
        let mut settings = ExplicitSettings::new(1.0);
        settings.max_steps = Some(100);
        let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
        let summary = solver.run(&mut |_| {}).unwrap();
        assert_eq!(summary.steps, 100);
        let t = summary.time;
        let v_scale = p
            .model
            .reference
            .iter()
            .map(|x| field(x).norm())
            .fold(0.0, f64::max);
        let interior: Vec<usize> = (0..p.model.node_count())
            .filter(|n| !boundary.contains(&(*n as u32)))
            .collect();
        for &n in &interior {
            let x = p.model.reference[n];
            let dv = (solver.v_full[n] - field(&x)).norm() / v_scale;
            let du = (solver.u[n] - t * field(&x)).norm() / (t * v_scale);
            assert!(
                dv < 1e-10,
                "{}: node {n} velocity error {dv:e}",
                material.name()
            );
            assert!(
                du < 1e-10,
                "{}: node {n} displacement error {du:e}",
                material.name()
            );
        }
        let stress = p.model.element_fields(&solver.whole(&solver.u)).cauchy;
        let first = voigt_to_matrix(&stress[0]);
        assert!(
            max_abs(&first) > 1e3,
            "the homogeneous deformation must stress the body"
        );
        for (e, s) in stress.iter().enumerate() {
            let err = max_abs(&(voigt_to_matrix(s) - first)) / max_abs(&first);
            assert!(
                err < 1e-10,
                "{}: element {e} stress differs by {err:e}",
                material.name()
            );
        }
    }
}
