//! Steps 1 and 2 of the method (module `mesher`): the region checked, its edges marked, the
//! nodes numbered and the region's elements subdivided ([`split_region`]).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

use super::{edge_key, remesh_error, MesherOptions, TET_EDGES};
use crate::error::Result;
use crate::kinematics::signed_volume;
use crate::mesh::ops::subdivision::{face_triangles, red_refinement};
use crate::mesh::{face_key, TET_FACES};

/// The mesh after the subdivision, before the repairs: nodes, elements with their origins,
/// the old nodes kept, and which nodes the repairs may move.
pub(super) struct Draft {
    /// Coordinates of the new mesh's nodes (m).
    pub nodes: Vec<Vector3<f64>>,
    /// The new connectivity: the elements outside the region, then the region's.
    pub tets: Vec<[u32; 4]>,
    /// New element -> the old element it copies unchanged.
    pub origin: Vec<Option<u32>>,
    /// Index of the first element that replaces the region.
    pub first_region_element: usize,
    /// Old node id -> new node id for the nodes kept.
    pub kept_nodes: Vec<Option<u32>>,
    /// The nodes free to move: the region's inner old nodes, the midpoints of its inner edges
    /// and the centroids.
    pub movable: Vec<u32>,
    /// Old nodes of elements outside the region: they never move (the interface stays
    /// conforming).
    pub outside: Vec<bool>,
}

/// The region, ascending and without duplicates, and which elements it holds; an error for an
/// empty region, an element out of range or one whose current volume is not positive.
fn checked_region(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
) -> Result<(Vec<usize>, Vec<bool>)> {
    let region: Vec<usize> = region
        .iter()
        .copied()
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    if region.is_empty() {
        return Err(remesh_error(
            "refinement region",
            "is empty: nothing to remesh".to_string(),
        ));
    }
    let mut in_region = vec![false; tets.len()];
    for &e in &region {
        if e >= tets.len() {
            return Err(remesh_error(
                &format!("region element {e}"),
                format!("out of range: the mesh has {} elements", tets.len()),
            ));
        }
        in_region[e] = true;
        let v = signed_volume(&tets[e].map(|n| x[n as usize]));
        if !(v > 0.0) {
            return Err(remesh_error(
                &format!("element {e}"),
                format!("current volume {v:.6e} m^3 is not positive: it cannot be remeshed"),
            ));
        }
    }
    Ok((region, in_region))
}

/// Faces: how many region and other elements hold each one; an error where a face has more
/// than two (the mesh is not conforming).
fn face_counts(tets: &[[u32; 4]], in_region: &[bool]) -> Result<HashMap<[u32; 3], (u8, u8)>> {
    let mut faces: HashMap<[u32; 3], (u8, u8)> = HashMap::with_capacity(4 * tets.len());
    for (e, tet) in tets.iter().enumerate() {
        for f in TET_FACES {
            let c = faces.entry(face_key(f.map(|i| tet[i]))).or_insert((0, 0));
            if in_region[e] {
                c.0 += 1;
            } else {
                c.1 += 1;
            }
            if c.0 + c.1 > 2 {
                return Err(remesh_error(
                    &format!("element {e}"),
                    "shares a face with two other elements: the mesh is not conforming".into(),
                ));
            }
        }
    }
    Ok(faces)
}

/// Step 1: which old nodes are fixed, and which edges are split.
struct EdgeMarks {
    /// Old nodes that keep their place: those of elements outside the region, and those of the
    /// region's faces on the outer boundary.
    fixed: Vec<bool>,
    /// Old nodes of elements outside the region.
    outside: Vec<bool>,
    /// Old nodes of the region's elements.
    region_node: Vec<bool>,
    /// Boundary edges of the region (for midpoints that must not move).
    boundary_edges: BTreeSet<(u32, u32)>,
    /// The edges split at their midpoints.
    marked: BTreeSet<(u32, u32)>,
}

/// Step 1 of the method: every edge of a region element long enough to halve (`min_edge`) is
/// split, unless `keep_edge` holds for it or it is an edge of an element outside the region
/// (which must not be split).
fn mark_edges(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    in_region: &[bool],
    options: &MesherOptions,
    keep_edge: &dyn Fn(u32, u32) -> bool,
) -> Result<EdgeMarks> {
    let faces = face_counts(tets, in_region)?;
    let mut fixed = vec![false; x.len()];
    let mut outside = vec![false; x.len()];
    let mut region_node = vec![false; x.len()];
    for &e in region {
        for n in tets[e] {
            region_node[n as usize] = true;
        }
    }
    let mut boundary_edges = BTreeSet::new();
    for &e in region {
        for f in TET_FACES {
            let face = f.map(|i| tets[e][i]);
            if faces[&face_key(face)] == (1, 0) {
                for k in 0..3 {
                    fixed[face[k] as usize] = true;
                    boundary_edges.insert(edge_key(face[k], face[(k + 1) % 3]));
                }
            }
        }
    }
    let mut marked: BTreeSet<(u32, u32)> = region
        .iter()
        .flat_map(|&e| TET_EDGES.map(|[i, j]| edge_key(tets[e][i], tets[e][j])))
        .filter(|&(a, b)| (x[a as usize] - x[b as usize]).norm() >= 2.0 * options.min_edge)
        .filter(|&(a, b)| !keep_edge(a, b))
        .collect();
    for (e, tet) in tets.iter().enumerate() {
        if in_region[e] {
            continue;
        }
        for n in tet {
            fixed[*n as usize] = true;
            outside[*n as usize] = true;
        }
        if tet.iter().any(|n| region_node[*n as usize]) {
            for [i, j] in TET_EDGES {
                marked.remove(&edge_key(tet[i], tet[j]));
            }
        }
    }
    Ok(EdgeMarks {
        fixed,
        outside,
        region_node,
        boundary_edges,
        marked,
    })
}

