//! Random vertex-face continuous-collision queries, written once for the solver's CCD property
//! tests (`solver/tests/ccd.rs`) and the harness's cross-check against ipctk
//! (`harness/crosscheck/ccd_queries/`), with the proptest strategies built on them in
//! `strategies.rs` (feature `strategies`).
//!
//! A query is the straight-line motion over one step of a node and a triangle (thesis 7.4.4).
//! Each is a deterministic function of a [`SplitMix64`] stream and its [`Family`]: the
//! cross-check looks up ipctk's cached answers (`references/crosscheck/cache/`) by the exact bits
//! of the queries, so the arithmetic and the order of the draws below are part of the data and
//! must not change (the cache is rebuilt only with Python and ipctk, `impact-vv
//! crosscheck-refresh`). A sequence of queries cycles through a *mix* of families, one rng for
//! the whole sequence ([`queries`]).
//!
//! Three mixes are in use:
//! - [`CROSSCHECK_MIX`]: constructed contacts and near misses, endpoint, parallel, box and sliver
//!   families ([`hard`]), built so that about half are hits and many are hard;
//! - [`SWEEP_MIX`]: the CCD sweep against brute-force sampling ([`sweep`]): anything, coplanar at
//!   a chosen time, nearly parallel, tiny and large motions, in-plane motion, far from the
//!   origin, rigid and collapsing slivers;
//! - [`CROSSING_MIX`]: the CCD bench's plain hits and misses (`solver/benches/ccd.rs`).

pub mod hard;
pub mod sweep;

use impact_solver::contact::ccd::Trajectory;
use impact_solver::rng::SplitMix64;
use impact_solver::Vector3;

type V = Vector3<f64>;

/// One vertex-face CCD query: the node's and the face's motions over a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Query {
    /// The node's straight-line motion over the step (m).
    pub node: Trajectory,
    /// The face's three node motions, in the face's node order (m).
    pub face: [Trajectory; 3],
}

impl Query {
    /// The 8 positions in ipctk's argument order `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1,
    /// f2_t1` (the layout of the cross-check's query files).
    pub fn points(&self) -> [[f64; 3]; 8] {
        let p = |x: &V| [x.x, x.y, x.z];
        let [a, b, c] = &self.face;
        [
            p(&self.node.start),
            p(&a.start),
            p(&b.start),
            p(&c.start),
            p(&self.node.end),
            p(&a.end),
            p(&b.end),
            p(&c.end),
        ]
    }

    /// The query of 8 positions in the order of [`Query::points`].
    pub fn from_points(points: &[[f64; 3]; 8]) -> Self {
        let t = |i: usize| Trajectory {
            start: V::from(points[i]),
            end: V::from(points[i + 4]),
        };
        Self {
            node: t(0),
            face: [t(1), t(2), t(3)],
        }
    }
}

/// The families of queries; [`Family::generate`] documents each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// (a) of [`hard`]: a constructed contact or near miss on a moving, deforming triangle.
    Constructed,
    /// (b) of [`hard`]: as (a) with the contact exactly at the start or end of the step.
    Endpoint,
    /// (c) of [`hard`]: motion parallel to the triangle's plane, in it or just off it.
    Parallel,
    /// (d) of [`hard`]: all 8 points uniform in the unit box.
    Box,
    /// (e) of [`hard`]: a constructed contact on a needle or cap triangle.
    Sliver,
    /// [`sweep`]: four random points with four random displacements.
    Anything,
    /// [`sweep`]: coplanar at a chosen time and weights, random velocities.
    CoplanarAtTime,
    /// [`sweep`]: a rigidly moving face and a nearly tangential node.
    NearlyParallel,
    /// [`sweep`]: displacements of 1e-12 to 1e-4 of the face size.
    TinyMotion,
    /// [`sweep`]: displacements of 10 to 1e4 times the face size.
    LargeMotion,
    /// [`sweep`]: all four points moving within one plane.
    InPlane,
    /// [`sweep`]: coplanar at a chosen time, 1e3 face sizes from the origin.
    FarFromOrigin,
    /// [`sweep`]: a sliver face in rigid motion, the node on it at a chosen time.
    RigidSliver,
    /// [`sweep`]: a sliver face whose corners move independently, often collapsing.
    CollapsingSliver,
    /// [`sweep`]: a moving, deforming unit face that the node crosses inside (the CCD bench).
    CrossingHit,
    /// [`sweep`]: as [`Family::CrossingHit`], crossing the plane outside the face or stopping
    /// short of it (the CCD bench).
    CrossingMiss,
}

