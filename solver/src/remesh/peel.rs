//! Peeling of boundary slivers, the remesher's last repair (step 6 of the method in
//! `mesher.rs`).
//!
//! An element with all four nodes on a curved part of the outer boundary (the cavity around a
//! penetrator's nose) cannot be reshaped: none of its nodes moves (a curved surface would lose
//! its shape), it has no inner face to flip, and a collapse would move the surface. When such an
//! element is a sliver lying on the surface with two of its faces on it, it is removed ("peeled",
//! as boundary slivers are in Delaunay refinement: Cheng, Dey & Shewchuk 2012, *Delaunay Mesh
//! Generation*, 10.4): its two inner faces become the boundary. The surface moves inward by at
//! most the sliver's height, away from whatever presses on it (material is removed, none added),
//! and the body keeps its mass: the transfer gives the region's new elements exactly the mass of
//! the old ones they replace (`apply.rs`).

use std::collections::HashMap;

use nalgebra::Vector3;

use super::mesher::shape_quality;
use crate::mesh::{face_key, TET_FACES};

/// The quality ([`shape_quality`]) below which a boundary sliver is peeled: a collapse ratio or
/// inverse mean ratio of 10, the remeshing limit of the thesis (Box 8.1).
pub(super) const PEEL_QUALITY: f64 = 0.1;

/// A peeled element and, per local face (opposite local node `k`), whether it was on the outer
/// boundary when the element was removed (the other faces became boundary).
pub type PeeledElement = ([u32; 4], [bool; 4]);

/// Removes from `tets` (the whole new mesh) the changeable elements (`k >= first`, `fixed[k -
/// first]` false) of quality below [`PEEL_QUALITY`] with exactly two faces on the outer boundary
/// (held by no other element) and two held by other changeable elements, repeatedly up to
/// `passes` times. Returns the kept elements' indices and the peeled elements, in the order
/// removed. Deterministic.
pub(super) fn peel_boundary_slivers(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    first: usize,
    fixed: &[bool],
    passes: usize,
) -> (Vec<usize>, Vec<PeeledElement>) {
    let mut holders: HashMap<[u32; 3], Vec<usize>> = HashMap::with_capacity(4 * tets.len());
    for (e, tet) in tets.iter().enumerate() {
        for f in TET_FACES {
            holders
                .entry(face_key(f.map(|i| tet[i])))
                .or_default()
                .push(e);
        }
    }
    let mut alive = vec![true; tets.len()];
    let mut peeled = Vec::new();
    for _ in 0..passes {
        let before = peeled.len();
        for e in first..tets.len() {
            if !alive[e] || fixed[e - first] {
                continue;
            }
            let tet = tets[e];
            if shape_quality(&tet.map(|n| nodes[n as usize])) >= PEEL_QUALITY {
                continue;
            }
            let mut outer = [false; 4];
            let mut inner_ok = true;
            for (k, f) in TET_FACES.iter().enumerate() {
                let others: Vec<usize> = holders[&face_key(f.map(|i| tet[i]))]
                    .iter()
                    .copied()
                    .filter(|&o| o != e && alive[o])
                    .collect();
                match others[..] {
                    [] => outer[k] = true,
                    [o] => inner_ok &= o >= first,
                    _ => inner_ok = false,
                }
            }
            if !inner_ok || outer.iter().filter(|&&b| b).count() != 2 {
                continue;
            }
            alive[e] = false;
            peeled.push((tet, outer));
        }
        if peeled.len() == before {
            break;
        }
    }
    ((0..tets.len()).filter(|&e| alive[e]).collect(), peeled)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::signed_volume;

    /// `t` positively oriented over `x`.
    fn oriented(x: &[Vector3<f64>], mut t: [u32; 4]) -> [u32; 4] {
        if signed_volume(&t.map(|n| x[n as usize])) < 0.0 {
            t.swap(2, 3);
        }
        t
    }

    /// A pyramid on the square `a b c d` (apex `e` below), its base split along `a c`, and on
    /// top the sliver `a b c d` (`d` lifted by `lift`), whose top is split along `b d`.
    fn roof(lift: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::new(0.0, 1.0, lift),
            Vector3::new(0.5, 0.5, -1.0),
        ];
        let tets = [[0, 1, 2, 4], [0, 2, 3, 4], [0, 1, 2, 3]]
            .map(|t| oriented(&x, t))
            .to_vec();
        (x, tets)
    }

    #[test]
    fn a_flat_element_with_two_faces_on_the_boundary_is_peeled() {
        let (x, tets) = roof(0.02);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, &[false; 3], 10);
        assert_eq!(kept, vec![0, 1]);
        assert_eq!(peeled.len(), 1);
        let (t, outer) = peeled[0];
        assert_eq!(t, tets[2]);
        // The outer faces are the two that hold the lifted node and the diagonal b d.
        for (k, f) in TET_FACES.iter().enumerate() {
            let face: Vec<u32> = f.iter().map(|&i| t[i]).collect();
            assert_eq!(outer[k], face.contains(&1) && face.contains(&3), "{face:?}");
        }
    }

    #[test]
    fn a_good_element_or_a_copied_one_stays() {
        // Lifted by 1: a well-shaped element on top.
        let (x, tets) = roof(1.0);
        assert!(shape_quality(&tets[2].map(|n| x[n as usize])) > PEEL_QUALITY);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, &[false; 3], 10);
        assert_eq!((kept.len(), peeled.len()), (3, 0));
        // A sliver that copies an old element is never changed.
        let (x, tets) = roof(0.02);
        let (kept, _) = peel_boundary_slivers(&x, &tets, 0, &[false, false, true], 10);
        assert_eq!(kept.len(), 3);
    }
}
