//! One explicit step of the 2 m/s drop test (`cases/beam/drop-2ms.yaml`: the thesis beam of
//! microplane concrete on 50 mm cells, 25 920 tetrahedra, and the steel hammer, 4 116), with the
//! beam and the hammer in contact, beside the same step with a linear elastic beam of the same
//! initial constants: the cost of the concrete model in a whole step, measured in one run.
//!
//! Benchmarks: `drop_step/microplane` and `drop_step/elastic`, each a whole step on two threads
//! (the rayon pool of the machine: forces, predictor, prescribed motion, contact, energies; no
//! output). Each sample starts from a fresh run advanced untimed by [`WARM_STEPS`] steps (the
//! hammer is on the beam after about 12), then times up to [`CHUNK`] steps; longer samples
//! repeat the pattern, so every timed step lies within the first 90 steps (0.4 ms), while the
//! contact force still rises (it ends near 0.55 ms). The bench prints the steps' time step, the
//! contact force at the start of the timed window and the share of microplane updates that took
//! the elastic path there.
//!
//! Run with `cargo bench -p impact-solver --bench drop_step` (about two minutes); the ratio of
//! the two medians is the drop test's cost over an elastic beam's (issue 20: at most 3).
// Benchmark code: an `unwrap` that fails stops the benchmark (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::problem::Problem;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, MaterialSpec, Scene};

/// Steps run untimed before each timed window: the hammer has touched and the contact force
/// rises.
const WARM_STEPS: usize = 40;
/// Steps timed from one fresh start.
const CHUNK: u64 = 50;

/// The scene of the drop-test case, with the beam's material replaced by linear elasticity at its
/// initial constants when `elastic`.
fn drop_scene(elastic: bool) -> Scene {
    let case = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/beam/drop-2ms.yaml");
    let mut scene = Scene::from_yaml_file_entry(&case, "scene").unwrap();
    if elastic {
        let beam = scene.bodies.iter_mut().find(|b| b.name == "beam").unwrap();
        let constants = beam.material.model(&beam.name).unwrap().constants();
        beam.material = MaterialSpec::LinearElastic(constants);
    }
    scene
}

/// A fresh run of `problem` advanced by [`WARM_STEPS`].
fn warmed<'p>(problem: &'p Problem, scene: &Scene) -> ExplicitSolver<'p> {
    let Analysis::Explicit(ExplicitAnalysis { settings, .. }) = &scene.analysis else {
        panic!("the drop test is an explicit analysis")
    };
    let output = OutputSettings {
        dir: None,
        stem: "drop-step".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::new(problem, settings.clone(), output).unwrap();
    for _ in 0..WARM_STEPS {
        solver.step().unwrap();
    }
    solver
}

fn drop_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("drop_step");
    group.sample_size(10);
    for (name, elastic) in [("microplane", false), ("elastic", true)] {
        let scene = drop_scene(elastic);
        let problem = build_problem(&scene).unwrap();
        let solver = warmed(&problem, &scene);
        let contact: f64 = solver.contact_steps.iter().map(|s| s.normal_force).sum();
        let elastic_share = problem
            .model
            .fast_update_share(solver.history(), WARM_STEPS)
            .map_or("-".to_string(), |s| format!("{:.1} %", 100.0 * s));
        eprintln!(
            "{name}: dt = {:.3e} s, after {WARM_STEPS} steps t = {:.3e} s, contact force \
             {contact:.3e} N, elastic-path share so far {elastic_share}",
            solver.time_step(),
            solver.time,
        );
        drop(solver);
        group.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                let mut left = iters;
                while left > 0 {
                    let mut solver = warmed(&problem, &scene);
                    let n = left.min(CHUNK);
                    let start = Instant::now();
                    for _ in 0..n {
                        black_box(solver.step().unwrap());
                    }
                    total += start.elapsed();
                    left -= n;
                }
                total
            })
        });
    }
    group.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(20))
}

criterion_group! {
    name = benches;
    config = config();
    targets = drop_step
}
criterion_main!(benches);
