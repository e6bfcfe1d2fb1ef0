//! Same input, bitwise the same output, whatever the number of threads.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::microplane::{state, MicroplaneConcrete};
use impact_solver::material::{read_microplane_file, MaterialModel};

/// The state, the history table and the material history (bits) after 60 steps.
fn run(threads: usize, material: MaterialModel) -> (Vec<u64>, Vec<u64>, Vec<u64>) {
    // Enough elements for several assembly chunks, so shared nodes are exercised.
    let mut p = problem(box_body([1.0, 0.5, 0.5], [24, 12, 12], 0.2, 9), material);
    drive_end_face(&mut p, "hit", [true, true, false], 2.0);
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
            .whole(&solver.u)
            .iter()
            .chain(solver.whole(&solver.v_full).iter())
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect();
        let history = summary
            .history
            .rows()
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect();
        let material_history = material_history_bits(solver.history());
        (state, history, material_history)
    })
}

/// The concrete of the thesis in microplane form, from its parameter file.
fn microplane_concrete() -> MaterialModel {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/materials/thesis-concrete.yaml");
    MaterialModel::Microplane(read_microplane_file(&path).unwrap())
}

#[test]
fn one_and_two_threads_give_bitwise_identical_results() {
    for material in [
        MaterialModel::LinearElastic(STEEL),
        MaterialModel::SaintVenantKirchhoff(STEEL),
        microplane_concrete(),
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
        assert_eq!(
            one.2,
            two.2,
            "{}: material history differs between 1 and 2 threads",
            material.name()
        );
    }
}

/// The microplane run of the test above loads elements past the peak of their tension law
/// (2 m/s against concrete), so the history it compares is not merely elastic.
#[test]
fn the_microplane_determinism_run_damages_the_concrete() {
    let material = microplane_concrete();
    let MaterialModel::Microplane(p) = material else {
        unreachable!()
    };
    let (_, _, history) = run(2, material);
    // Each element's history: a header, then per plane [D+ strain, D+ stress, ...]. Beyond the
    // peak of the exponential law the secant s/e of D+ is below exp(-1) of E_D0 = E / (1 + nu)
    // (whatever the rate factor); count the planes well past it.
    let values: Vec<f32> = history.iter().map(|&b| f32::from_bits(b as u32)).collect();
    let e_d0 = p.youngs_modulus / (1.0 + p.poisson_ratio);
    let state_len = MicroplaneConcrete::new(p).unwrap().state_len();
    // Then the element's Cauchy stress, six f64 (one value of `history` each).
    let elements = values.len() / (state_len + 6);
    let softened = values[..elements * state_len]
        .chunks_exact(state_len)
        .flat_map(|element| element[state::HEADER..].chunks_exact(state::PER_PLANE))
        .filter(|plane| {
            let (e, s) = (
                plane[state::D_POSITIVE] as f64,
                plane[state::D_POSITIVE + 1] as f64,
            );
            e > 0.0 && s / e < 0.2 * e_d0
        })
        .count();
    assert!(softened > 100, "only {softened} planes softened");
}
