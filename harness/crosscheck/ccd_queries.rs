//! Point-triangle continuous collision detection queries for a cross-check of our vertex-face
//! CCD (`impact_solver::contact::ccd::vertex_face_ccd`) against an independent implementation
//! (ipctk's Tight-Inclusion point-triangle CCD): queries recorded from real runs of catalogue
//! cases, and random ones built to be hard, with our answers.
//!
//! A query is the straight-line motion over one step of a point `v` and a triangle
//! `(f0, f1, f2)`, given by the 8 positions in ipctk's argument order
//! `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1` (`t0`: start of the step, `t1`: its
//! end; `f0..f2` in the face's node order).
//!
//! # File format (`CCDQ0001`)
//!
//! Little-endian, packed, no padding:
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"CCDQ0001"` |
//! | 8 | 8 | `u64` number of queries `n` |
//! | 16 | `193 n` | per query: `u8` source code ([`QuerySource::code`]), then 24 `f64`: the 8 points above, `x y z` each |
//!
//! In Python: `numpy.fromfile(path, dtype=numpy.dtype([('source', 'u1'), ('x', '<f8', (8, 3))]),
//! offset=16)` (the structured dtype is packed, itemsize 193).

use std::collections::HashSet;
use std::path::Path;
use std::time::Instant;

use impact_solver::contact::ccd::{vertex_face_ccd, Trajectory};
use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::rng::SplitMix64;
use impact_solver::scene::{build_problem, Analysis};
use impact_solver::Vector3;

/// The file's first 8 bytes.
pub const MAGIC: &[u8; 8] = b"CCDQ0001";
/// Bytes before the first query.
pub const HEADER_BYTES: usize = 16;
/// Bytes per query: the source code and 24 `f64`.
pub const QUERY_BYTES: usize = 1 + 24 * 8;

/// Where a query comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QuerySource {
    /// Recorded from `contact/spheres-headon` (code 0).
    Sphere,
    /// Recorded from `beam/drop-2ms` (code 1).
    Beam,
    /// Built by [`random_queries`] (code 2).
    Random,
}

impl QuerySource {
    pub const ALL: [QuerySource; 3] = [QuerySource::Sphere, QuerySource::Beam, QuerySource::Random];

    pub fn name(self) -> &'static str {
        match self {
            QuerySource::Sphere => "sphere",
            QuerySource::Beam => "beam",
            QuerySource::Random => "random",
        }
    }

    /// The byte stored in the file.
    pub fn code(self) -> u8 {
        match self {
            QuerySource::Sphere => 0,
            QuerySource::Beam => 1,
            QuerySource::Random => 2,
        }
    }

    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.code() == code)
    }
}

/// One point-triangle CCD query: `points` in ipctk's order
/// `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdQuery {
    pub source: QuerySource,
    pub points: [[f64; 3]; 8],
}

impl CcdQuery {
    /// The query of a node's and a face's trajectories.
    pub fn from_trajectories(
        source: QuerySource,
        node: &Trajectory,
        face: &[Trajectory; 3],
    ) -> Self {
        let p = |x: &Vector3<f64>| [x.x, x.y, x.z];
        Self {
            source,
            points: [
                p(&node.start),
                p(&face[0].start),
                p(&face[1].start),
                p(&face[2].start),
                p(&node.end),
                p(&face[0].end),
                p(&face[1].end),
                p(&face[2].end),
            ],
        }
    }

    /// The node's trajectory and the face's three.
    pub fn trajectories(&self) -> (Trajectory, [Trajectory; 3]) {
        let v = |i: usize| Vector3::from(self.points[i]);
        let t = |i: usize| Trajectory {
            start: v(i),
            end: v(i + 4),
        };
        (t(0), [t(1), t(2), t(3)])
    }

    /// The bit patterns of the points: equal exactly when the queries' geometry is.
    fn key(&self) -> [u64; 24] {
        let mut k = [0u64; 24];
        for (slot, x) in k.iter_mut().zip(self.points.iter().flatten()) {
            *slot = x.to_bits();
        }
        k
    }
}

