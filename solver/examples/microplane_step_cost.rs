//! Wall time per element and step of explicit runs with microplane concrete, against the same run
//! with linear elastic concrete.
//!
//! A 0.6 x 0.3 x 0.3 m block of 25 mm cells (20 736 tetrahedra, element size 25 mm) is struck
//! at x = 0 with 5 m/s in x and y, so its elements load, crack and soften during the run; each
//! configuration runs `RUNS` times for `STEPS` steps and the median is printed, per thread count.
//!
//! `cargo run --release -p impact-solver --example microplane_step_cost`

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::{read_microplane_file, IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, BoxSpec};
use impact_solver::model::{Constraint, Model, Motion, TimeFunction};
use impact_solver::problem::Problem;

const STEPS: usize = 100;
const RUNS: usize = 5;

fn problem(material: MaterialModel) -> Problem {
    let mesh = box_mesh(&BoxSpec {
        origin: [0.0; 3],
        size: [0.6, 0.3, 0.3],
        divisions: [24, 12, 12],
        mirror: Vec::new(),
    });
    let mut p = Problem::new(Model::new(vec![("block".into(), mesh, material)]).unwrap());
    let face: Vec<u32> = (0..p.model.node_count() as u32)
        .filter(|&n| p.model.reference[n as usize].x < 1e-9)
        .collect();
    p.constraints.push(Constraint {
        name: "strike".into(),
        nodes: face,
        motion: Motion::Velocity([true, true, false], TimeFunction::Constant(5.0)),
    });
    p
}

/// Median wall time per element and step (ns) over `RUNS` runs, and the largest rate factor.
fn cost(p: &Problem, threads: usize) -> (f64, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut times = Vec::new();
    let mut rate: f64 = 0.0;
    for _ in 0..RUNS {
        let mut settings = ExplicitSettings::new(1.0);
        settings.max_steps = Some(STEPS);
        let mut solver = ExplicitSolver::new(p, settings, OutputSettings::default()).unwrap();
        let summary = pool.install(|| solver.run(&mut |_| {}).unwrap());
        // run() takes STEPS + 1 force evaluations (t_0 to t_STEPS).
        let per_step = summary.wall_seconds / (summary.steps + 1) as f64;
        times.push(per_step / p.model.element_count() as f64 * 1e9);
        let fields = p
            .model
            .element_fields_with_history(&solver.whole(&solver.u), Some(solver.history()));
        rate = fields.rate_factor.iter().fold(rate, |a, &b| a.max(b));
    }
    times.sort_by(f64::total_cmp);
    (times[RUNS / 2], rate)
}

fn main() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/materials/thesis-concrete.yaml");
    let parameters = read_microplane_file(&path).unwrap();
    let elastic = IsotropicElastic {
        density: parameters.density,
        youngs_modulus: parameters.youngs_modulus,
        poisson_ratio: parameters.poisson_ratio,
    };
    for (name, material) in [
        ("linear_elastic", MaterialModel::LinearElastic(elastic)),
        ("microplane", MaterialModel::Microplane(parameters)),
    ] {
        let p = problem(material);
        for threads in [1, 2] {
            let (ns, rate) = cost(&p, threads);
            println!(
                "{name:>15}, {threads} thread(s): {ns:8.1} ns per element and step \
                 (median of {RUNS} runs of {STEPS} steps, {} elements; largest rate factor {rate:.3})",
                p.model.element_count()
            );
        }
    }
}
