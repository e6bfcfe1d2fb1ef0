//! When to remesh and where to refine (thesis 8.2 and 8.3).
//!
//! * The distortion check: the collapse ratio `chi_e = L_max / L_min` of every element in the
//!   spatial (current) configuration (8.1), against the limit 10 of Box 8.1.
//! * The refinement region: the elements whose Jacobian of deformation `det F_e` passes
//!   `delta` times the extreme value (8.3)-(8.4), `delta = 0.85`, leaving out those already
//!   smaller than a volume `V_min` (8.5). The error estimator (8.2) is quoted by the thesis and
//!   then set aside ("the briefly illustrated FE error estimator is here not considered"); it is
//!   not implemented here either.

use nalgebra::Vector3;

use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;

/// The collapse ratio above which an element is declared distorted (thesis 8.2, Box 8.1: "if
/// the parameter `chi_e` is greater than 10").
pub const COLLAPSE_RATIO_LIMIT: f64 = 10.0;

/// The scaling coefficient `delta` of the refinement criterion (8.4): "set to 0.85".
pub const REFINEMENT_DELTA: f64 = 0.85;

/// The element collapse ratio `chi_e = L_max^e / L_min^e` (8.1): longest over shortest of the
/// six edges of the tetrahedron `x`, which the thesis takes in the spatial configuration (so `x`
/// are current coordinates). 1 for the regular tetrahedron; infinite when two nodes coincide.
pub fn collapse_ratio(x: &[Vector3<f64>; 4]) -> f64 {
    let (min_edge, max_edge) = crate::mesh::edge_extremes(x);
    if min_edge > 0.0 {
        max_edge / min_edge
    } else {
        f64::INFINITY
    }
}

/// The distortion a remeshing run watches: the collapse ratio (8.1), or the inverse mean ratio
/// `1 / eta` ([`super::mean_ratio`]) where that is larger; infinite for an element whose volume
/// is not positive. 1 for the regular tetrahedron.
///
/// Why not the collapse ratio alone: it sees an element whose edges differ (a needle, a wedge,
/// a cap), not a sliver, four nodes nearly in one plane with edges alike (`chi` near 1, no
/// volume). Under a penetrator such an element went from `chi` 3 to inverted within the ten
/// steps between two checks. Every element with `chi` above the limit 10 is still caught
/// (`1 / eta` only adds to it).
pub fn distortion(x: &[Vector3<f64>; 4]) -> f64 {
    let eta = super::mean_ratio(x);
    if eta > 0.0 {
        let (chi, altitude) = edge_and_altitude_ratios(x);
        chi.max(1.0 / eta).max(altitude)
    } else {
        f64::INFINITY
    }
}

/// The altitude ratio `sqrt(2/3) L_max / h_min`: the longest edge over the smallest altitude,
/// scaled to 1 for the regular tetrahedron (whose altitudes are `sqrt(2/3)` of its edge).
/// Infinite for an element without positive volume.
///
/// Why: the explicit step goes with the smallest altitude (`h_min / c_d`), which neither the
/// collapse ratio nor the mean ratio bounds. A sliver whose altitude is 1/50 of its edges has
/// `chi` near 2 and `1 / eta` near 12 (the mean ratio reads the volume to the power 2/3); in the
/// nail run such elements, flattened across by the nose's passage, held the step at 1 ns while
/// a well-shaped element of the same edges allows 30.
pub fn altitude_ratio(x: &[Vector3<f64>; 4]) -> f64 {
    edge_and_altitude_ratios(x).1
}

/// [`collapse_ratio`] and [`altitude_ratio`] of `x` from one pass over its edges and faces (the
/// distortion check and the remesher's quality read both).
pub(crate) fn edge_and_altitude_ratios(x: &[Vector3<f64>; 4]) -> (f64, f64) {
    let q = crate::mesh::element_quality(x);
    let chi = if q.min_edge > 0.0 {
        q.max_edge / q.min_edge
    } else {
        f64::INFINITY
    };
    let altitude = if q.min_altitude > 0.0 {
        (2.0f64 / 3.0).sqrt() * q.max_edge / q.min_altitude
    } else {
        f64::INFINITY
    };
    (chi, altitude)
}