/// Our answer: the step fraction of the first contact found by `vertex_face_ccd` with the
/// barycentric `tolerance` (the solver's detection passes `1e-9`), or `None`.
pub fn our_time_of_impact(q: &CcdQuery, tolerance: f64) -> Option<f64> {
    let (node, face) = q.trajectories();
    vertex_face_ccd(&node, [&face[0], &face[1], &face[2]], tolerance).map(|h| h.t)
}

/// What [`record_case`] recorded.
#[derive(Debug, Clone)]
pub struct Recording {
    /// The kept queries, in recording order.
    pub queries: Vec<CcdQuery>,
    /// Queries recorded by the run (every CCD call of detection in the recorded steps).
    pub recorded: usize,
    /// Of those, the distinct ones (exact duplicates removed).
    pub distinct: usize,
    /// Of the recorded ones, those our CCD reported a hit for.
    pub recorded_hits: usize,
    /// Steps the run took.
    pub steps: usize,
    /// Wall time of the run (s).
    pub wall_seconds: f64,
}

/// Runs the scene of the catalogue case `case_file` up to `end_time` (the rest of its explicit
/// settings kept), recording every CCD query of contact detection in every `every`-th step on
/// all its contact pairs, and keeps at most `max` distinct ones by even subsampling (see
/// [`record_case`]).
pub fn record_from_case(
    case_file: &Path,
    end_time: f64,
    every: usize,
    max: usize,
    source: QuerySource,
) -> Result<Vec<CcdQuery>, String> {
    record_case(case_file, end_time, every, max, source).map(|r| r.queries)
}

/// [`record_from_case`] with the counts and the run's wall time.
///
/// Exact duplicates (the same 8 points to the bit, as the two passes or consecutive steps can
/// repeat) are removed, first occurrence kept; if more than `max` distinct queries remain, the
/// ones at indices `floor(i n / max)`, `i = 0..max`, are kept (evenly spread over the run, in
/// recording order).
pub fn record_case(
    case_file: &Path,
    end_time: f64,
    every: usize,
    max: usize,
    source: QuerySource,
) -> Result<Recording, String> {
    let name = case_file.display();
    if every == 0 {
        return Err(format!("{name}: record every 0 steps: give 1 or more"));
    }
    if end_time.is_nan() || end_time <= 0.0 {
        return Err(format!("{name}: end time {end_time} s must be positive"));
    }
    let spec = crate::case_file::load_spec(case_file).map_err(|e| e.to_string())?;
    let mut scene = spec
        .scene
        .ok_or_else(|| format!("{name}: the case has no scene to record CCD queries from"))?;
    let mut settings = match &scene.analysis {
        Analysis::Explicit(s) => s.clone(),
        _ => {
            return Err(format!(
                "{name}: the scene's analysis is not explicit dynamics; CCD queries are recorded \
                 from explicit runs"
            ))
        }
    };
    settings.end_time = end_time;
    scene.analysis = Analysis::Explicit(settings.clone());
    if scene.contact.is_empty() {
        return Err(format!("{name}: the scene has no contact pair"));
    }
    for pair in &mut scene.contact {
        pair.record_ccd_every = Some(every);
    }
    let problem = build_problem(&scene).map_err(|e| format!("{name}: {e}"))?;
    let mut solver = ExplicitSolver::new(&problem, settings, OutputSettings::default())
        .map_err(|e| format!("{name}: {e}"))?;
    let started = Instant::now();
    let outcome = solver.run(&mut |_| {});
    let wall_seconds = started.elapsed().as_secs_f64();
    let summary = outcome.map_err(|e| format!("{name}: the run failed: {e}"))?;
    let recorded = solver.take_recorded_ccd_queries();
    let recorded_hits = recorded.iter().filter(|q| q.hit.is_some()).count();
    let mut seen = HashSet::new();
    let distinct: Vec<CcdQuery> = recorded
        .iter()
        .map(|r| CcdQuery::from_trajectories(source, &r.node, &r.face))
        .filter(|q| seen.insert(q.key()))
        .collect();
    Ok(Recording {
        queries: subsample(&distinct, max),
        recorded: recorded.len(),
        distinct: distinct.len(),
        recorded_hits,
        steps: summary.steps,
        wall_seconds,
    })
}

