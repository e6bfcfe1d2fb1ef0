//! Vertex-face continuous collision detection (`contact::ccd::vertex_face_ccd`), per query.
//!
//! A fixed, seeded set of 10 000 queries, half of them hits and half misses (a node crossing the
//! face's plane outside the triangle, or not reaching it), on faces of unit size that move,
//! turn and deform over the step: the crossing families of the shared generator
//! (`references/queries/sweep.rs`). Two measurements:
//! - per query, individually: each query is timed over 5 repetitions of a batch of 8 calls
//!   (the batch amortises the clock's own cost), its cost is the fastest repetition; the median,
//!   p99 and maximum over the set are printed (`eprintln`), also separately for hits and misses;
//! - criterion: `ccd/vertex_face/{mixed,hits,misses}` run through the whole set, reported in
//!   queries per second (`1e9 / throughput` is the mean cost in ns).
//!
//! Run with `cargo bench -p impact-solver --bench ccd` (about 20 s).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use impact_references::queries::Family;
use impact_solver::contact::ccd::vertex_face_ccd;
use impact_solver::rng::SplitMix64;

const QUERIES: usize = 10_000;
const TOL: f64 = 1e-9;
const REPETITIONS: usize = 5;
const BATCH: u32 = 8;

/// A query of the shared generator (`impact_references::queries::sweep::crossing`).
struct Query(impact_references::queries::Query);

impl Query {
    fn run(&self) -> Option<f64> {
        let [a, b, c] = &self.0.face;
        vertex_face_ccd(&self.0.node, [a, b, c], TOL).map(|hit| hit.t)
    }
}

/// `QUERIES / 2` hits and as many misses, as classified by the CCD itself.
fn queries() -> (Vec<Query>, Vec<Query>) {
    let mut rng = SplitMix64::new(0xBE7C_CCD0);
    let (mut hits, mut misses) = (Vec::new(), Vec::new());
    while hits.len() < QUERIES / 2 || misses.len() < QUERIES / 2 {
        let want_hit =
            hits.len() < QUERIES / 2 && (misses.len() >= QUERIES / 2 || rng.next_f64() < 0.5);
        let family = if want_hit {
            Family::CrossingHit
        } else {
            Family::CrossingMiss
        };
        let q = Query(family.generate(&mut rng));
        match (q.run().is_some(), want_hit) {
            (true, true) => hits.push(q),
            (false, false) => misses.push(q),
            _ => {}
        }
    }
    (hits, misses)
}

/// The cost of each query in ns: the fastest of `REPETITIONS` timings of `BATCH` calls.
fn per_query_ns(set: &[Query]) -> Vec<f64> {
    set.iter()
        .map(|q| {
            (0..REPETITIONS)
                .map(|_| {
                    let start = Instant::now();
                    for _ in 0..BATCH {
                        black_box(black_box(q).run());
                    }
                    start.elapsed().as_nanos() as f64 / BATCH as f64
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

fn report(label: &str, mut ns: Vec<f64>) {
    ns.sort_by(f64::total_cmp);
    let at = |q: f64| ns[((ns.len() - 1) as f64 * q).round() as usize];
    eprintln!(
        "ccd {label:>6} ({} queries): p10 {:.0} ns, p25 {:.0} ns, median {:.0} ns, \
         p99 {:.0} ns, max {:.0} ns",
        ns.len(),
        at(0.1),
        at(0.25),
        at(0.5),
        at(0.99),
        at(1.0)
    );
}

fn ccd(c: &mut Criterion) {
    let (hits, misses) = queries();
    // Warm up caches and branch predictors once before the individual timings.
    for q in hits.iter().chain(&misses) {
        black_box(q.run());
    }
    let hit_ns = per_query_ns(&hits);
    let miss_ns = per_query_ns(&misses);
    report("hits", hit_ns.clone());
    report("misses", miss_ns.clone());
    report("all", hit_ns.into_iter().chain(miss_ns).collect());

    let mixed: Vec<&Query> = hits.iter().zip(&misses).flat_map(|(h, m)| [h, m]).collect();
    let mut group = c.benchmark_group("ccd/vertex_face");
    group
        .sample_size(30)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(mixed.len() as u64));
    group.bench_function("mixed", |b| {
        b.iter(|| {
            mixed
                .iter()
                .filter(|q| black_box(q).run().is_some())
                .count()
        })
    });
    for (label, set) in [("hits", &hits), ("misses", &misses)] {
        group.throughput(Throughput::Elements(set.len() as u64));
        group.bench_function(label, |b| {
            b.iter(|| set.iter().filter(|q| black_box(q).run().is_some()).count())
        });
    }
    group.finish();
}

criterion_group!(benches, ccd);
criterion_main!(benches);