/// The outcome of the distortion check of Box 8.1 over a whole mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct DistortionCheck {
    /// Whether some element's collapse ratio exceeds the limit (Box 8.1's
    /// `REMESHING_STATUS = "YES"`).
    pub remesh: bool,
    /// The largest collapse ratio of the mesh (1 for a mesh of regular tetrahedra), the quality
    /// measure a remeshing record reports before and after.
    pub worst_ratio: f64,
    /// The element with the largest ratio (the lowest id among equals); 0 for an empty mesh.
    pub worst_element: usize,
    /// Number of elements whose ratio exceeds the limit.
    pub distorted: usize,
}

/// The distortion check of Box 8.1 on the mesh `tets` at the current coordinates `x`: every
/// element's collapse ratio (8.1) against `limit` ([`COLLAPSE_RATIO_LIMIT`] in the thesis).
///
/// Box 8.1 leaves its loop at the first distorted element; this check visits them all, so that
/// the record can say how many there are and which one is worst. The answer to "remesh?" is the
/// same. An element whose ratio is NaN (non-finite coordinates) counts as distorted.
pub fn check_distortion(x: &[Vector3<f64>], tets: &[[u32; 4]], limit: f64) -> DistortionCheck {
    let mut check = DistortionCheck {
        remesh: false,
        worst_ratio: 0.0,
        worst_element: 0,
        distorted: 0,
    };
    for (e, tet) in tets.iter().enumerate() {
        let chi = collapse_ratio(&tet.map(|n| x[n as usize]));
        if !(chi <= limit) {
            check.distorted += 1;
            check.remesh = true;
        }
        // NaN is the worst there is.
        if chi > check.worst_ratio || (chi.is_nan() && !check.worst_ratio.is_nan()) {
            check.worst_ratio = chi;
            check.worst_element = e;
        }
    }
    check
}

/// The Jacobian of deformation `J_e = det F_e` of every element between the coordinates
/// `reference` and `current` (8.6, Box 8.2). For the linear tetrahedron `F` is constant and
/// `det F = v / V`, the ratio of the current to the reference volume, which is what is computed
/// (Box 8.2 builds `F` from the shape-function gradients first; the value is the same to
/// round-off). A reference volume that is not positive is an error naming the element.
pub fn deformation_jacobians(
    reference: &[Vector3<f64>],
    current: &[Vector3<f64>],
    tets: &[[u32; 4]],
) -> Result<Vec<f64>> {
    tets.iter()
        .enumerate()
        .map(|(e, tet)| {
            let v0 = signed_volume(&tet.map(|n| reference[n as usize]));
            if !(v0 > 0.0) {
                return Err(SolverError::Remesh {
                    entity: format!("element {e}"),
                    message: format!(
                        "reference volume {v0:.6e} m^3 is not positive, so det F is undefined"
                    ),
                });
            }
            Ok(signed_volume(&tet.map(|n| current[n as usize])) / v0)
        })
        .collect()
}

/// Which extreme of the Jacobian the refinement criterion compares with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianExtreme {
    /// The thesis as written, (8.3)-(8.4): `det F_e > delta * max_e det F_e`. It selects the
    /// elements that expanded most. With every `det F` near 1 (small strain, or a body at rest)
    /// it selects nearly every element: `1 > 0.85 * 1`.
    Largest,
    /// Our reading for penetration, where the material ahead of the impactor is compressed
    /// (`det F < 1`): the size of the volume change `|ln det F_e|` compared with its largest
    /// value, `|ln det F_e| > delta * max_e |ln det F_e|`. It treats compression and expansion
    /// alike and selects nothing in an undeformed body (the comparison is strict and the largest
    /// value is 0), which is the behaviour a refinement driven by deformation should have.
    LogVolumeChange,
}

