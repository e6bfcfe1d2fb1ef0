//! Element shape measures the remesher improves (issue 21): the mean ratio (Liu & Joe 1994) and
//! the quality `min(1 / chi, eta)` that the smoothing, collapses, flips and peel all compare.

use nalgebra::Vector3;

use crate::kinematics::signed_volume;

/// The six edges of a tetrahedron as local node pairs.
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The mean-ratio quality `eta = 12 (3V)^(2/3) / sum l^2` of a tetrahedron (Liu & Joe 1994): 1
/// for the regular tetrahedron, tending to 0 as it flattens; -1 for a volume that is not
/// positive, so that an inverted element is always the worst.
pub fn mean_ratio(x: &[Vector3<f64>; 4]) -> f64 {
    let v = signed_volume(x);
    if !(v > 0.0) {
        return -1.0;
    }
    let sum: f64 = TET_EDGES
        .iter()
        .map(|[i, j]| (x[*j] - x[*i]).norm_squared())
        .sum();
    12.0 * (3.0 * v).powf(2.0 / 3.0) / sum
}

/// The quality the smoothing raises: `min(1 / chi, eta)`, the inverse collapse ratio (8.1) that
/// the distortion check reads, bounded by the mean ratio so that a sliver (four nearly coplanar
/// nodes with edges of similar length, `chi` near 1 but no volume) is also poor. 1 for the
/// regular tetrahedron; -1 when inverted.
pub(crate) fn shape_quality(x: &[Vector3<f64>; 4]) -> f64 {
    let eta = mean_ratio(x);
    if eta < 0.0 {
        return eta;
    }
    let (chi, altitude) = crate::mesh::ops::distortion::edge_and_altitude_ratios(x);
    eta.min(1.0 / chi).min(1.0 / altitude)
}

/// `shape_quality(x).min(cap)`, bit for bit, without the power of the mean ratio where the
/// cube of the comparison already shows it above the rest: `eta >= b` is
/// `1728 (3V)^2 >= (b sum l^2)^3`, taken here with a margin of 1e-9 (far above the round-off of
/// either side). The smoothing asks this for every element around every candidate place, and
/// the power was a sixth of a nail run's CPU.
pub(crate) fn shape_quality_capped(x: &[Vector3<f64>; 4], cap: f64) -> f64 {
    let v = signed_volume(x);
    if !(v > 0.0) {
        return (-1.0f64).min(cap);
    }
    let (chi, altitude) = crate::mesh::ops::distortion::edge_and_altitude_ratios(x);
    let bound = (1.0 / chi).min(1.0 / altitude).min(cap);
    let sum: f64 = TET_EDGES
        .iter()
        .map(|[i, j]| (x[*j] - x[*i]).norm_squared())
        .sum();
    if bound > 0.0 && 1728.0 * (3.0 * v).powi(2) > (bound * (1.0 + 1e-9) * sum).powi(3) {
        return bound;
    }
    (12.0 * (3.0 * v).powf(2.0 / 3.0) / sum)
        .min(1.0 / chi)
        .min(1.0 / altitude)
        .min(cap)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Alternate corners of a cube, positively oriented.
    fn regular() -> [Vector3<f64>; 4] {
        [
            Vector3::new(1.0, -1.0, -1.0),
            Vector3::new(1.0, 1.0, 1.0),
            Vector3::new(-1.0, 1.0, -1.0),
            Vector3::new(-1.0, -1.0, 1.0),
        ]
    }

    #[test]
    fn the_regular_tetrahedron_has_quality_one_and_an_inverted_one_minus_one() {
        let x = regular();
        assert!(signed_volume(&x) > 0.0);
        assert!((mean_ratio(&x) - 1.0).abs() < 1e-14, "{}", mean_ratio(&x));
        assert!(
            (shape_quality(&x) - 1.0).abs() < 1e-12,
            "{}",
            shape_quality(&x)
        );
        let inverted = [x[1], x[0], x[2], x[3]];
        assert_eq!(mean_ratio(&inverted), -1.0);
        assert_eq!(shape_quality(&inverted), -1.0);
    }

    #[test]
    fn a_sliver_is_poor_though_its_edges_are_alike() {
        // Four nodes of a square, one lifted by 1e-3 of the edge: edge ratio about sqrt(2), no volume.
        let x = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 1.0, 1e-3),
            Vector3::new(0.0, 1.0, 0.0),
        ];
        let x = if signed_volume(&x) > 0.0 {
            x
        } else {
            [x[1], x[0], x[2], x[3]]
        };
        assert!(shape_quality(&x) < 0.01, "{}", shape_quality(&x));
    }

    #[test]
    fn the_capped_quality_is_the_quality_capped_bit_for_bit() {
        let mut x = regular();
        for k in 0..200 {
            let t = k as f64 / 200.0;
            x[3] = Vector3::new(-1.0 + 1.5 * t, -1.0 + t * t, 1.0 - 1.9 * t);
            for cap in [0.05, 0.3, 0.7, 1.0, 2.0] {
                assert_eq!(
                    shape_quality_capped(&x, cap).to_bits(),
                    shape_quality(&x).min(cap).to_bits(),
                    "t = {t}, cap = {cap}"
                );
            }
        }
    }
}
