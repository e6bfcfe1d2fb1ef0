//! Touching contacts: a point that comes within a minimum separation `delta` of the triangle
//! during the step without crossing its plane where the cubic (7.13) can see it (a point
//! grazing an edge or a vertex, sliding in the face's plane a rounding error off it, passing by
//! a sliver). As Tight Inclusion's minimum separation (Wang et al. 2021), `delta` makes "touch"
//! a stated distance instead of the rounding of one formula.
//!
//! The distance `d(t)` from the point to the moving triangle is Lipschitz in `t` with constant
//! `L = max_k |v_p - v_k|` (`v` the displacements over the step): every point of the triangle
//! moves with a convex combination of its corners' velocities. So on `[t0, t1]`,
//! `d >= (d(t0) + d(t1) - L (t1 - t0)) / 2`, and a branch and bound over the step (earliest
//! interval first) either prunes an interval, finds a time with `d <= delta`, or halves it.
//! Isolated approaches cost a few evaluations per halving (about 40 halvings down to 1e-12);
//! the search stops after [`MAX_EVALUATIONS`], which only a point grazing the triangle just
//! beyond `delta` over a long stretch reaches: it is then reported as not touching.

use nalgebra::Vector3;

use super::{CcdHit, Trajectory};
use crate::geometry::proximity::{clamped_triangle_weights, closest_point_on_triangle};

/// `delta = TOUCH_SEPARATION * s`, `s` the largest absolute coordinate of the query's eight
/// positions: positions are known to about `eps s` (2.2e-16 s), and a point within 1e-12 s
/// (about 4500 of those units; 1 pm in a scene of metres) touches. The cross-check against
/// ipctk judges a missed touch with the same level.
pub const TOUCH_SEPARATION: f64 = 1e-12;

/// Distance evaluations the search may make.
pub const MAX_EVALUATIONS: usize = 512;

/// The minimum separation of a query: [`TOUCH_SEPARATION`] times its largest coordinate.
pub fn minimum_separation(node: &Trajectory, face: [&Trajectory; 3]) -> f64 {
    let largest = std::iter::once(node)
        .chain(face)
        .flat_map(|q| [q.start, q.end])
        .flat_map(|x| [x.x, x.y, x.z])
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    TOUCH_SEPARATION * largest
}

/// The earliest time at which the point, farther than `delta` from the triangle at the start of
/// the step, comes within `delta` of it, with the clamped weights of the triangle's point
/// nearest it; `None` when it does not, or when it starts within `delta` (already in contact).
/// A face degenerate to a segment or a point at that time has no weights and gives no touch.
pub fn earliest_touch(node: &Trajectory, face: [&Trajectory; 3], delta: f64) -> Option<CcdHit> {
    let velocity = |q: &Trajectory| q.end - q.start;
    let vp = velocity(node);
    let lipschitz = face
        .iter()
        .map(|q| (vp - velocity(q)).norm())
        .fold(0.0_f64, f64::max);
    let distance = |t: f64| -> (f64, Vector3<f64>, [Vector3<f64>; 3]) {
        let p = node.at(t);
        let [a, b, c] = face.map(|q| q.at(t));
        let q = closest_point_on_triangle(&p, &a, &b, &c);
        ((p - q).norm(), q, [a, b, c])
    };
    let hit = |t: f64| {
        let (_, q, [a, b, c]) = distance(t);
        let weights = clamped_triangle_weights(&q, &a, &b, &c);
        weights
            .iter()
            .all(|w| w.is_finite())
            .then_some(CcdHit { t, weights })
    };
    // The first time within delta in `[lo, hi]`, `d(lo) > delta >= d(hi)`: bisection, to the
    // resolution of the times.
    let first_within = |mut lo: f64, mut hi: f64| {
        for _ in 0..64 {
            let m = 0.5 * (lo + hi);
            if m <= lo || m >= hi {
                break;
            }
            if distance(m).0 <= delta {
                hi = m;
            } else {
                lo = m;
            }
        }
        hi
    };
    let (d0, d1) = (distance(0.0).0, distance(1.0).0);
    if d0 <= delta {
        // In contact at the start: not an approach in this step (Tight Inclusion answers such
        // a query as initial contact without a time of impact). Detection deals with a node
        // resting on a face by its other strategies; reporting it here would move a resting
        // node's contact to whichever face it touches at t = 0.
        return None;
    }
    let mut evaluations = 2;
    // Intervals still to search, the earliest on top: each popped interval has all earlier
    // times searched.
    let mut stack = vec![(0.0, 1.0, d0, d1)];
    while let Some((t0, t1, d0, d1)) = stack.pop() {
        if d1 <= delta {
            return hit(first_within(t0, t1));
        }
        if 0.5 * (d0 + d1 - lipschitz * (t1 - t0)) > delta {
            continue;
        }
        let mid = 0.5 * (t0 + t1);
        if evaluations >= MAX_EVALUATIONS || mid <= t0 || mid >= t1 {
            return None;
        }
        let dm = distance(mid).0;
        evaluations += 1;
        stack.push((mid, t1, dm, d1));
        stack.push((t0, mid, d0, dm));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixed(x: Vector3<f64>) -> Trajectory {
        Trajectory { start: x, end: x }
    }

    #[test]
    fn a_point_grazing_an_edge_touches_and_one_passing_farther_does_not() {
        let face = [
            fixed(Vector3::new(0.0, 0.0, 0.0)),
            fixed(Vector3::new(1.0, 0.0, 0.0)),
            fixed(Vector3::new(0.0, 1.0, 0.0)),
        ];
        let f = [&face[0], &face[1], &face[2]];
        // Along z past the edge y = 0 at x = 0.5, y = -gap, the closest at t = 0.5.
        let pass = |gap: f64| Trajectory {
            start: Vector3::new(0.5, -gap, 1.0),
            end: Vector3::new(0.5, -gap, -1.0),
        };
        let touch = earliest_touch(&pass(1e-13), f, 1e-12).expect("a touch");
        assert!((touch.t - 0.5).abs() < 1e-12, "{touch:?}");
        assert!(touch.weights.iter().all(|&w| w >= 0.0));
        assert!((touch.weights[0] - 0.5).abs() < 1e-9 && (touch.weights[1] - 0.5).abs() < 1e-9);
        assert!(earliest_touch(&pass(1e-11), f, 1e-12).is_none());
        // Starting within delta is contact at the start, not a touch in the step.
        let resting = Trajectory {
            start: Vector3::new(0.5, -1e-13, 0.0),
            end: Vector3::new(0.5, -1e-13, -1.0),
        };
        assert!(earliest_touch(&resting, f, 1e-12).is_none());
    }

    #[test]
    fn the_separation_scales_with_the_coordinates() {
        let p = fixed(Vector3::new(-3.0, 0.5, 0.0));
        let q = fixed(Vector3::zeros());
        assert_eq!(minimum_separation(&p, [&q, &q, &q]), 3e-12);
    }
}
