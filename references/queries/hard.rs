//! The cross-check's families ([`super::CROSSCHECK_MIX`]): queries built to be hard,
//! constructed contacts and near misses, endpoint, parallel, box and sliver families, mixed so
//! that about half are hits. Moved unchanged from `harness/crosscheck/ccd_queries/random.rs`:
//! ipctk's cached answers are keyed on these exact bits.
//!
//! - **(a) constructed** ([`constructed`]): a random non-degenerate triangle at `t0` (size `s`
//!   log-uniform in `[0.01, 1]`, centre in `[-1, 1]^3`) and at `t1` (moved by up to `s`, each
//!   corner perturbed by up to `0.3 s`, so it translates, turns and deforms), a contact time `t*`
//!   uniform in `[0, 1]`, barycentric weights `w` of the contact point `q = sum w_k f_k(t*)` on
//!   the interpolated triangle, a random node displacement `d` (length `s` times log-uniform in
//!   `[0.01, 2]`), and `v_t0 = q - t* d`, `v_t1 = q + (1 - t*) d`. The weights are: well inside
//!   (each >= 0.05, 40 %), exactly on an edge (one weight 0, 10 %), exactly at a corner (5 %),
//!   outside one edge (the edge's weight `-delta`, 30 %) or beyond a corner
//!   (`(1 + delta, -delta/2, -delta/2)`, 15 %) with `delta` drawn from `1e-3, 1e-6, 1e-9`:
//!   `delta` is a barycentric distance, `delta` times the height of the triangle over that edge.
//!   Outside points are near misses at `t*`, though the node may still meet the triangle at
//!   another root of the coplanarity cubic.
//! - **(b) endpoint** ([`endpoint`]): as (a) with `t*` exactly `0` or `1` (the node starts, or
//!   ends, on the face; the plane is met only to rounding) and weights inside (40 %), on an edge
//!   (20 %) or outside an edge by `delta` (40 %).
//! - **(c) parallel** ([`parallel`]): the triangle translates rigidly (or stays), and the node
//!   moves parallel to its plane, in it or at an offset of `0`, `1e-9 s`, `1e-6 s` or `1e-3 s`
//!   along the normal, from a point of the plane to another (weights in `[-0.5, 1.5]`), so the
//!   node may enter, cross, stay inside or stay outside the triangle. At offset 0 the
//!   coplanarity cubic vanishes identically: in-plane motion.
//! - **(d) box** ([`unit_box`]): all 8 points uniform in the unit box; mostly misses.
//! - **(e) sliver** ([`sliver`]): as (a) with weights inside (45 %), on an edge (20 %) or outside
//!   an edge by `delta` (35 %, the other two weights equal), on a near-degenerate triangle: a
//!   needle (two corners `eps s` apart) or a cap (one corner `eps s` off the line of the other
//!   two, between them), `eps` in `1e-3, 1e-6, 1e-9`, translated rigidly between `t0` and `t1`.

use impact_solver::contact::ccd::Trajectory;
use impact_solver::rng::SplitMix64;
use impact_solver::Vector3;

use super::{at_weights, direction, in_ball, log_uniform, passing, pick, uniform_vec, Query};

type V = Vector3<f64>;
/// A triangle's three corners.
pub type Triangle = [V; 3];

const DELTAS: [f64; 3] = [1e-3, 1e-6, 1e-9];

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

/// The triangle at the step fraction `t` between `a` (at 0) and `b` (at 1).
pub fn lerp(a: &Triangle, b: &Triangle, t: f64) -> Triangle {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

/// A well-shaped triangle at `t0` and `t1` (also at every time between, checked at a few), and
/// its size.
pub fn moving_triangle(rng: &mut SplitMix64) -> (Triangle, Triangle, f64) {
    loop {
        let s = log_uniform(rng, 0.01, 1.0);
        let centre = uniform_vec(rng, 1.0);
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
pub fn inside_weights(rng: &mut SplitMix64) -> [f64; 3] {
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
pub fn through(t0: &Triangle, t1: &Triangle, t_star: f64, w: [f64; 3], d: V) -> Query {
    let q = at_weights(&lerp(t0, t1, t_star), w);
    between(passing(q, d, t_star), t0, t1)
}

/// The query of a node's trajectory and a triangle moving from `t0` to `t1`.
fn between(node: Trajectory, t0: &Triangle, t1: &Triangle) -> Query {
    Query {
        node,
        face: [0, 1, 2].map(|k| Trajectory {
            start: t0[k],
            end: t1[k],
        }),
    }
}

fn node_displacement(rng: &mut SplitMix64, s: f64) -> V {
    direction(rng) * s * log_uniform(rng, 0.01, 2.0)
}

/// (a): a constructed contact or near miss.
pub fn constructed(rng: &mut SplitMix64) -> Query {
    let (t0, t1, s) = moving_triangle(rng);
    let t_star = rng.next_f64();
    let w = constructed_weights(rng);
    let d = node_displacement(rng, s);
    through(&t0, &t1, t_star, w, d)
}

/// (b): the contact at the start or the end of the step.
pub fn endpoint(rng: &mut SplitMix64) -> Query {
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

/// (c): motion parallel to the triangle's plane.
pub fn parallel(rng: &mut SplitMix64) -> Query {
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
    let node = Trajectory {
        start: at_weights(&t0, w0) + normal * offset,
        end: at_weights(&t1, w1) + normal * offset,
    };
    between(node, &t0, &t1)
}

/// (d): all 8 points uniform in the unit box, in the order of [`Query::points`].
pub fn unit_box(rng: &mut SplitMix64) -> Query {
    let mut p = [[0.0; 3]; 8];
    for x in p.iter_mut().flatten() {
        *x = rng.next_f64();
    }
    Query::from_points(&p)
}

/// (e): a constructed contact on a needle or cap triangle.
pub fn sliver(rng: &mut SplitMix64) -> Query {
    let s = log_uniform(rng, 0.01, 1.0);
    let eps = pick(rng, &DELTAS);
    let centre = uniform_vec(rng, 1.0);
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