/// At most `max` of `items`, evenly spread, in order: indices `floor(i n / max)`.
fn subsample<T: Clone>(items: &[T], max: usize) -> Vec<T> {
    let n = items.len();
    if n <= max {
        return items.to_vec();
    }
    (0..max).map(|i| items[i * n / max].clone()).collect()
}

/// Writes `queries` to `path` in the `CCDQ0001` format (module documentation).
pub fn write_queries(path: &Path, queries: &[CcdQuery]) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(HEADER_BYTES + QUERY_BYTES * queries.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&(queries.len() as u64).to_le_bytes());
    for q in queries {
        bytes.push(q.source.code());
        for x in q.points.iter().flatten() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Reads a file written by [`write_queries`].
pub fn read_queries(path: &Path) -> Result<Vec<CcdQuery>, String> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    if bytes.len() < HEADER_BYTES {
        return Err(format!(
            "{name}: truncated: {} bytes, shorter than the {HEADER_BYTES}-byte header",
            bytes.len()
        ));
    }
    if &bytes[..8] != MAGIC {
        return Err(format!(
            "{name}: bad magic {:?}: not a CCD query file (expected {:?})",
            String::from_utf8_lossy(&bytes[..8]),
            String::from_utf8_lossy(MAGIC)
        ));
    }
    let count = u64::from_le_bytes(bytes[8..16].try_into().expect("8 bytes"));
    let expected = usize::try_from(count)
        .ok()
        .and_then(|c| c.checked_mul(QUERY_BYTES))
        .and_then(|b| b.checked_add(HEADER_BYTES));
    match expected {
        Some(e) if e == bytes.len() => {}
        Some(e) if e > bytes.len() => {
            return Err(format!(
                "{name}: truncated: the header announces {count} queries ({e} bytes), the file \
                 has {} bytes",
                bytes.len()
            ))
        }
        Some(e) => {
            return Err(format!(
                "{name}: {} bytes after the {count} queries the header announces",
                bytes.len() - e
            ))
        }
        None => return Err(format!("{name}: impossible query count {count}")),
    }
    bytes[HEADER_BYTES..]
        .chunks_exact(QUERY_BYTES)
        .enumerate()
        .map(|(i, record)| {
            let source = QuerySource::from_code(record[0]).ok_or_else(|| {
                format!("{name}: query {i} has unknown source code {}", record[0])
            })?;
            let mut points = [[0.0; 3]; 8];
            for (k, chunk) in record[1..].chunks_exact(8).enumerate() {
                points[k / 3][k % 3] = f64::from_le_bytes(chunk.try_into().expect("8 bytes"));
            }
            Ok(CcdQuery { source, points })
        })
        .collect()
}

/// The families of [`random_queries`], in the order of their share of the queries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RandomFamily {
    Constructed,
    Endpoint,
    Parallel,
    Box,
    Sliver,
}

/// The family of query `i`: a fixed cycle of 20 gives 8 constructed, 2 endpoint, 3 parallel,
/// 4 box and 3 sliver queries, interleaved so that any prefix holds a mix.
pub fn random_family(i: usize) -> RandomFamily {
    use RandomFamily::*;
    const CYCLE: [RandomFamily; 20] = [
        Constructed,
        Parallel,
        Sliver,
        Box,
        Constructed,
        Endpoint,
        Constructed,
        Sliver,
        Parallel,
        Constructed,
        Box,
        Constructed,
        Box,
        Endpoint,
        Constructed,
        Parallel,
        Constructed,
        Box,
        Sliver,
        Constructed,
    ];
    CYCLE[i % CYCLE.len()]
}

