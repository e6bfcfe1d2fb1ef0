//! The CCD sweep's families ([`super::SWEEP_MIX`]): the trajectories on which
//! `solver/tests/ccd.rs` compares the CCD with brute-force sampling, each family aimed at one way
//! a closed-form CCD can fail (rounding of the coplanarity cubic, nearly parallel or tangent
//! motion, extreme scales, slivers). Moved unchanged from that test, so its seeded sweep draws
//! the same trajectories as before.
//!
//! The crossing families ([`crossing`]), plain hits and misses on well-shaped faces, are the
//! CCD bench's set (`solver/benches/ccd.rs`), moved from it unchanged.
//!
//! Contact times are drawn by [`collision_time`] (exactly 0 or 1, within 1e-12..1e-2 of either,
//! or uniform) and contact weights by [`near_boundary_weights`] (mostly inside, sometimes just
//! outside, sometimes within a hair of an edge or a corner).

use impact_solver::contact::ccd::Trajectory;
use impact_solver::rng::SplitMix64;
use impact_solver::Vector3;
use nalgebra::Rotation3;

use super::{at_weights, decades, direction, moving, passing, uniform_vec, Query};

type V = Vector3<f64>;

/// Barycentric weights summing to one: two uniform in `[-0.2, 1.2]` (one in four within
/// 1e-13..1e-3 of an edge, one in four within that of a corner), the corner they favour rotated
/// at random.
pub fn near_boundary_weights(rng: &mut SplitMix64) -> [f64; 3] {
    let near = |rng: &mut SplitMix64| {
        decades(rng, -13.0, -3.0) * if rng.next_f64() < 0.5 { -1.0 } else { 1.0 }
    };
    let mut w = [rng.uniform(-0.2, 1.2), rng.uniform(-0.2, 1.2), 0.0];
    match rng.next_u64() % 4 {
        0 => {
            // Near an edge.
            let k = (rng.next_u64() % 2) as usize;
            w[k] = near(rng);
        }
        1 => {
            // Near a vertex.
            w = [near(rng), near(rng), 0.0];
        }
        _ => {}
    }
    w[2] = 1.0 - w[0] - w[1];
    // Rotate which vertex is special.
    let r = (rng.next_u64() % 3) as usize;
    [w[r], w[(r + 1) % 3], w[(r + 2) % 3]]
}

/// A contact time: 0 or 1 exactly (one in ten each), within 1e-12..1e-2 of 0 or of 1 (one in
/// ten each), or uniform in `[0, 1)`.
pub fn collision_time(rng: &mut SplitMix64) -> f64 {
    match rng.next_u64() % 10 {
        0 => 0.0,
        1 => 1.0,
        2 => decades(rng, -12.0, -2.0),
        3 => 1.0 - decades(rng, -12.0, -2.0),
        _ => rng.next_f64(),
    }
}

/// Three corners uniform in `[-s, s)^3`.
fn triangle(rng: &mut SplitMix64, s: f64) -> [V; 3] {
    [
        uniform_vec(rng, s),
        uniform_vec(rng, s),
        uniform_vec(rng, s),
    ]
}

/// Face corners `x[0..3]` and the node `x[3]`, each moving by `d`.
fn displaced(x: [V; 4], d: [V; 4]) -> Query {
    Query {
        node: moving(x[3], d[3]),
        face: [0, 1, 2].map(|k| moving(x[k], d[k])),
    }
}

/// Face corners `x[0..3]` and the node `x[3]` where they are at the step fraction `tc`, each
/// moving by `vel`.
fn through(x: [V; 4], vel: [V; 4], tc: f64) -> Query {
    Query {
        node: passing(x[3], vel[3], tc),
        face: [0, 1, 2].map(|k| passing(x[k], vel[k], tc)),
    }
}

