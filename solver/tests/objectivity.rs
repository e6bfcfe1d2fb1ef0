//! Objectivity (CATALOGUE `patch/rigid-rotation`): a rigid rotation of 90 degrees produces no
//! stress, and a freely spinning body keeps its kinetic energy.

mod common;

use std::f64::consts::FRAC_PI_2;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::model::{Constraint, Motion, TimeFunction};
use nalgebra::{Unit, Vector3};

#[test]
fn prescribed_rotation_by_90_degrees_leaves_no_stress() {
    for material in [
        MaterialModel::SaintVenantKirchhoff(STEEL),
        MaterialModel::LinearElastic(STEEL),
    ] {
        let mut p = problem(box_body([0.2, 0.1, 0.1], [4, 2, 2], 0.2, 3), material);
        let all: Vec<u32> = (0..p.model.node_count() as u32).collect();
        let end = 2e-4;
        p.constraints.push(Constraint {
            name: "rotation".into(),
            nodes: all,
            motion: Motion::Rotation {
                axis: Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)),
                center: Vector3::new(0.1, 0.05, 0.05),
                // Constant angular velocity through the end of the run (no stop at the last step).
                angle: TimeFunction::Ramp {
                    t0: 0.0,
                    t1: 2.0 * end,
                    from: 0.0,
                    to: 2.0 * FRAC_PI_2,
                },
            },
        });
        let mut solver =
            ExplicitSolver::new(&p, ExplicitSettings::new(end), OutputSettings::default()).unwrap();
        solver.run(&mut |_| {}).unwrap();
        // The body really turned: a corner moved by about its distance from the axis.
        let moved = solver
            .whole(&solver.u)
            .iter()
            .map(|u| u.norm())
            .fold(0.0, f64::max);
        assert!(
            moved > 0.05,
            "rotation did not happen: largest displacement {moved}"
        );
        let worst = max_element_stress(&p.model, &solver.whole(&solver.u));
        assert!(
            worst < 1e-8 * STEEL.youngs_modulus,
            "{}: stress {worst:e} Pa after a rigid rotation",
            material.name()
        );
    }
}

#[test]
fn free_spin_keeps_kinetic_energy_and_stays_unstressed() {
    // Soft enough for few steps, slow enough that the physical centrifugal stress
    // rho w^2 r^2 (about 1e-9 E here) stays below the 1e-8 E bound.
    let rubber = IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1e7,
        poisson_ratio: 0.3,
    };
    let omega = 0.02;
    for material in [
        MaterialModel::SaintVenantKirchhoff(rubber),
        MaterialModel::LinearElastic(rubber),
    ] {
        let mut p = problem(box_body([0.2, 0.2, 0.2], [2, 2, 2], 0.0, 0), material);
        // Spin about a principal axis of the lumped-mass inertia through the centre of mass:
        // the Kuhn mesh lumps unequal masses, so about any other axis the body would precess.
        let model = &p.model;
        let total = model.total_mass();
        let center = model
            .reference
            .iter()
            .zip(&model.mass)
            .fold(Vector3::zeros(), |a, (x, m)| a + x * *m)
            / total;
        let inertia = model.reference.iter().zip(&model.mass).fold(
            nalgebra::Matrix3::zeros(),
            |acc, (x, m)| {
                let r = x - center;
                acc + (nalgebra::Matrix3::identity() * r.norm_squared() - r * r.transpose()) * *m
            },
        );
        let eig = inertia.symmetric_eigen();
        let axis = (0..3)
            .map(|i| eig.eigenvectors.column(i).into_owned())
            .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
            .unwrap();
        let w = axis * omega;
        p.initial_velocity = p
            .model
            .reference
            .iter()
            .map(|x| w.cross(&(x - center)))
            .collect();
        let end = FRAC_PI_2 / omega;
        let mut settings = ExplicitSettings::new(end);
        settings.history_interval = Some(end / 200.0);
        let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
        let summary = solver.run(&mut |_| {}).unwrap();
        let k = summary.history.column("kinetic").unwrap();
        let k0 = k[0];
        let drift = k.iter().map(|x| (x - k0).abs() / k0).fold(0.0, f64::max);
        assert!(
            drift < 1e-6,
            "{}: kinetic energy drifted by {drift:e}",
            material.name()
        );
        // Every node turned rigidly about the axis by the angle of the run (90 degrees).
        let angle = omega * summary.time;
        assert!((angle - FRAC_PI_2).abs() < 1e-3);
        let rotation =
            nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
        for n in 0..p.model.node_count() {
            let x = p.model.reference[n];
            let expected = center + rotation * (x - center);
            let err = (x + solver.u[n] - expected).norm();
            assert!(
                err < 1e-7,
                "{}: node {n} is {err:e} m off the rigid rotation",
                material.name()
            );
        }
        let worst = max_element_stress(&p.model, &solver.whole(&solver.u));
        assert!(
            worst < 1e-8 * rubber.youngs_modulus,
            "{}: stress {worst:e} Pa in free spin",
            material.name()
        );
    }
}