/// `n` random queries, deterministic for a `seed`, mixed so that about half are hits and many
/// are hard. Query `i` belongs to family [`random_family`]`(i)`:
///
/// - **(a) constructed** (40 %): a random non-degenerate triangle at `t0` (size `s` log-uniform
///   in `[0.01, 1]`, centre in `[-1, 1]^3`) and at `t1` (moved by up to `s`, each corner
///   perturbed by up to `0.3 s`, so it translates, turns and deforms), a contact time `t*`
///   uniform in `[0, 1]`, barycentric weights `w` of the contact point `q = sum w_k f_k(t*)`
///   on the interpolated triangle, a random node displacement `d` (length `s` times
///   log-uniform in `[0.01, 2]`), and `v_t0 = q - t* d`, `v_t1 = q + (1 - t*) d`. The weights
///   are: well inside (each >= 0.05, 40 %), exactly on an edge (one weight 0, 10 %), exactly
///   at a corner (5 %), outside one edge (the edge's weight `-delta`, 30 %) or beyond a corner
///   (`(1 + delta, -delta/2, -delta/2)`, 15 %) with `delta` drawn from `1e-3, 1e-6, 1e-9`:
///   `delta` is a barycentric distance, `delta` times the height of the triangle over that
///   edge. Outside points are near misses at `t*`, though the node may still meet the
///   triangle at another root of the coplanarity cubic.
/// - **(b) endpoint** (10 %): as (a) with `t*` exactly `0` or `1` (the node starts, or ends,
///   on the face; the plane is met only to rounding) and weights inside (40 %), on an edge
///   (20 %) or outside an edge by `delta` (40 %).
/// - **(c) parallel** (15 %): the triangle translates rigidly (or stays), and the node moves
///   parallel to its plane, in it or at an offset of `0`, `1e-9 s`, `1e-6 s` or `1e-3 s` along
///   the normal, from a point of the plane to another (weights in `[-0.5, 1.5]`), so the node may
///   enter, cross, stay inside or stay outside the triangle. At offset 0 the coplanarity cubic
///   vanishes identically: in-plane motion.
/// - **(d) box** (20 %): all 8 points uniform in the unit box; mostly misses.
/// - **(e) sliver** (15 %): as (a) with weights inside (45 %), on an edge (20 %) or outside
///   an edge by `delta` (35 %, the other two weights equal), on a
///   near-degenerate triangle: a needle (two corners `eps s` apart) or a cap (one corner
///   `eps s` off the line of the other two, between them), `eps` in `1e-3, 1e-6, 1e-9`,
///   translated rigidly between `t0` and `t1`.
pub fn random_queries(n: usize, seed: u64) -> Vec<CcdQuery> {
    let mut rng = SplitMix64::new(seed);
    (0..n)
        .map(|i| {
            let points = match random_family(i) {
                RandomFamily::Constructed => constructed(&mut rng),
                RandomFamily::Endpoint => endpoint(&mut rng),
                RandomFamily::Parallel => parallel(&mut rng),
                RandomFamily::Box => {
                    let mut p = [[0.0; 3]; 8];
                    for x in p.iter_mut().flatten() {
                        *x = rng.next_f64();
                    }
                    p
                }
                RandomFamily::Sliver => sliver(&mut rng),
            };
            CcdQuery {
                source: QuerySource::Random,
                points,
            }
        })
        .collect()
}

type V = Vector3<f64>;
type Triangle = [V; 3];

const DELTAS: [f64; 3] = [1e-3, 1e-6, 1e-9];