/// The refinement criterion (8.4)-(8.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefinementCriteria {
    /// The scaling coefficient `delta` of (8.4), [`REFINEMENT_DELTA`] in the thesis.
    pub delta: f64,
    /// The smallest element volume `V_min` (m^3) of (8.5): an element of this volume or less is
    /// not refined again, so that repeated refinement cannot collapse the elements.
    pub min_volume: f64,
    /// Which extreme `delta` scales ([`JacobianExtreme::Largest`] is the thesis as written).
    pub extreme: JacobianExtreme,
}

impl RefinementCriteria {
    /// The thesis' criterion (8.5): `delta = 0.85` against the largest `det F`, with the given
    /// smallest volume (m^3).
    pub fn thesis(min_volume: f64) -> Self {
        Self {
            delta: REFINEMENT_DELTA,
            min_volume,
            extreme: JacobianExtreme::Largest,
        }
    }
}

/// The elements over which the mesh is refined, ascending (8.5): those whose `det F_e` passes
/// `delta` times the extreme value ([`JacobianExtreme`]) and whose volume `volume[e]` (the
/// current one, m^3) exceeds `V_min`.
///
/// `jacobian[e]` is `det F` of element `e` since the stress-free configuration (after an earlier
/// remeshing, the product with the carried deformation's `det F_0`); see
/// [`deformation_jacobians`]. A non-finite or non-positive Jacobian is an error naming the
/// element: an inverted element cannot be refined, the run must stop.
pub fn refinement_region(
    jacobian: &[f64],
    volume: &[f64],
    criteria: &RefinementCriteria,
) -> Result<Vec<usize>> {
    if jacobian.len() != volume.len() {
        return Err(SolverError::Remesh {
            entity: "refinement region".to_string(),
            message: format!(
                "{} Jacobians for {} element volumes",
                jacobian.len(),
                volume.len()
            ),
        });
    }
    if let Some(e) = jacobian.iter().position(|j| !(j.is_finite() && *j > 0.0)) {
        return Err(SolverError::Remesh {
            entity: format!("element {e}"),
            message: format!("det F = {} is not a positive number", jacobian[e]),
        });
    }
    let measure = |j: f64| match criteria.extreme {
        JacobianExtreme::Largest => j,
        JacobianExtreme::LogVolumeChange => j.ln().abs(),
    };
    // (8.3): the extreme value over all elements.
    let extreme = jacobian
        .iter()
        .map(|&j| measure(j))
        .fold(f64::NEG_INFINITY, f64::max);
    let threshold = criteria.delta * extreme;
    Ok((0..jacobian.len())
        .filter(|&e| measure(jacobian[e]) > threshold && volume[e] > criteria.min_volume)
        .collect())
}