impl Family {
    /// A short name for reports and test output.
    pub fn name(self) -> &'static str {
        match self {
            Family::Constructed => "constructed",
            Family::Endpoint => "endpoint",
            Family::Parallel => "parallel",
            Family::Box => "box",
            Family::Sliver => "sliver",
            Family::Anything => "random",
            Family::CoplanarAtTime => "coplanar at a chosen time",
            Family::NearlyParallel => "nearly parallel",
            Family::TinyMotion => "tiny motion",
            Family::LargeMotion => "large motion",
            Family::InPlane => "in-plane motion",
            Family::FarFromOrigin => "far from the origin",
            Family::RigidSliver => "sliver face",
            Family::CollapsingSliver => "collapsing sliver face",
            Family::CrossingHit => "crossing hit",
            Family::CrossingMiss => "crossing miss",
        }
    }

    /// One query of this family, drawn from `rng`.
    pub fn generate(self, rng: &mut SplitMix64) -> Query {
        match self {
            Family::Constructed => hard::constructed(rng),
            Family::Endpoint => hard::endpoint(rng),
            Family::Parallel => hard::parallel(rng),
            Family::Box => hard::unit_box(rng),
            Family::Sliver => hard::sliver(rng),
            Family::Anything => sweep::anything(rng),
            Family::CoplanarAtTime => sweep::coplanar_at_time(rng),
            Family::NearlyParallel => sweep::nearly_parallel(rng),
            Family::TinyMotion => sweep::tiny_motion(rng),
            Family::LargeMotion => sweep::large_motion(rng),
            Family::InPlane => sweep::in_plane(rng),
            Family::FarFromOrigin => sweep::far_from_origin(rng),
            Family::RigidSliver => sweep::rigid_sliver(rng),
            Family::CollapsingSliver => sweep::collapsing_sliver(rng),
            Family::CrossingHit => sweep::crossing(rng, true),
            Family::CrossingMiss => sweep::crossing(rng, false),
        }
    }
}

/// The cross-check's mix: a fixed cycle of 20 gives 8 constructed, 2 endpoint, 3 parallel, 4 box
/// and 3 sliver queries, interleaved so that any prefix holds a mix.
pub const CROSSCHECK_MIX: [Family; 20] = {
    use Family::*;
    [
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
    ]
};

/// The CCD sweep's mix: each family of [`sweep`] in turn.
pub const SWEEP_MIX: [Family; 9] = [
    Family::Anything,
    Family::CoplanarAtTime,
    Family::NearlyParallel,
    Family::TinyMotion,
    Family::LargeMotion,
    Family::InPlane,
    Family::FarFromOrigin,
    Family::RigidSliver,
    Family::CollapsingSliver,
];

/// The CCD bench's families: plain crossings inside and outside well-shaped faces.
pub const CROSSING_MIX: [Family; 2] = [Family::CrossingHit, Family::CrossingMiss];

/// `n` queries, deterministic for a `seed`: query `i` is of family `mix[i % mix.len()]`, all
/// drawn from one [`SplitMix64`] stream in turn.
pub fn queries(mix: &[Family], n: usize, seed: u64) -> impl Iterator<Item = (Family, Query)> + '_ {
    let mut rng = SplitMix64::new(seed);
    (0..n).map(move |i| {
        let family = mix[i % mix.len()];
        (family, family.generate(&mut rng))
    })
}

// ---------------------------------------------------------------------------------------------
// Draws shared by the families.

/// Uniform in the cube `[-s, s)^3`.
pub fn uniform_vec(rng: &mut SplitMix64, s: f64) -> V {
    V::new(rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s))
}

/// One of `items`, uniformly.
pub fn pick<T: Copy>(rng: &mut SplitMix64, items: &[T]) -> T {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

/// Log-uniform in `[lo, hi)`: `exp(u)`, `u` uniform in `[ln lo, ln hi)`.
pub fn log_uniform(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    (rng.uniform(lo.ln(), hi.ln())).exp()
}

/// Log-uniform over decades: `10^u`, `u` uniform in `[lo, hi)`. The same distribution as
/// [`log_uniform`] over `[10^lo, 10^hi)`, but other bits, which the sweep's seeded queries keep.
pub fn decades(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.uniform(lo, hi))
}

/// Uniform in the ball of radius `r` (rejection from the cube).
pub fn in_ball(rng: &mut SplitMix64, r: f64) -> V {
    loop {
        let v = uniform_vec(rng, 1.0);
        if v.norm_squared() <= 1.0 {
            return v * r;
        }
    }
}

/// A unit vector, uniform on the sphere (a point of the ball away from its centre, scaled).
pub fn direction(rng: &mut SplitMix64) -> V {
    loop {
        let v = in_ball(rng, 1.0);
        let n = v.norm();
        if n > 0.1 {
            return v / n;
        }
    }
}

/// The point of barycentric weights `w` on the triangle `t`: `sum w_k t_k`.
pub fn at_weights(t: &[V; 3], w: [f64; 3]) -> V {
    t[0] * w[0] + t[1] * w[1] + t[2] * w[2]
}

/// The trajectory that is at `x` at the step fraction `t` and moves by `d` over the step:
/// `x - t d` to `x + (1 - t) d`.
pub fn passing(x: V, d: V, t: f64) -> Trajectory {
    Trajectory {
        start: x - d * t,
        end: x + d * (1.0 - t),
    }
}

/// The trajectory from `x` moving by `d` over the step.
pub fn moving(x: V, d: V) -> Trajectory {
    Trajectory {
        start: x,
        end: x + d,
    }
}
