//! Stress update plus internal-force assembly, `Model::internal_forces`, per element and call.
//!
//! Benchmarks are named `internal_force/<material>/<mesh>/<threads>t`, e.g.
//! `internal_force/linear_elastic/480k/1t`, and report elements per second (criterion's
//! `Throughput::Elements`), so `1e9 / throughput` is the cost in ns per element per step.
//! Meshes are Freudenthal-Kuhn boxes of 60 000 and 480 000 tetrahedra with a smooth
//! displacement field of amplitude 1e-4 (strains of order 1e-4, so every stress is non-zero).
//! Each thread count runs in its own rayon pool; before timing, the bench checks that the forces
//! are bitwise identical on 1 and 2 threads (the assembly's determinism guarantee).
//!
//! Run with `cargo bench -p impact-solver --bench internal_force`; the whole bench takes about
//! a minute on two cores. It also prints the model's memory per element and the fraction of
//! nodes whose force goes through the assembly's slot buffer, per thread count. Read the medians
//! (`target/criterion/internal_force/*/new/estimates.json`); on a shared two-core machine another
//! busy process shows up as two-thread times close to the one-thread ones, so rerun then.

// Benchmark code: an `unwrap` that fails stops the benchmark (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, BoxSpec};
use impact_solver::model::{ForceAssembler, Model};
use impact_solver::Vector3;

const CONCRETE: IsotropicElastic = IsotropicElastic {
    density: 2300.0,
    youngs_modulus: 30e9,
    poisson_ratio: 0.2,
};

/// `(label, divisions)`: `6 nx ny nz` tetrahedra on a box of 1 cm cells.
const MESHES: [(&str, [usize; 3]); 2] = [("60k", [40, 25, 10]), ("480k", [80, 50, 20])];

const THREADS: [usize; 2] = [1, 2];

fn model(divisions: [usize; 3], material: MaterialModel) -> Model {
    let mesh = box_mesh(&BoxSpec {
        origin: [0.0; 3],
        size: divisions.map(|n| 0.01 * n as f64),
        divisions,
        mirror: Vec::new(),
    });
    Model::new(vec![("box".to_string(), mesh, material)]).expect("box meshes are valid")
}

/// A smooth, non-trivial displacement field: stretch, shear and some rotation everywhere.
fn displacement(model: &Model) -> Vec<Vector3<f64>> {
    model
        .reference
        .iter()
        .map(|x| {
            1e-4 * Vector3::new(
                (3.0 * x.x + x.y).sin() + 0.5 * x.z,
                (2.0 * x.y + x.z).cos() - 0.3 * x.x,
                (x.x + 2.0 * x.z).sin() + 0.2 * x.y,
            )
        })
        .collect()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn internal_force(c: &mut Criterion) {
    let pools: Vec<_> = THREADS.iter().map(|&t| (t, pool(t))).collect();
    let mut group = c.benchmark_group("internal_force");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for (label, divisions) in MESHES {
        for material in [
            MaterialModel::LinearElastic(CONCRETE),
            MaterialModel::SaintVenantKirchhoff(CONCRETE),
        ] {
            let model = model(divisions, material);
            let u = displacement(&model);
            let mut f = vec![Vector3::zeros(); model.node_count()];
            let n = model.element_count();
            if matches!(material, MaterialModel::LinearElastic(_)) {
                eprintln!("mesh {label}: {n} elements, {} nodes", model.node_count());
                // The assembly's chunking, and so its slot buffer, follows the thread count.
                let ranges: Vec<_> = model.bodies.iter().map(|b| b.elements.clone()).collect();
                for (threads, pool) in &pools {
                    let (bytes, shared) = pool.install(|| {
                        assert_eq!(model.internal_forces(&u, &mut f).unwrap(), None);
                        let assembler =
                            ForceAssembler::new(&model.tets, model.node_count(), &ranges);
                        (
                            model.bytes_per_element(),
                            assembler.shared_fraction(model.node_count()),
                        )
                    });
                    eprintln!(
                        "  {threads} thread(s): {bytes:.1} bytes per element, \
                         shared-node fraction {shared:.3}"
                    );
                }
            }
            // Determinism: one and two threads give bitwise identical forces.
            let forces: Vec<Vec<u64>> = pools
                .iter()
                .map(|(_, p)| {
                    let mut f = vec![Vector3::zeros(); model.node_count()];
                    assert_eq!(
                        p.install(|| model.internal_forces(&u, &mut f).unwrap()),
                        None
                    );
                    assert!(f.iter().any(|x| x.norm() > 0.0));
                    f.iter()
                        .flat_map(|x| x.iter().map(|c| c.to_bits()))
                        .collect()
                })
                .collect();
            assert!(
                forces.windows(2).all(|w| w[0] == w[1]),
                "forces differ between thread counts"
            );

            group.throughput(Throughput::Elements(n as u64));
            for (threads, pool) in &pools {
                let id = format!("{}/{label}/{threads}t", material.name());
                group.bench_function(id, |b| {
                    pool.install(|| {
                        b.iter(|| black_box(model.internal_forces(black_box(&u), &mut f)))
                    })
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, internal_force);
criterion_main!(benches);