/// A sliver: the corners 0 and 1 of `tri`, the third `h` times its own position off the middle
/// of their edge.
fn sliver_of(tri: [V; 3], h: f64) -> [V; 3] {
    [
        tri[0],
        tri[1],
        tri[0] + 0.5 * (tri[1] - tri[0]) + h * tri[2],
    ]
}

/// Anything: four random points, four random displacements (the face deforms and turns).
pub fn anything(rng: &mut SplitMix64) -> Query {
    let x = [0, 1, 2, 3].map(|_| uniform_vec(rng, 1.0));
    let d = [0, 1, 2, 3].map(|_| uniform_vec(rng, 1.0));
    displaced(x, d)
}

/// Coplanar at a chosen time, at chosen weights (often near an edge or vertex), with
/// independent random velocities of all four points.
pub fn coplanar_at_time(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let p = at_weights(&tri, near_boundary_weights(rng));
    let s = rng.uniform(0.0, 2.0);
    let vel = [0, 1, 2, 3].map(|_| uniform_vec(rng, s));
    let tc = collision_time(rng);
    through([tri[0], tri[1], tri[2], p], vel, tc)
}

/// Nearly parallel: a rigidly translating face (plus a small deformation) and a node whose
/// relative velocity is tangential up to a tiny normal part; either coplanar at some time, or
/// offset from the plane by about the normal motion.
pub fn nearly_parallel(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let n = (tri[1] - tri[0]).cross(&(tri[2] - tri[0])).normalize();
    let p = at_weights(&tri, near_boundary_weights(rng));
    let common = uniform_vec(rng, 1.0);
    let deform = decades(rng, -16.0, -3.0);
    let vel = [0, 1, 2].map(|_| common + uniform_vec(rng, deform));
    let tangential = uniform_vec(rng, 2.0);
    let tangential = tangential - n * n.dot(&tangential);
    let normal = decades(rng, -16.0, -1.0) * tangential.norm();
    let sign = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
    let vel3 = common + tangential + sign * normal * n;
    let offset = if rng.next_f64() < 0.5 {
        0.0
    } else {
        rng.uniform(-2.0, 2.0) * normal
    };
    let tc = collision_time(rng);
    through(
        [tri[0], tri[1], tri[2], p + offset * n],
        [vel[0], vel[1], vel[2], vel3],
        tc,
    )
}

/// Tiny motions: displacements 1e-12..1e-4 of the face size, the node that close to the face.
pub fn tiny_motion(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let n = (tri[1] - tri[0]).cross(&(tri[2] - tri[0])).normalize();
    let s = decades(rng, -12.0, -4.0);
    let p = at_weights(&tri, near_boundary_weights(rng)) + rng.uniform(-2.0, 2.0) * s * n;
    let vel = [0, 1, 2, 3].map(|_| uniform_vec(rng, s));
    displaced([tri[0], tri[1], tri[2], p], vel)
}

/// Large motions: displacements 10..1e4 times the face size.
pub fn large_motion(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let p = at_weights(&tri, near_boundary_weights(rng));
    let s = decades(rng, 1.0, 4.0);
    let common = uniform_vec(rng, s);
    let vel = [0, 1, 2, 3].map(|k| {
        if k == 3 {
            uniform_vec(rng, s)
        } else {
            let deform = rng.uniform(0.0, 1.0);
            common + uniform_vec(rng, deform)
        }
    });
    let tc = collision_time(rng);
    through([tri[0], tri[1], tri[2], p], vel, tc)
}

/// Motion within a common plane (coplanar up to the rounding of a random rotation).
pub fn in_plane(rng: &mut SplitMix64) -> Query {
    let e1 = direction(rng);
    let e2 = e1.cross(&direction(rng)).normalize();
    let origin = uniform_vec(rng, 1.0);
    let in_plane = |rng: &mut SplitMix64| rng.uniform(-1.0, 1.0) * e1 + rng.uniform(-1.0, 1.0) * e2;
    let x = [0, 1, 2, 3].map(|_| origin + in_plane(rng));
    let d = [0, 1, 2, 3].map(|_| in_plane(rng));
    displaced(x, d)
}

