//! The contact phase reports the nodes it may have moved (`ContactPhase::touched_nodes`), and
//! the explicit step corrects, and writes forces for, those nodes only. This checks the report
//! against what `resolve` did: outside it no predicted position and no friction correction
//! changes, by a single bit.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::{contact_pair, tight_solver};
use impact_solver::contact::registry::SolverKind;
use impact_solver::contact::ContactPhase;
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, BoxSpec};
use impact_solver::model::Model;
use nalgebra::Vector3;

const GAP: f64 = 1e-4;

/// Two blocks side by side along x, `GAP` apart, with a frictional pair between them.
fn blocks(kind: SolverKind) -> (Model, ContactPhase) {
    let block = |x0: f64, divisions: [usize; 3]| {
        box_mesh(&BoxSpec {
            origin: [x0, 0.0, 0.0],
            size: [0.1, 0.1, 0.1],
            divisions,
            mirror: Vec::new(),
        })
    };
    let m = MaterialModel::LinearElastic(IsotropicElastic {
        density: 2000.0,
        youngs_modulus: 1e9,
        poisson_ratio: 0.25,
    });
    // Different divisions, so nodes do not face nodes.
    let model = Model::new(vec![
        ("left".into(), block(0.0, [3, 4, 4]), m),
        ("right".into(), block(0.1 + GAP, [3, 5, 3]), m),
    ])
    .unwrap();
    let pair = contact_pair("pair", 0.5, tight_solver(kind));
    let phase = ContactPhase::new(&model, vec![pair]);
    (model, phase)
}

#[test]
fn only_the_touched_nodes_move() {
    for kind in [SolverKind::GaussSeidelThesis, SolverKind::ConicCoulomb] {
        let (model, mut phase) = blocks(kind);
        let inverse_mass: Vec<Vector3<f64>> = model
            .mass
            .iter()
            .map(|&m| Vector3::repeat(1.0 / m))
            .collect();
        let x0 = model.reference.to_vec();
        // The right block moves into the left one and sideways: normal and friction forces.
        let right = model.bodies[1].nodes.clone();
        let mut x1 = x0.clone();
        for n in right {
            x1[n] += Vector3::new(-3.0 * GAP, 0.5 * GAP, 0.2 * GAP);
        }
        let predicted = x1.clone();
        let mut tangential = vec![Vector3::zeros(); x0.len()];
        let steps = phase.resolve(
            0,
            &model,
            &inverse_mass,
            1e-6,
            &x0,
            &mut x1,
            &mut tangential,
        );
        assert!(
            steps[0].active > 0,
            "{kind:?}: the blocks must be in contact"
        );

        let touched = phase.touched_nodes();
        assert!(
            touched.windows(2).all(|w| w[0] < w[1]),
            "{kind:?}: ascending, no repeats"
        );
        let surface = phase.surface_nodes();
        assert!(touched.iter().all(|n| surface.binary_search(n).is_ok()));
        let mut is_touched = vec![false; x0.len()];
        for &n in touched {
            is_touched[n as usize] = true;
        }
        let mut moved = 0;
        for i in 0..x0.len() {
            let same = x1[i]
                .iter()
                .zip(predicted[i].iter())
                .all(|(a, b)| a.to_bits() == b.to_bits());
            if is_touched[i] {
                moved += usize::from(!same);
            } else {
                assert!(same, "{kind:?}: node {i} moved but is not reported");
                assert_eq!(tangential[i], Vector3::zeros(), "{kind:?}: node {i}");
            }
        }
        assert!(moved > 0, "{kind:?}: the correction moved no reported node");
    }
}
