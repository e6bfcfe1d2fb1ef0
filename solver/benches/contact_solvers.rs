//! Contact solvers on identical problems (issue 5): time to a natural-map error of 1e-8 of
//! `gauss-seidel/thesis`, `gauss-seidel/exact` and `conic/coulomb`.
//!
//! Problems:
//! - `stack`: a synthetic frictionless or frictional problem of our own kind (lumped masses:
//!   diagonal blocks multiples of the identity), a row of slave nodes pressed onto a chain of
//!   shared faces, built by `ContactProblem::from_constraints`, 64 contacts;
//! - `rover1039` and `oneobject-i1028-138` from `references/contact-problems` (Siconos,
//!   Apache-2.0, committed with the repository).
//!
//! Before the criterion groups, the natural-map error each solver reached is printed, so a
//! time never stands without its accuracy. Run with
//! `cargo bench -p impact-solver --bench contact_solvers` (about a minute).

// Benchmark code: an `unwrap` that fails stops the benchmark (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use impact_solver::contact::gauss_seidel::ContactConstraint;
use impact_solver::contact::problem::{natural_map_error, ContactProblem};
use impact_solver::contact::problem_file::read_problem;
use impact_solver::contact::registry::SolverKind;
use impact_solver::contact::solver::{ContactSolver, SolveLimits};
use impact_solver::rng::SplitMix64;
use impact_solver::Vector3;

const TOLERANCE: f64 = 1e-8;

/// Slave nodes `0..n` each pressed 0-1 mm into one of a strip of faces whose nodes are shared,
/// so neighbouring contacts couple through the Delassus matrix.
fn strip(n: usize, friction: f64) -> ContactProblem {
    let mut rng = SplitMix64::new(11);
    let faces = n / 2;
    let mut x = Vec::new();
    for k in 0..n {
        x.push(Vector3::new(
            k as f64 * 0.5 + 0.1,
            0.3,
            -1e-3 * rng.next_f64(),
        ));
    }
    let base = x.len() as u32;
    for k in 0..=faces + 1 {
        x.push(Vector3::new(k as f64, 0.0, 0.0));
        x.push(Vector3::new(k as f64, 1.0, 0.0));
    }
    let inverse_mass: Vec<Vector3<f64>> = (0..x.len())
        .map(|_| Vector3::repeat(rng.uniform(0.5, 2.0)))
        .collect();
    let constraints: Vec<ContactConstraint> = (0..n)
        .map(|k| {
            let f = (k / 2) as u32;
            ContactConstraint {
                slave: k as u32,
                face: [base + 2 * f, base + 2 * f + 2, base + 2 * f + 1],
                weights: [0.4, 0.3, 0.3],
                normal: Vector3::z(),
                friction,
                allowance: 0.0,
            }
        })
        .collect();
    // A tangential push on every slave, so friction has something to resist.
    for xk in x.iter_mut().take(n) {
        xk.x -= 2e-4;
    }
    ContactProblem::from_constraints(&constraints, &inverse_mass, 1e-2, &x, "strip".into())
}

fn problems() -> Vec<(String, ContactProblem)> {
    let mut list = vec![
        ("strip-frictionless".to_string(), strip(64, 0.0)),
        ("strip-mu0.3".to_string(), strip(64, 0.3)),
    ];
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../references/contact-problems");
    for name in ["rover1039", "oneobject-i1028-138"] {
        let path = dir.join(format!("{name}.json"));
        let (p, _) = read_problem(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (committed data: restore the checkout)",
                path.display()
            )
        });
        list.push((name.to_string(), p));
    }
    list
}

/// The solvers compared, built by the registry as the stepper and the harness build them.
fn solvers() -> Vec<Box<dyn ContactSolver + Send>> {
    [
        SolverKind::GaussSeidelThesis,
        SolverKind::GaussSeidelExact,
        SolverKind::ConicCoulomb,
    ]
    .into_iter()
    .map(SolverKind::build)
    .collect()
}

fn contact_solvers(c: &mut Criterion) {
    let limits = SolveLimits {
        tolerance: TOLERANCE,
        max_iterations: 20_000,
        time_limit: None,
    };
    for (name, problem) in problems() {
        let mut group = c.benchmark_group(format!("contact_solvers/{name}"));
        for mut solver in solvers() {
            let report = solver.solve(&problem, &limits).expect("solves");
            eprintln!(
                "{name:22} {:20} {:>14} {:>6} it  error {:.2e}",
                solver.name(),
                report.status.label(),
                report.iterations,
                natural_map_error(&problem, &report.r).relative
            );
            group.bench_function(solver.name(), |b| {
                b.iter(|| black_box(solver.solve(black_box(&problem), &limits).unwrap()))
            });
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2));
    targets = contact_solvers
}
criterion_main!(benches);
