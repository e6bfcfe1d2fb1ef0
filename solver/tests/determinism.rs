//! Same input, bitwise the same output, whatever the number of threads.

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::MaterialModel;
use impact_solver::model::{Constraint, Motion, TimeFunction};

fn run(threads: usize, material: MaterialModel) -> (Vec<u64>, Vec<u64>) {
    // Enough elements for several assembly chunks, so shared nodes are exercised.
    let mut p = problem(box_body([1.0, 0.5, 0.5], [24, 12, 12], 0.2, 9), material);
    let end: Vec<u32> = (0..p.model.node_count() as u32)
        .filter(|&n| p.model.reference[n as usize].x < 1e-12)
        .collect();
    p.constraints.push(Constraint {
        name: "hit".into(),
        nodes: end,
        motion: Motion::Velocity([true, true, false], TimeFunction::Constant(2.0)),
    });
    let mut settings = ExplicitSettings::new(1.0);
    settings.max_steps = Some(60);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
        let summary = solver.run(&mut |_| {}).unwrap();
        let state = solver
            .u
            .iter()
            .chain(&solver.v_full)
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect();
        let history = summary
            .history
            .rows()
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect();
        (state, history)
    })
}

#[test]
fn one_and_two_threads_give_bitwise_identical_results() {
    for material in [
        MaterialModel::LinearElastic(STEEL),
        MaterialModel::SaintVenantKirchhoff(STEEL),
    ] {
        let one = run(1, material);
        let two = run(2, material);
        assert!(one.0.iter().any(|&b| b != 0), "the run must move something");
        assert_eq!(
            one.0,
            two.0,
            "{}: state differs between 1 and 2 threads",
            material.name()
        );
        assert_eq!(
            one.1,
            two.1,
            "{}: history differs between 1 and 2 threads",
            material.name()
        );
    }
}
