//! Static patch tests (CATALOGUE `patch/static-*`): a cube of irregular tetrahedra whose boundary
//! follows a linear displacement field must reproduce it exactly inside, with exact stresses.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_references::analytic::{corotated_cauchy, svk_cauchy};
use impact_solver::material::MaterialModel;
use impact_solver::model::{Constraint, Motion, TimeFunction};
use impact_solver::statics::{solve_static, StaticSettings};
use nalgebra::{Matrix3, Vector3};

const SIZE: [f64; 3] = [1.0, 1.0, 1.0];

fn patch(
    material: MaterialModel,
    gradient: Matrix3<f64>,
    reference: fn(&impact_solver::material::IsotropicElastic, &Matrix3<f64>) -> Matrix3<f64>,
) {
    let mut p = problem(box_body(SIZE, [4, 4, 4], 0.25, 7), material);
    let boundary = box_boundary_nodes(&p.model, SIZE);
    let translation = Vector3::new(1e-3, -2e-3, 0.5e-3);
    p.constraints.push(Constraint {
        name: "boundary".into(),
        nodes: boundary.clone(),
        motion: Motion::AffineDisplacement {
            translation,
            gradient,
            center: Vector3::zeros(),
            scale: TimeFunction::Ramp {
                t0: 0.0,
                t1: 1.0,
                from: 0.0,
                to: 1.0,
            },
        },
    });
    let solution = solve_static(
        &p,
        &StaticSettings {
            load_steps: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let exact = |x: &Vector3<f64>| translation + gradient * x;
    let u_scale = p
        .model
        .reference
        .iter()
        .map(|x| exact(x).norm())
        .fold(0.0, f64::max);
    let interior: Vec<usize> = (0..p.model.node_count())
        .filter(|n| !boundary.contains(&(*n as u32)))
        .collect();
    assert!(interior.len() >= 27, "the patch needs interior nodes");
    for &n in &interior {
        let err = (solution.u[n] - exact(&p.model.reference[n])).norm() / u_scale;
        assert!(err < 1e-10, "node {n}: displacement error {err:e} relative");
    }
    let f = Matrix3::identity() + gradient;
    let sigma = reference(&material.constants(), &f);
    let fields = p.model.element_fields(&solution.u);
    for (e, s) in fields.cauchy.iter().enumerate() {
        let err = max_abs(&(voigt_to_matrix(s) - sigma)) / max_abs(&sigma);
        assert!(err < 1e-10, "element {e}: stress error {err:e} relative");
    }
}

fn tension() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(2e-2, 0.0, 0.0))
}
fn shear() -> Matrix3<f64> {
    Matrix3::new(0.0, 1.5e-2, 0.0, 1.5e-2, 0.0, 0.0, 0.0, 0.0, 0.0)
}
fn general() -> Matrix3<f64> {
    Matrix3::new(
        1.2e-2, -0.7e-2, 0.4e-2, 0.3e-2, -0.9e-2, 1.1e-2, -0.5e-2, 0.8e-2, 0.6e-2,
    )
}

#[test]
fn svk_pure_tension() {
    patch(
        MaterialModel::SaintVenantKirchhoff(STEEL),
        tension(),
        svk_cauchy,
    );
}
#[test]
fn svk_pure_shear() {
    patch(
        MaterialModel::SaintVenantKirchhoff(STEEL),
        shear(),
        svk_cauchy,
    );
}
#[test]
fn svk_general_linear_field() {
    patch(
        MaterialModel::SaintVenantKirchhoff(STEEL),
        general(),
        svk_cauchy,
    );
}
#[test]
fn linear_elastic_pure_tension() {
    patch(
        MaterialModel::LinearElastic(STEEL),
        tension(),
        corotated_cauchy,
    );
}
#[test]
fn linear_elastic_pure_shear() {
    patch(
        MaterialModel::LinearElastic(STEEL),
        shear(),
        corotated_cauchy,
    );
}
#[test]
fn linear_elastic_general_linear_field() {
    patch(
        MaterialModel::LinearElastic(STEEL),
        general(),
        corotated_cauchy,
    );
}
