//! A symmetry plane holds every node of its body that reaches it (`Motion::Symmetry`,
//! `dynamics/explicit/symmetry_wall.rs`): a soft box whose cut face is held on the plane only
//! over its lower half is thrown at the plane; the upper half of that face would cross it.
#![allow(clippy::unwrap_used)]

use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, BoxSpec};
use impact_solver::model::{Constraint, Model, Motion};
use impact_solver::problem::Problem;
use nalgebra::Vector3;

const SIZE: f64 = 0.1;
const PULL: f64 = 100.0;

/// The box `[0, SIZE]^3` at rest, pulled along -x by a body force of `PULL` (m/s^2), its face
/// x = 0 held by `motion` below mid-height.
fn pulled_box(motion: Motion) -> Problem {
    let mesh = box_mesh(&BoxSpec {
        origin: [0.0; 3],
        size: [SIZE; 3],
        divisions: [4, 4, 2],
        mirror: Vec::new(),
    });
    let soft = MaterialModel::LinearElastic(IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1e6,
        poisson_ratio: 0.25,
    });
    let model = Model::new(vec![("box".into(), mesh, soft)]).unwrap();
    let mut p = Problem::new(model);
    let held: Vec<u32> = (0..p.model.node_count())
        .filter(|&n| {
            let x = p.model.reference[n];
            x.x.abs() < 1e-12 && x.y < 0.5 * SIZE + 1e-12
        })
        .map(|n| n as u32)
        .collect();
    p.gravity = Some(Vector3::new(-PULL, 0.0, 0.0));
    p.constraints.push(Constraint {
        name: "cut".into(),
        nodes: held,
        motion,
    });
    p
}

/// Runs 10 ms (the free nodes of the face start on the plane; unheld, they would go 5 mm
/// through it); returns the smallest x any node reached and the worst relative energy
/// error over its second half.
fn run(problem: &Problem) -> (f64, f64) {
    let mut solver = ExplicitSolver::new(
        problem,
        ExplicitSettings::new(1e-2),
        OutputSettings::default(),
    )
    .unwrap();
    let (mut least, mut error) = (f64::INFINITY, 0.0_f64);
    while solver.time < 1e-2 {
        solver.step().unwrap();
        for (x, u) in problem
            .model
            .reference
            .iter()
            .zip(solver.whole(&solver.u).iter())
        {
            least = least.min(x.x + u.x);
        }
        // Relative to the energy put in so far, which starts at zero: judged over the second
        // half of the run.
        if solver.time > 5e-3 {
            error = error.max(solver.energies.relative_error().abs());
        }
    }
    (least, error)
}

#[test]
fn nodes_that_reach_the_plane_stay_on_it_and_the_energy_balances() {
    let (least, error) = run(&pulled_box(Motion::Symmetry {
        axis: 0,
        value: 0.0,
    }));
    assert!(
        least >= -1e-15,
        "a node crossed the plane to x = {least:.3e} m"
    );
    // The project's bar for a run's energy balance (1 %, as the drop tests'); measured 3.3e-3,
    // against 1.6e-3 for the same box held as a fixed component (nothing reaches the plane).
    assert!(error < 1e-2, "relative energy error {error:.3e}");
    // Held as a plain fixed component, the free half of the face goes through the plane.
    let (least, _) = run(&pulled_box(Motion::Fixed([true, false, false])));
    assert!(
        least < -1e-3,
        "without the wall the face reached only {least:.3e} m"
    );
}
