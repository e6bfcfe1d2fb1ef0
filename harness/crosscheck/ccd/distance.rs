//! The smallest distance between the point and the triangle of a query over its step, computed
//! independently of both CCD algorithms.

use nalgebra::Vector3;

use crate::crosscheck::ccd_queries::CcdQuery;

/// The exact distance from a point to a triangle (Ericson 2005, 5.1.5) is the solver's, so the
/// cross-check and contact detection share one geometry; it is independent of both CCD
/// algorithms, which never call it.
pub use impact_solver::geometry::proximity::point_triangle_distance;

/// The distance below which the point counts as touching the triangle: the minimum separation
/// of our CCD (`contact::ccd::touch`), `1e-12` times the largest coordinate of the query.
pub fn touch_level(q: &CcdQuery) -> f64 {
    impact_solver::contact::ccd::touch::TOUCH_SEPARATION
        * q.points
            .iter()
            .flatten()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Distance between the point and the triangle of `q` at step fraction `t`.
pub fn distance_at(q: &CcdQuery, t: f64) -> f64 {
    let at = |k: usize| {
        let (x0, x1) = (Vector3::from(q.points[k]), Vector3::from(q.points[k + 4]));
        x0 + t * (x1 - x0)
    };
    point_triangle_distance(&at(0), &at(1), &at(2), &at(3))
}

/// Smallest distance over the step: 2001 samples, then golden-section search around the best.
/// Independent of both CCD algorithms (it never solves for coplanarity).
pub fn min_distance(q: &CcdQuery) -> f64 {
    const N: usize = 2000;
    let (mut best, mut at) = (f64::INFINITY, 0);
    for i in 0..=N {
        let d = distance_at(q, i as f64 / N as f64);
        if d < best {
            (best, at) = (d, i);
        }
    }
    let (mut lo, mut hi) = (
        (at.max(1) - 1) as f64 / N as f64,
        (at + 1).min(N) as f64 / N as f64,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if distance_at(q, m1) < distance_at(q, m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    best.min(distance_at(q, 0.5 * (lo + hi)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crosscheck::ccd_queries::QuerySource;

    #[test]
    fn the_smallest_distance_over_a_step_finds_a_crossing_and_a_near_miss() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let query = |p0: [f64; 3], p1: [f64; 3]| CcdQuery {
            source: QuerySource::Random,
            points: [p0, tri[0], tri[1], tri[2], p1, tri[0], tri[1], tri[2]],
        };
        assert!(min_distance(&query([0.2, 0.2, 1.0], [0.2, 0.2, -1.0])) < 1e-12);
        // Passes beside the edge bc (x + y = 1) at 5e-5 outside along x and y: sqrt(2) 5e-5 away.
        let miss = min_distance(&query(
            [0.5 + 5e-5, 0.5 + 5e-5, 1.0],
            [0.5 + 5e-5, 0.5 + 5e-5, -1.0],
        ));
        assert!((miss - 2f64.sqrt() * 5e-5).abs() < 1e-12, "{miss}");
    }
}