/// The new numbering: kept old nodes in old order, then the region's inner old nodes, then the
/// midpoints (ascending edge). Returns the new id of every old node, the kept ones, the nodes,
/// the movable ones and each split edge's midpoint.
#[allow(clippy::type_complexity)]
fn number_nodes(
    x: &[Vector3<f64>],
    marks: &EdgeMarks,
    region_len: usize,
) -> (
    Vec<u32>,
    Vec<Option<u32>>,
    Vec<Vector3<f64>>,
    Vec<u32>,
    BTreeMap<(u32, u32), u32>,
) {
    let (fixed, region_node) = (&marks.fixed, &marks.region_node);
    let mut new_id = vec![0u32; x.len()];
    let mut kept_nodes = vec![None; x.len()];
    let mut nodes = Vec::with_capacity(x.len() + marks.marked.len() + region_len);
    let mut movable = Vec::new();
    for n in 0..x.len() {
        if !region_node[n] || fixed[n] {
            new_id[n] = nodes.len() as u32;
            kept_nodes[n] = Some(new_id[n]);
            nodes.push(x[n]);
        }
    }
    for n in 0..x.len() {
        if region_node[n] && !fixed[n] {
            new_id[n] = nodes.len() as u32;
            movable.push(new_id[n]);
            nodes.push(x[n]);
        }
    }
    let mut midpoint = BTreeMap::new();
    for &(a, b) in &marks.marked {
        let id = nodes.len() as u32;
        midpoint.insert((a, b), id);
        if !marks.boundary_edges.contains(&(a, b)) {
            movable.push(id);
        }
        nodes.push(0.5 * (x[a as usize] + x[b as usize]));
    }
    (new_id, kept_nodes, nodes, movable, midpoint)
}

/// Steps 1 and 2 of the method: the region's edges marked, the nodes numbered, and each region
/// element kept, refined (red, all six edges split) or coned from its centroid (a new node,
/// numbered after the midpoints in ascending element order).
pub(super) fn split_region(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    options: &MesherOptions,
    keep_edge: &dyn Fn(u32, u32) -> bool,
) -> Result<Draft> {
    let (region, in_region) = checked_region(x, tets, region)?;
    let marks = mark_edges(x, tets, &region, &in_region, options, keep_edge)?;
    let (new_id, kept_nodes, mut nodes, mut movable, midpoint) =
        number_nodes(x, &marks, region.len());
    let outside = marks.outside;
    let mut out_tets: Vec<[u32; 4]> = Vec::with_capacity(tets.len() + 8 * region.len());
    let mut origin = Vec::with_capacity(out_tets.capacity());
    for (e, tet) in tets.iter().enumerate() {
        if !in_region[e] {
            out_tets.push(tet.map(|n| new_id[n as usize]));
            origin.push(Some(e as u32));
        }
    }
    let first_region_element = out_tets.len();
    // Midpoint of the old edge (a, b) as a new node id, if the edge is split.
    let mid = |a: u32, b: u32| midpoint.get(&edge_key(a, b)).copied();
    for &e in &region {
        let old = tets[e];
        let v = old.map(|n| new_id[n as usize]);
        let count = TET_EDGES
            .iter()
            .filter(|[i, j]| mid(old[*i], old[*j]).is_some())
            .count();
        if count == 0 {
            // Unsplit: a copy where no node can move (all held by elements outside), else a
            // new element that the smoothing and the collapses may change.
            out_tets.push(v);
            let copy = old.iter().all(|&n| outside[n as usize]);
            origin.push(copy.then_some(e as u32));
        } else if count == 6 {
            let m = |i: usize, j: usize| mid(old[i], old[j]).expect("all six edges are split");
            red_refinement(v, m, &nodes, &mut out_tets);
            origin.resize(out_tets.len(), None);
        } else {
            let centroid = nodes.len() as u32;
            movable.push(centroid);
            nodes.push(0.25 * old.iter().map(|&n| x[n as usize]).sum::<Vector3<f64>>());
            for f in TET_FACES {
                let face_old = f.map(|i| old[i]);
                for t in face_triangles(face_old, &mid, &new_id, &nodes) {
                    out_tets.push([t[0], t[2], t[1], centroid]);
                    origin.push(None);
                }
            }
        }
    }
    Ok(Draft {
        nodes,
        tets: out_tets,
        origin,
        first_region_element,
        kept_nodes,
        movable,
        outside,
    })
}