/// The connected parts of a refinement region (thesis 8.3: "the procedure can form space
/// regions that are not connected between each other. In this case, each `Omega_r` should be
/// treated separately"). Two elements of `region` are connected when they share a node. Each
/// part lists its elements ascending; parts are ordered by their first element.
pub fn region_parts(tets: &[[u32; 4]], region: &[usize]) -> Vec<Vec<usize>> {
    // Union-find over the region's elements, joined through a map node -> first element seen.
    let mut parent: Vec<usize> = (0..region.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut owner = std::collections::BTreeMap::new();
    for (i, &e) in region.iter().enumerate() {
        for &n in &tets[e] {
            match owner.get(&n) {
                None => {
                    owner.insert(n, i);
                }
                Some(&j) => {
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    // The smaller index becomes the root, so the result does not depend on the
                    // order of the unions.
                    let (lo, hi) = (a.min(b), a.max(b));
                    parent[hi] = lo;
                }
            }
        }
    }
    let mut sorted: Vec<usize> = region.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let index_of: std::collections::BTreeMap<usize, usize> =
        region.iter().enumerate().map(|(i, &e)| (e, i)).collect();
    let mut parts: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for e in sorted {
        let r = root(&mut parent, index_of[&e]);
        parts.entry(r).or_default().push(e);
    }
    let mut parts: Vec<Vec<usize>> = parts.into_values().collect();
    parts.sort_by_key(|p| p[0]);
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn regular() -> [Vector3<f64>; 4] {
        [
            Vector3::new(1.0, 1.0, 1.0),
            Vector3::new(-1.0, 1.0, -1.0),
            Vector3::new(1.0, -1.0, -1.0),
            Vector3::new(-1.0, -1.0, 1.0),
        ]
    }

    #[test]
    fn regular_tetrahedron_has_ratio_one() {
        assert!(signed_volume(&regular()) > 0.0);
        let chi = collapse_ratio(&regular());
        assert!((chi - 1.0).abs() < 1e-15, "chi = {chi}");
    }

    #[test]
    fn flattened_tetrahedron_is_distorted() {
        // The unit corner tetrahedron has chi = sqrt 2; squash its apex to 5 % of its height,
        // and pull it sideways so that one edge becomes short: chi well above 10.
        let mut x = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        assert!((collapse_ratio(&x) - 2f64.sqrt()).abs() < 1e-15);
        x[3] = Vector3::new(0.95, 0.0, 0.05);
        let chi = collapse_ratio(&x);
        // Shortest edge |x3 - x1| = sqrt(0.05^2 + 0.05^2), longest |x2 - x3| > 1.
        assert!(chi > COLLAPSE_RATIO_LIMIT, "chi = {chi}");
        let tets = [[0, 1, 2, 3], [0, 1, 2, 3]];
        let check = check_distortion(&x, &tets, COLLAPSE_RATIO_LIMIT);
        assert!(check.remesh);
        assert_eq!(check.distorted, 2);
        assert_eq!(check.worst_element, 0);
        assert_eq!(check.worst_ratio, chi);
    }

    #[test]
    fn distortion_sees_the_sliver_the_collapse_ratio_misses() {
        // The sliver (1, 0, h), (-1, 0, h), (0, 1, -h), (0, -1, -h): edges 2, 2 and four of
        // sqrt(2 + 4 h^2), so chi = sqrt 2 / sqrt(1 + 2 h^2) whatever h; volume 4h / 3, so
        // eta = 12 (3V)^(2/3) / sum l^2 = 0.75 (4h)^(2/3) / (1 + h^2). Its four faces have the
        // area sqrt(1 + 4 h^2), so every altitude is 3V / area = 4h / sqrt(1 + 4 h^2) and the
        // altitude ratio sqrt(2/3) 2 / h_min = sqrt(2/3) sqrt(1 + 4 h^2) / (2h).
        for h in [0.1, 0.01, 1e-3, 1e-6] {
            let x = [
                Vector3::new(1.0, 0.0, h),
                Vector3::new(-1.0, 0.0, h),
                Vector3::new(0.0, 1.0, -h),
                Vector3::new(0.0, -1.0, -h),
            ];
            assert!((signed_volume(&x) - 4.0 * h / 3.0).abs() < 1e-15);
            let chi = collapse_ratio(&x);
            assert!(chi < 1.5, "chi = {chi}");
            let eta = 0.75 * (4.0 * h).powf(2.0 / 3.0) / (1.0 + h * h);
            let altitude = (2.0f64 / 3.0).sqrt() * (1.0 + 4.0 * h * h).sqrt() / (2.0 * h);
            assert!(
                altitude > 1.0 / eta,
                "h {h}: {altitude} against {}",
                1.0 / eta
            );
            let d = distortion(&x);
            assert!(
                (d / altitude - 1.0).abs() < 1e-12,
                "h {h}: distortion {d}, altitude ratio {altitude}"
            );
            // Caught from h = 0.01 on (altitude ratio 40.8, 1/eta 11.4), where chi stays
            // sqrt 2; at h = 0.1 the altitude ratio is 4.2.
            assert_eq!(d > COLLAPSE_RATIO_LIMIT, h <= 0.01, "h {h}: {d}");
            // Inverted: infinite.
            let flipped = [x[1], x[0], x[2], x[3]];
            assert_eq!(distortion(&flipped), f64::INFINITY);
        }
        // A needle (one edge 0.01 long) has chi = 100 sqrt 2 = 141, above its 1/eta (17) and
        // its altitude ratio (sqrt(2/3) sqrt 2 / h_min = 115, with h_min = 3V over the largest
        // face, 0.01 / sqrt(1.0002)): the distortion is chi.
        let needle = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.01, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let altitude = (4.0f64 / 3.0).sqrt() * 1.0002f64.sqrt() / 0.01;
        assert!((altitude_ratio(&needle) / altitude - 1.0).abs() < 1e-12);
        assert_eq!(distortion(&needle), collapse_ratio(&needle));
        assert!((distortion(&regular()) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn undistorted_mesh_needs_no_remeshing() {
        let x = regular();
        let check = check_distortion(&x, &[[0, 1, 2, 3]], COLLAPSE_RATIO_LIMIT);
        assert!(!check.remesh);
        assert_eq!(check.distorted, 0);
        // A coincident pair of nodes is infinitely distorted.
        let mut y = x;
        y[1] = y[0];
        assert!(check_distortion(&y, &[[0, 1, 2, 3]], COLLAPSE_RATIO_LIMIT).remesh);
    }

    #[test]
    fn jacobian_is_the_volume_ratio() {
        let x = regular();
        let tets = [[0, 1, 2, 3]];
        // Stretch by 2 along x and 0.5 along z: det F = 1; then by 3 along y: det F = 3.
        let y: Vec<_> = x
            .iter()
            .map(|p| Vector3::new(2.0 * p.x, 3.0 * p.y, 0.5 * p.z))
            .collect();
        let j = deformation_jacobians(&x, &y, &tets).unwrap();
        assert!((j[0] - 3.0).abs() < 1e-14, "{j:?}");
    }

    #[test]
    fn refinement_region_follows_8_5() {
        let jacobian = [1.0, 1.2, 0.9, 1.19, 1.01, 0.5];
        let volume = [1.0, 1.0, 1.0, 1e-9, 1.0, 1.0];
        let thesis = RefinementCriteria::thesis(1e-6);
        // 0.85 * 1.2 = 1.02: elements 1 and 3 pass, element 3 is below V_min.
        assert_eq!(
            refinement_region(&jacobian, &volume, &thesis).unwrap(),
            vec![1]
        );
        let log = RefinementCriteria {
            extreme: JacobianExtreme::LogVolumeChange,
            ..thesis
        };
        // |ln J| largest for 0.5 (0.693); 0.85 * 0.693 = 0.589: only element 5.
        assert_eq!(
            refinement_region(&jacobian, &volume, &log).unwrap(),
            vec![5]
        );
        // At rest: the thesis' reading selects everything, the log reading nothing.
        let rest = [1.0; 4];
        assert_eq!(
            refinement_region(&rest, &[1.0; 4], &thesis).unwrap().len(),
            4
        );
        assert!(refinement_region(&rest, &[1.0; 4], &log)
            .unwrap()
            .is_empty());
        assert!(refinement_region(&[1.0, -0.1], &[1.0; 2], &thesis).is_err());
        assert!(refinement_region(&[1.0], &[1.0; 2], &thesis).is_err());
    }

    #[test]
    fn region_parts_split_disconnected_sets() {
        let tets = [
            [0, 1, 2, 3],
            [1, 2, 3, 4],
            [5, 6, 7, 8],
            [8, 9, 10, 11],
            [12, 13, 14, 15],
        ];
        assert_eq!(
            region_parts(&tets, &[3, 0, 1, 4, 2]),
            vec![vec![0, 1], vec![2, 3], vec![4]]
        );
        assert_eq!(region_parts(&tets, &[4, 0]), vec![vec![0], vec![4]]);
        assert!(region_parts(&tets, &[]).is_empty());
    }
}