/// Far from the origin (1e3 x the face size), coplanar at a chosen time.
pub fn far_from_origin(rng: &mut SplitMix64) -> Query {
    let shift = uniform_vec(rng, 1e3);
    let tri = triangle(rng, 1.0).map(|x| x + shift);
    let p = at_weights(&tri, near_boundary_weights(rng));
    let vel = [0, 1, 2, 3].map(|_| uniform_vec(rng, 1.0));
    let tc = collision_time(rng);
    through([tri[0], tri[1], tri[2], p], vel, tc)
}

/// A sliver face (one vertex within 1e-8..1e-1 of the opposite edge) in rigid motion (a
/// rotation of up to 1 rad and a translation, interpolated linearly, which keeps the face from
/// collapsing) plus a deformation of a tenth of its width; the node is on it at a chosen time.
pub fn rigid_sliver(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let h = decades(rng, -8.0, -1.0);
    let tri = sliver_of(tri, h);
    let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
    let rotation = Rotation3::new(direction(rng) * rng.uniform(0.0, 1.0));
    let shift = uniform_vec(rng, 1.0);
    let end = tri.map(|x| centre + shift + rotation * (x - centre) + uniform_vec(rng, 0.1 * h));
    let face = [0, 1, 2].map(|k| Trajectory {
        start: tri[k],
        end: end[k],
    });
    let tc = collision_time(rng);
    let at_tc = face.map(|q| q.at(tc));
    let p = at_weights(&at_tc, near_boundary_weights(rng));
    let vel = uniform_vec(rng, 1.0);
    Query {
        node: passing(p, vel, tc),
        face,
    }
}

/// A sliver face whose vertices move independently: it often collapses through zero area (turns
/// inside out) during the step right at the contact, where the weights change extremely fast.
pub fn collapsing_sliver(rng: &mut SplitMix64) -> Query {
    let tri = triangle(rng, 1.0);
    let h = decades(rng, -8.0, -1.0);
    let tri = sliver_of(tri, h);
    let p = at_weights(&tri, near_boundary_weights(rng));
    let vel = [0, 1, 2, 3].map(|_| uniform_vec(rng, 0.5));
    let tc = collision_time(rng);
    through([tri[0], tri[1], tri[2], p], vel, tc)
}

/// A face of unit size (corners in `[-1, 1]^3`) moving by a common displacement plus a
/// deformation, and a node that is coplanar with it at a random time `tc` at weights `w`: inside
/// (each at least 0.05) for a `hit`; otherwise outside one edge by 0.05..0.5, and in one miss of
/// four the node stops halfway to that crossing instead.
pub fn crossing(rng: &mut SplitMix64, hit: bool) -> Query {
    let tri = triangle(rng, 1.0);
    let common = uniform_vec(rng, 0.5);
    let vel = [0, 1, 2].map(|_| common + uniform_vec(rng, 0.2));
    let tc = rng.next_f64();
    let w1 = rng.uniform(0.05, 0.9);
    let w2 = rng.uniform(0.05, 0.95 - w1);
    let mut w = [1.0 - w1 - w2, w1, w2];
    if !hit {
        let k = (rng.next_u64() % 3) as usize;
        let out = rng.uniform(0.05, 0.5);
        w[k] = -out;
        w[(k + 1) % 3] += out;
    }
    let p = at_weights(&[0, 1, 2].map(|k| tri[k] + tc * vel[k]), w);
    let vp = common + uniform_vec(rng, 1.0);
    let mut node = passing(p, vp, tc);
    if !hit && rng.next_u64() % 4 == 0 {
        // Stop short: end the node's motion halfway to the crossing.
        node.end = node.start + 0.5 * tc * vp;
    }
    Query {
        node,
        face: [0, 1, 2].map(|k| moving(tri[k], vel[k])),
    }
}
