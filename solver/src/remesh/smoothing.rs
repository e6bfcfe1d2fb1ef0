//! Node smoothing of the remeshed region (step 3 of the method in `mesher.rs`): inner nodes
//! move freely, nodes on the outer boundary slide within the axis-aligned planes of their faces
//! (symmetry planes), and a move is taken only where it raises the worst element around.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

use super::mesher::shape_quality;
use crate::mesh::{face_key, TET_FACES};

/// How far apart (m) two coordinates may be and still put their nodes in one axis plane: a few
/// round-offs of the largest coordinate. A node placed on a symmetry plane by a projection (a
/// surface node moved out of a contact partner) can be off it by 1e-20 m.
pub(super) fn plane_tolerance(nodes: &[Vector3<f64>]) -> f64 {
    4.0 * f64::EPSILON * nodes.iter().map(|p| p.amax()).fold(0.0, f64::max)
}

/// The nodes on the outer boundary of the remeshed region `tets` that may slide without
/// changing the body's shape, each with the axes along which it may move, and those on a
/// curved part of it.
///
/// A face that only one region element holds is on the outer boundary or on the interface
/// with the untouched mesh; the interface's nodes are `pinned`. A boundary face whose three
/// nodes share a coordinate `k` (to [`plane_tolerance`]) lies in the plane `x_k = const` (a
/// symmetry plane, or a flat face not yet deformed). A node all of whose boundary faces lie
/// in such planes may move along the axes none of those planes fixes: in its plane, or along the line where two
/// planes meet (the axis of a quarter model). It stays in the union of its faces as long as none
/// of its elements inverts, which the smoothing ensures, so the boundary keeps its shape
/// exactly. A node with a face in no axis plane (a curved or deformed surface) does not move.
/// Without this, an element whose nodes all lie on symmetry planes (at the axis under a
/// penetrator) could not be reshaped: refinement alone gives children as flat as itself.
pub(super) fn boundary_nodes(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    pinned: &[bool],
) -> BoundaryNodes {
    let mut kinds = BoundaryNodes::default();
    for (n, (axes, curved)) in boundary_planes(nodes, tets, pinned) {
        if curved {
            kinds.surface.push((n, axes));
        } else if axes.iter().filter(|&&h| h).count() < 3 {
            kinds.sliding.push((n, axes.map(|h| !h)));
        }
    }
    kinds
}

/// The nodes on the outer boundary of a remeshed region, by what the remesher may do with them
/// ([`boundary_nodes`]). Both lists ascend.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct BoundaryNodes {
    /// Nodes whose boundary faces all lie in axis planes, with the axes along which they may
    /// slide (smoothing and collapses keep the boundary's shape exactly).
    pub sliding: Vec<(u32, [bool; 3])>,
    /// Nodes with a face on a curved or deformed surface (in no axis plane), each with the axes
    /// its other faces' planes fix (a node where the surface meets a symmetry plane): those an
    /// edge collapse may merge along the surface (`collapse.rs`).
    pub surface: Vec<(u32, [bool; 3])>,
}

/// Per node on the outer boundary of `tets` (less the `pinned`): the axes that the planes of
/// its boundary faces in axis planes fix, and whether it has a face in no axis plane. Ordered
/// by node id, so the callers do not depend on hashing.
fn boundary_planes(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    pinned: &[bool],
) -> BTreeMap<u32, ([bool; 3], bool)> {
    let tolerance = plane_tolerance(nodes);
    let mut count: HashMap<[u32; 3], u32> = HashMap::with_capacity(4 * tets.len());
    for tet in tets {
        for f in TET_FACES {
            *count.entry(face_key(f.map(|i| tet[i]))).or_insert(0) += 1;
        }
    }
    let mut planes: BTreeMap<u32, ([bool; 3], bool)> = BTreeMap::new();
    for tet in tets {
        for f in TET_FACES {
            let face = f.map(|i| tet[i]);
            if count[&face_key(face)] != 1 {
                continue;
            }
            let [a, b, c] = face.map(|n| nodes[n as usize]);
            let plane = (0..3).find(|&k| {
                let (lo, hi) = (a[k].min(b[k]).min(c[k]), a[k].max(b[k]).max(c[k]));
                hi - lo <= tolerance
            });
            for n in face {
                if pinned[n as usize] {
                    continue;
                }
                let (axes, curved) = planes.entry(n).or_insert(([false; 3], false));
                match plane {
                    Some(k) => axes[k] = true,
                    None => *curved = true,
                }
            }
        }
    }
    planes
}

/// Constrained Laplacian smoothing of the nodes `movable` over the elements `tets` (step 3 of
/// the method): a move is taken only if it raises the worst quality of the node's elements.
/// Each node moves only along the axes its flags free (all three inside the region).
pub(super) fn smooth(
    nodes: &mut [Vector3<f64>],
    tets: &[[u32; 4]],
    movable: &[(u32, [bool; 3])],
    sweeps: usize,
) {
    let mut incident: BTreeMap<u32, Vec<usize>> =
        movable.iter().map(|&(n, _)| (n, vec![])).collect();
    for (t, tet) in tets.iter().enumerate() {
        for n in tet {
            if let Some(list) = incident.get_mut(n) {
                list.push(t);
            }
        }
    }
    let neighbours: BTreeMap<u32, Vec<u32>> = incident
        .iter()
        .map(|(&n, list)| {
            let set: BTreeSet<u32> = list
                .iter()
                .flat_map(|&t| tets[t])
                .filter(|&m| m != n)
                .collect();
            (n, set.into_iter().collect())
        })
        .collect();
    let worst = |nodes: &[Vector3<f64>], list: &[usize]| {
        list.iter()
            .map(|&t| shape_quality(&tets[t].map(|n| nodes[n as usize])))
            .fold(f64::INFINITY, f64::min)
    };
    for _ in 0..sweeps {
        let mut moved = false;
        for &(n, free) in movable {
            let list = &incident[&n];
            let around = &neighbours[&n];
            if around.is_empty() {
                continue;
            }
            let current = nodes[n as usize];
            let mean = around
                .iter()
                .map(|&m| nodes[m as usize])
                .sum::<Vector3<f64>>()
                / around.len() as f64;
            let mut best = (worst(nodes, list), current);
            // The Laplacian candidates, then a pattern search along the axes with a step of a
            // tenth of the mean distance to the neighbours, halved until one improves.
            let spacing = around
                .iter()
                .map(|&m| (nodes[m as usize] - current).norm())
                .sum::<f64>()
                / around.len() as f64;
            let mut candidates = vec![mean, 0.5 * (current + mean)];
            for step in [0.1, 0.05, 0.025] {
                for axis in (0..3).filter(|&k| free[k]) {
                    for sign in [1.0, -1.0] {
                        let mut c = current;
                        c[axis] += sign * step * spacing;
                        candidates.push(c);
                    }
                }
            }
            for candidate in candidates {
                // A sliding node keeps its held coordinates bit for bit.
                let candidate =
                    Vector3::from_fn(|k, _| if free[k] { candidate[k] } else { current[k] });
                nodes[n as usize] = candidate;
                let q = worst(nodes, list);
                if q > best.0 {
                    best = (q, candidate);
                }
            }
            nodes[n as usize] = best.1;
            moved |= best.1 != current;
        }
        if !moved {
            break;
        }
    }
}
