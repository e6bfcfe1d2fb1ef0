//! The geometric primitives of contact detection: barycentric weights in a tetrahedron and on a
//! triangle, the contact point of the closest-point strategy, and the exact closest point and
//! distance between a point and a triangle (also the harness's CCD cross-check's reference).
//!
//! Each function keeps the arithmetic detection has always used, operation for operation, so
//! that moving them here changed no result bit.

use nalgebra::Vector3;

/// Barycentric coordinates of `p` in the tetrahedron `x` from signed sub-volumes (thesis
/// (3.46)): `xi_k = V(x with node k replaced by p) / V(x)`.
pub fn tetrahedron_barycentric(p: &Vector3<f64>, x: &[Vector3<f64>; 4]) -> [f64; 4] {
    let vol = |a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>, d: &Vector3<f64>| {
        (b - a).cross(&(c - a)).dot(&(d - a))
    };
    let v = vol(&x[0], &x[1], &x[2], &x[3]);
    [
        vol(p, &x[1], &x[2], &x[3]) / v,
        vol(&x[0], p, &x[2], &x[3]) / v,
        vol(&x[0], &x[1], p, &x[3]) / v,
        vol(&x[0], &x[1], &x[2], p) / v,
    ]
}

/// Barycentric weights of the point of the triangle `(a, b, c)`'s plane nearest `p`, as signed
/// sub-areas over the whole (the local coordinates of thesis (7.6)-(7.7)): with
/// `n = (b - a) x (c - a)`, `N_a = ((b - p) x (c - p)).n / n.n`, `N_b = ((c - p) x (a - p)).n /
/// n.n`, `N_c = 1 - N_a - N_b`. Outside the triangle some weight is negative.
pub fn triangle_weights(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> [f64; 3] {
    let n = (b - a).cross(&(c - a));
    let area2 = n.norm_squared();
    let wa = (b - p).cross(&(c - p)).dot(&n) / area2;
    let wb = (c - p).cross(&(a - p)).dot(&n) / area2;
    [wa, wb, 1.0 - wa - wb]
}

/// The contact point of the closest-point strategy (thesis 7.4.2): the plane weights of `p`
/// ([`triangle_weights`]) with the negative ones set to zero and the rest rescaled to sum to one.
/// A point of the triangle near `p`, and the nearest one whenever the projection lies inside;
/// outside a corner's or an edge's region it may differ from [`closest_point_on_triangle`].
/// Detection keeps it because its results were pinned with it.
pub fn clamped_triangle_weights(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> [f64; 3] {
    let mut w = triangle_weights(p, a, b, c).map(|x| x.max(0.0));
    let sum: f64 = w.iter().sum();
    w.iter_mut().for_each(|x| *x /= sum);
    w
}

/// The point of the triangle `(a, b, c)` nearest `p`, exactly: the Voronoi region of `p` (three
/// corners, three edges or the face) decides which (Ericson, *Real-Time Collision Detection*,
/// 2005, 5.1.5).
pub fn closest_point_on_triangle(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> Vector3<f64> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + v * ab;
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + w * ac;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + w * (c - b);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    a + ab * v + ac * w
}

/// Distance from `p` to the triangle `(a, b, c)`: `|p - q|` with `q` the
/// [`closest_point_on_triangle`].
pub fn point_triangle_distance(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> f64 {
    (p - closest_point_on_triangle(p, a, b, c)).norm()
}

/// Whether `v` points against the (unnormalised) normal `n`, beyond rounding:
/// `n . v < -1e-12 |n| |v|`.
pub fn against(n: &Vector3<f64>, v: &Vector3<f64>) -> bool {
    n.dot(v) < -1e-12 * n.norm() * v.norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_coordinates_sum_to_one_and_locate_points() {
        let x = [Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()];
        let xi = tetrahedron_barycentric(&Vector3::new(0.1, 0.2, 0.3), &x);
        assert!((xi.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!(
            (xi[1] - 0.1).abs() < 1e-15
                && (xi[2] - 0.2).abs() < 1e-15
                && (xi[3] - 0.3).abs() < 1e-15
        );
        assert!(tetrahedron_barycentric(&Vector3::new(0.6, 0.6, 0.1), &x)[0] < 0.0);
    }

    #[test]
    fn point_triangle_distance_in_each_region() {
        let (a, b, c) = (
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        );
        let d = |p: [f64; 3]| point_triangle_distance(&Vector3::from(p), &a, &b, &c);
        assert_eq!(d([0.25, 0.25, 2.0]), 2.0); // face
        assert_eq!(d([-3.0, -4.0, 0.0]), 5.0); // vertex a
        assert_eq!(d([0.5, -2.0, 0.0]), 2.0); // edge ab
        assert!((d([1.0, 1.0, 0.0]) - 0.5f64.sqrt()).abs() < 1e-15); // edge bc
        assert_eq!(d([2.0, 0.0, 0.0]), 1.0); // vertex b
        assert_eq!(d([0.0, 3.0, 1.0]), 5.0f64.sqrt()); // vertex c
        assert_eq!(d([-2.0, 0.5, 0.0]), 2.0); // edge ca
    }

    #[test]
    fn plane_weights_rebuild_the_projection_and_clamping_stays_on_the_triangle() {
        let (a, b, c) = (
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(2.0, 0.0, 0.0),
            Vector3::new(0.0, 2.0, 0.0),
        );
        let p = Vector3::new(0.5, 0.25, 3.0);
        let w = triangle_weights(&p, &a, &b, &c);
        let q = a * w[0] + b * w[1] + c * w[2];
        assert!((q - Vector3::new(0.5, 0.25, 0.0)).norm() < 1e-15);
        // Inside, clamping changes nothing and gives the exact closest point.
        let clamped = clamped_triangle_weights(&p, &a, &b, &c);
        let q = a * clamped[0] + b * clamped[1] + c * clamped[2];
        assert!((q - closest_point_on_triangle(&p, &a, &b, &c)).norm() < 1e-15);
        // Outside, the clamped weights still describe a point of the triangle.
        let outside = clamped_triangle_weights(&Vector3::new(3.0, -1.0, 0.0), &a, &b, &c);
        assert!(outside.iter().all(|&x| x >= 0.0));
        assert!((outside.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }
}
