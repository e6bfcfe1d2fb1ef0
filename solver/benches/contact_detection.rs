//! Cost of one detection pass (`contact::detection::detect`) against the number of slave
//! boundary nodes, and the contact share of a sphere-impact run.
//!
//! Detection: two stacked blocks with non-matching meshes (n x n x 2 cells below, (n-1) x
//! (n-1) x 2 above) whose upper block is pushed 1/10 of a cell into the lower one, so every
//! bottom node of the upper block penetrates and goes through local detection. The cost per
//! pass is reported against the slave surface's boundary node count: a grid broad phase makes it
//! grow linearly, where all-pairs testing would grow quadratically. The per-node costs are
//! printed (`eprintln`) after the criterion groups, with their ratio between the largest and the
//! smallest mesh.
//!
//! `contact/detect-kept` times the same pass with a [`Detector`] kept over the calls, as the
//! time stepper keeps one per pass: its grids of the master's layer elements and faces are
//! built once and refitted, so a call pays for the region where the bodies meet only.
//!
//! Run with `cargo bench -p impact-solver --bench contact_detection` (about a minute).

// Benchmark code: an `unwrap` that fails stops the benchmark (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use impact_solver::contact::detection::{detect, ContactSurface, DetectionSettings, Detector};
use impact_solver::contact::normals::NormalSettings;
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::{box_mesh, BoxSpec};
use impact_solver::model::Model;
use impact_solver::Vector3;

const SIZES: [usize; 4] = [8, 16, 32, 64];

struct Scene {
    model: Model,
    slave: ContactSurface,
    master: ContactSurface,
    x0: Vec<Vector3<f64>>,
    x1: Vec<Vector3<f64>>,
}

fn scene(n: usize) -> Scene {
    let material = MaterialModel::LinearElastic(IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1e9,
        poisson_ratio: 0.3,
    });
    let block = |z: f64, cells: usize| {
        box_mesh(&BoxSpec {
            origin: [0.0, 0.0, z],
            size: [1.0, 1.0, 0.1],
            divisions: [cells, cells, 2],
            mirror: Vec::new(),
        })
    };
    let model = Model::new(vec![
        ("lower".into(), block(0.0, n), material),
        ("upper".into(), block(0.1, n - 1), material),
    ])
    .unwrap();
    let slave = ContactSurface::new(&model, 1);
    let master = ContactSurface::new(&model, 0);
    let x0 = model.reference.to_vec();
    let mut x1 = x0.clone();
    let push = 0.1 / n as f64;
    for i in model.bodies[1].nodes.clone() {
        x1[i].z -= push;
    }
    Scene {
        model,
        slave,
        master,
        x0,
        x1,
    }
}

fn settings() -> DetectionSettings {
    DetectionSettings {
        tolerance: 1e-9,
        friction: 0.0,
        normals: NormalSettings::default(),
        release: f64::INFINITY,
    }
}

fn detection(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact/detect");
    group.sample_size(20);
    for n in SIZES {
        let s = scene(n);
        group.throughput(Throughput::Elements(s.slave.nodes.len() as u64));
        group.bench_with_input(
            BenchmarkId::from_parameter(s.slave.nodes.len()),
            &s,
            |b, s| {
                b.iter(|| {
                    detect(
                        &s.model,
                        &s.slave,
                        &s.master,
                        &s.x0,
                        black_box(&s.x1),
                        &settings(),
                    )
                })
            },
        );
    }
    group.finish();
    let mut group = c.benchmark_group("contact/detect-kept");
    group.sample_size(20);
    for n in SIZES {
        let s = scene(n);
        let mut detector = Detector::default();
        group.throughput(Throughput::Elements(s.slave.nodes.len() as u64));
        group.bench_with_input(
            BenchmarkId::from_parameter(s.slave.nodes.len()),
            &s,
            |b, s| {
                b.iter(|| {
                    detector.detect(
                        &s.model,
                        &s.slave,
                        &s.master,
                        &s.x0,
                        black_box(&s.x1),
                        &settings(),
                        None,
                    )
                })
            },
        );
    }
    group.finish();
    // Median of repeated passes per size, per slave boundary node.
    let mut per_node = Vec::new();
    for n in SIZES {
        let s = scene(n);
        let mut times: Vec<f64> = (0..15)
            .map(|_| {
                let t = Instant::now();
                let (c, _) = detect(&s.model, &s.slave, &s.master, &s.x0, &s.x1, &settings());
                black_box(c);
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let nodes = s.slave.nodes.len();
        eprintln!(
            "detect: {nodes:6} slave boundary nodes, {:5} master faces: median {:9.1} us per pass, {:6.1} ns per node",
            s.master.faces.len(),
            median * 1e6,
            median * 1e9 / nodes as f64
        );
        per_node.push(median / nodes as f64);
    }
    eprintln!(
        "detect: cost per node, largest over smallest mesh: {:.2} (1 = linear; {}x the nodes)",
        per_node[per_node.len() - 1] / per_node[0],
        (SIZES[SIZES.len() - 1] / SIZES[0]).pow(2)
    );
}

criterion_group!(benches, detection);
criterion_main!(benches);