fn pick<T: Copy>(rng: &mut SplitMix64, items: &[T]) -> T {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

fn log_uniform(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    (rng.uniform(lo.ln(), hi.ln())).exp()
}

/// Uniform in the ball of radius `r`.
fn in_ball(rng: &mut SplitMix64, r: f64) -> V {
    loop {
        let v = V::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        if v.norm_squared() <= 1.0 {
            return v * r;
        }
    }
}

/// A unit vector, uniform on the sphere.
fn direction(rng: &mut SplitMix64) -> V {
    loop {
        let v = in_ball(rng, 1.0);
        let n = v.norm();
        if n > 0.1 {
            return v / n;
        }
    }
}

/// Twice the area over the squared longest edge: 0 for a degenerate triangle, `sqrt(3)/2` for
/// an equilateral one.
fn shape_quality(t: &Triangle) -> f64 {
    let area2 = (t[1] - t[0]).cross(&(t[2] - t[0])).norm();
    let longest = [(t[1] - t[0]), (t[2] - t[1]), (t[0] - t[2])]
        .iter()
        .map(|e| e.norm_squared())
        .fold(0.0, f64::max);
    area2 / longest
}

fn lerp(a: &Triangle, b: &Triangle, t: f64) -> Triangle {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

/// A well-shaped triangle at `t0` and `t1` (also at every time between, checked at a few), and
/// its size.
fn moving_triangle(rng: &mut SplitMix64) -> (Triangle, Triangle, f64) {
    loop {
        let s = log_uniform(rng, 0.01, 1.0);
        let centre = V::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        let t0 = [0; 3].map(|_| centre + in_ball(rng, s));
        let shift = in_ball(rng, s);
        let t1 = t0.map(|x| x + shift + in_ball(rng, 0.3 * s));
        let good = [0.0, 0.25, 0.5, 0.75, 1.0]
            .iter()
            .all(|&t| shape_quality(&lerp(&t0, &t1, t)) > 0.1);
        if good {
            return (t0, t1, s);
        }
    }
}

/// Barycentric weights well inside: each at least 0.05.
fn inside_weights(rng: &mut SplitMix64) -> [f64; 3] {
    loop {
        let (a, b) = (rng.next_f64(), rng.next_f64());
        let w = [a, b, 1.0 - a - b];
        if w.iter().all(|&x| x >= 0.05) {
            return w;
        }
    }
}

/// Weights exactly on a random edge: one weight 0, the others summing to 1.
fn edge_weights(rng: &mut SplitMix64) -> [f64; 3] {
    let k = pick(rng, &[0usize, 1, 2]);
    let a = rng.uniform(0.05, 0.95);
    let mut w = [0.0; 3];
    w[(k + 1) % 3] = a;
    w[(k + 2) % 3] = 1.0 - a;
    w
}

/// Weights outside a random edge (the one opposite corner `k`) by `delta`: `w_k = -delta`.
fn outside_edge(rng: &mut SplitMix64, delta: f64) -> [f64; 3] {
    let k = pick(rng, &[0usize, 1, 2]);
    let a = rng.uniform(0.05, 0.95);
    let mut w = [0.0; 3];
    w[k] = -delta;
    w[(k + 1) % 3] = a * (1.0 + delta);
    w[(k + 2) % 3] = (1.0 - a) * (1.0 + delta);
    w
}

/// Weights of (a): inside, on an edge, at a corner, outside an edge or beyond a corner.
fn constructed_weights(rng: &mut SplitMix64) -> [f64; 3] {
    let u = rng.next_f64();
    let k = pick(rng, &[0usize, 1, 2]);
    let delta = pick(rng, &DELTAS);
    let mut w = [0.0; 3];
    if u < 0.40 {
        inside_weights(rng)
    } else if u < 0.50 {
        edge_weights(rng)
    } else if u < 0.55 {
        w[k] = 1.0;
        w
    } else if u < 0.85 {
        outside_edge(rng, delta)
    } else {
        w[k] = 1.0 + delta;
        w[(k + 1) % 3] = -delta / 2.0;
        w[(k + 2) % 3] = -delta / 2.0;
        w
    }
}

/// The query of a triangle moving from `t0` to `t1` and a node that is at `sum w_k f_k(t*)`
/// at `t*`, moving by `d` over the step.
fn through(t0: &Triangle, t1: &Triangle, t_star: f64, w: [f64; 3], d: V) -> [[f64; 3]; 8] {
    let at = lerp(t0, t1, t_star);
    let q = at[0] * w[0] + at[1] * w[1] + at[2] * w[2];
    let v0 = q - d * t_star;
    let v1 = q + d * (1.0 - t_star);
    pack(&v0, t0, &v1, t1)
}

fn pack(v0: &V, t0: &Triangle, v1: &V, t1: &Triangle) -> [[f64; 3]; 8] {
    let p = |x: &V| [x.x, x.y, x.z];
    [
        p(v0),
        p(&t0[0]),
        p(&t0[1]),
        p(&t0[2]),
        p(v1),
        p(&t1[0]),
        p(&t1[1]),
        p(&t1[2]),
    ]
}

fn node_displacement(rng: &mut SplitMix64, s: f64) -> V {
    direction(rng) * s * log_uniform(rng, 0.01, 2.0)
}

fn constructed(rng: &mut SplitMix64) -> [[f64; 3]; 8] {
    let (t0, t1, s) = moving_triangle(rng);
    let t_star = rng.next_f64();
    let w = constructed_weights(rng);
    let d = node_displacement(rng, s);
    through(&t0, &t1, t_star, w, d)
}

fn endpoint(rng: &mut SplitMix64) -> [[f64; 3]; 8] {
    let (t0, t1, s) = moving_triangle(rng);
    let t_star = pick(rng, &[0.0, 1.0]);
    let u = rng.next_f64();
    let w = if u < 0.4 {
        inside_weights(rng)
    } else if u < 0.6 {
        edge_weights(rng)
    } else {
        let delta = pick(rng, &DELTAS);
        outside_edge(rng, delta)
    };
    let d = node_displacement(rng, s);
    through(&t0, &t1, t_star, w, d)
}

fn parallel(rng: &mut SplitMix64) -> [[f64; 3]; 8] {
    let (t0, _, s) = moving_triangle(rng);
    let shift = if rng.next_f64() < 0.3 {
        V::zeros()
    } else {
        in_ball(rng, s)
    };
    let t1 = t0.map(|x| x + shift);
    let normal = (t0[1] - t0[0]).cross(&(t0[2] - t0[0])).normalize();
    let offset = s * pick(rng, &[0.0, 0.0, 1e-9, 1e-6, 1e-3]);
    let weights = |rng: &mut SplitMix64| {
        let (a, b) = (rng.uniform(-0.5, 1.5), rng.uniform(-0.5, 1.5));
        [1.0 - a - b, a, b]
    };
    let (w0, w1) = (weights(rng), weights(rng));
    let point = |t: &Triangle, w: [f64; 3]| t[0] * w[0] + t[1] * w[1] + t[2] * w[2];
    let v0 = point(&t0, w0) + normal * offset;
    let v1 = point(&t1, w1) + normal * offset;
    pack(&v0, &t0, &v1, &t1)
}

fn sliver(rng: &mut SplitMix64) -> [[f64; 3]; 8] {
    let s = log_uniform(rng, 0.01, 1.0);
    let eps = pick(rng, &DELTAS);
    let centre = V::new(
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
    );
    let a = centre + in_ball(rng, s);
    let along = direction(rng);
    let b = a + along * s * rng.uniform(0.5, 1.5);
    let across = {
        let mut u = direction(rng);
        u -= along * along.dot(&u);
        u.normalize()
    };
    let c = if rng.next_f64() < 0.5 {
        // Needle: c next to b.
        b + across * eps * s
    } else {
        // Cap: c just off the segment ab.
        a + (b - a) * rng.uniform(0.1, 0.9) + across * eps * s
    };
    // Random corner order, so the short edge is not always the same one.
    let mut t0 = [a, b, c];
    let r = (rng.next_u64() % 3) as usize;
    t0.rotate_left(r);
    let shift = in_ball(rng, s);
    let t1 = t0.map(|x| x + shift);
    let t_star = rng.next_f64();
    let u = rng.next_f64();
    let w = if u < 0.45 {
        inside_weights(rng)
    } else if u < 0.65 {
        edge_weights(rng)
    } else {
        let k = pick(rng, &[0usize, 1, 2]);
        let delta = pick(rng, &DELTAS);
        let mut w = [0.5 * (1.0 + delta); 3];
        w[k] = -delta;
        w
    };
    let d = node_displacement(rng, s);
    through(&t0, &t1, t_star, w, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("ccd-queries-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn queries_round_trip_bitwise_through_the_file() {
        let mut queries = random_queries(50, 7);
        queries[3].source = QuerySource::Sphere;
        queries[4].source = QuerySource::Beam;
        queries[5].points[2][1] = -0.0;
        queries[6].points[7][2] = f64::MIN_POSITIVE / 4.0;
        let path = temp("round-trip.ccdq");
        write_queries(&path, &queries).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), 16 + 193 * 50);
        assert_eq!(&bytes[..8], b"CCDQ0001");
        assert_eq!(bytes[16 + 193 * 4], 1, "source code of query 4");
        let back = read_queries(&path).unwrap();
        assert_eq!(back.len(), queries.len());
        for (a, b) in queries.iter().zip(&back) {
            assert_eq!(a.source, b.source);
            assert_eq!(a.key(), b.key());
        }
        write_queries(&path, &[]).unwrap();
        assert!(read_queries(&path).unwrap().is_empty());
    }

    #[test]
    fn bad_magic_and_truncated_files_are_refused_naming_the_file() {
        let queries = random_queries(3, 1);
        let path = temp("broken.ccdq");
        write_queries(&path, &queries).unwrap();
        let good = std::fs::read(&path).unwrap();

        let mut bad = good.clone();
        bad[..8].copy_from_slice(b"CCDQ0002");
        std::fs::write(&path, &bad).unwrap();
        let e = read_queries(&path).unwrap_err();
        assert!(e.contains("broken.ccdq") && e.contains("bad magic"), "{e}");

        std::fs::write(&path, &good[..good.len() - 1]).unwrap();
        let e = read_queries(&path).unwrap_err();
        assert!(e.contains("broken.ccdq") && e.contains("truncated"), "{e}");

        std::fs::write(&path, &good[..10]).unwrap();
        let e = read_queries(&path).unwrap_err();
        assert!(e.contains("broken.ccdq") && e.contains("truncated"), "{e}");

        let mut extra = good.clone();
        extra.push(0);
        std::fs::write(&path, &extra).unwrap();
        let e = read_queries(&path).unwrap_err();
        assert!(
            e.contains("broken.ccdq") && e.contains("1 bytes after"),
            "{e}"
        );

        let mut unknown = good.clone();
        unknown[16] = 9;
        std::fs::write(&path, &unknown).unwrap();
        let e = read_queries(&path).unwrap_err();
        assert!(e.contains("unknown source code 9"), "{e}");

        let e = read_queries(&temp("missing.ccdq")).unwrap_err();
        assert!(
            e.contains("missing.ccdq") && e.contains("cannot read"),
            "{e}"
        );
    }

    #[test]
    fn random_queries_are_deterministic_and_about_half_hits() {
        let a = random_queries(2000, 42);
        let b = random_queries(2000, 42);
        assert!(a.iter().zip(&b).all(|(x, y)| x.key() == y.key()));
        assert_ne!(random_queries(10, 43)[0].key(), a[0].key());
        let hits = a
            .iter()
            .filter(|q| our_time_of_impact(q, 1e-9).is_some())
            .count();
        let fraction = hits as f64 / a.len() as f64;
        let by_family = |f: RandomFamily| {
            let (n, h) = a
                .iter()
                .enumerate()
                .filter(|(i, _)| random_family(*i) == f)
                .fold((0, 0), |(n, h), (_, q)| {
                    (
                        n + 1,
                        h + usize::from(our_time_of_impact(q, 1e-9).is_some()),
                    )
                });
            format!("{f:?} {h}/{n}")
        };
        eprintln!(
            "hit fraction {fraction:.3}: {}",
            [
                RandomFamily::Constructed,
                RandomFamily::Endpoint,
                RandomFamily::Parallel,
                RandomFamily::Box,
                RandomFamily::Sliver
            ]
            .map(by_family)
            .join(", ")
        );
        assert!((0.2..=0.8).contains(&fraction), "hit fraction {fraction}");
    }

    #[test]
    fn a_constructed_hit_well_inside_is_found_at_its_time() {
        let mut rng = SplitMix64::new(5);
        let mut checked = 0;
        for _ in 0..200 {
            let (t0, t1, s) = moving_triangle(&mut rng);
            let t_star = rng.uniform(0.05, 0.95);
            let w = inside_weights(&mut rng);
            // Crossing the plane steeply: along the normal at t*, plus a tangential part.
            let at = lerp(&t0, &t1, t_star);
            let normal = (at[1] - at[0]).cross(&(at[2] - at[0])).normalize();
            let d = (normal * 0.5 + direction(&mut rng) * 0.2) * s;
            let q = CcdQuery {
                source: QuerySource::Random,
                points: through(&t0, &t1, t_star, w, d),
            };
            // The node may meet the deforming triangle earlier at another root; the
            // construction's contact is the answer when it is the first.
            let t = our_time_of_impact(&q, 1e-9).expect("a hit well inside is found");
            if t < t_star - 1e-6 {
                continue;
            }
            assert!((t - t_star).abs() < 1e-9, "t {t} against t* {t_star}");
            checked += 1;
        }
        assert!(checked > 150, "{checked}");
    }

    #[test]
    fn subsampling_is_even_and_in_order() {
        let items: Vec<usize> = (0..10).collect();
        assert_eq!(subsample(&items, 4), vec![0, 2, 5, 7]);
        assert_eq!(subsample(&items, 20), items);
        assert!(subsample(&items, 0).is_empty());
    }

    /// The recordings of the issue: `cargo test --release --lib crosscheck::ccd_queries --
    /// --ignored --nocapture`; writes `target/ccd-queries/<source>.ccdq`.
    #[test]
    #[ignore = "runs two catalogue cases (the beam one for minutes)"]
    fn record_the_catalogue_cases() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let out = root.join("target/ccd-queries");
        std::fs::create_dir_all(&out).unwrap();
        let runs = [
            (
                "cases/contact/spheres-headon.yaml",
                9e-4,
                QuerySource::Sphere,
            ),
            ("cases/beam/drop-2ms.yaml", 3e-4, QuerySource::Beam),
        ];
        for (file, end, source) in runs {
            let every: usize = std::env::var("CCD_EVERY")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(1);
            let r = record_case(&root.join(file), end, every, 1000, source).unwrap();
            let hits = r
                .queries
                .iter()
                .filter(|q| our_time_of_impact(q, 1e-9).is_some())
                .count();
            eprintln!(
                "{file} to {end:e} s, every {every}: {} steps in {:.1} s; {} queries recorded \
                 ({} hits, {:.3}), {} distinct; kept {} ({} hits, {:.3})",
                r.steps,
                r.wall_seconds,
                r.recorded,
                r.recorded_hits,
                r.recorded_hits as f64 / r.recorded.max(1) as f64,
                r.distinct,
                r.queries.len(),
                hits,
                hits as f64 / r.queries.len().max(1) as f64
            );
            write_queries(&out.join(format!("{}.ccdq", source.name())), &r.queries).unwrap();
        }
        let random = random_queries(1500, 2024);
        write_queries(&out.join("random.ccdq"), &random).unwrap();
    }
}
