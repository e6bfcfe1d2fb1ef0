//! Boundary faces and nodes by sorting face keys: `O(n log n)` in the number of elements,
//! instead of the pairwise face comparison of thesis Box 7.1.

use super::{Mesh, TET_FACES};

/// A face on the boundary of the mesh, with nodes ordered so that the right-hand normal points
/// out of the body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundaryFace {
    /// The face's three mesh node indices, counter-clockwise seen from outside.
    pub nodes: [u32; 3],
    /// The element that owns the face.
    pub element: u32,
    /// Local face index (the face opposite local node `local_face`).
    pub local_face: u8,
}

/// Faces that belong to exactly one element, in element order (deterministic).
pub fn boundary_faces(mesh: &Mesh) -> Vec<BoundaryFace> {
    boundary_faces_of(&mesh.tets)
}

/// The key of a triangular face independent of its orientation and first node: its node ids in
/// ascending order (two elements share a face when their faces have the same key).
pub fn face_key(face: [u32; 3]) -> [u32; 3] {
    let mut k = face;
    k.sort_unstable();
    k
}

/// Boundary faces of the elements `tets` (a whole mesh, or one body's range of a model);
/// `BoundaryFace::element` indexes `tets`.
pub fn boundary_faces_of(tets: &[[u32; 4]]) -> Vec<BoundaryFace> {
    // Every face as (key, slot = 4 e + k), sorted by key: a face held by one element has a key
    // that neither neighbour in the order shares. Sorting keeps no hash table (a remeshing
    // calls this on the whole body several times; SipHash of 4 faces per element cost more).
    let mut faces: Vec<([u32; 3], u32)> = Vec::with_capacity(4 * tets.len());
    for (e, tet) in tets.iter().enumerate() {
        for (k, face) in TET_FACES.iter().enumerate() {
            faces.push((face_key(face.map(|i| tet[i])), (4 * e + k) as u32));
        }
    }
    faces.sort_unstable();
    let mut single = vec![false; faces.len()];
    for i in 0..faces.len() {
        let key = faces[i].0;
        let shared =
            (i > 0 && faces[i - 1].0 == key) || (i + 1 < faces.len() && faces[i + 1].0 == key);
        if !shared {
            single[faces[i].1 as usize] = true;
        }
    }
    // In element order, as before (the order callers rely on for determinism).
    single
        .iter()
        .enumerate()
        .filter(|(_, s)| **s)
        .map(|(slot, _)| {
            let (e, k) = (slot / 4, slot % 4);
            BoundaryFace {
                nodes: TET_FACES[k].map(|i| tets[e][i]),
                element: e as u32,
                local_face: k as u8,
            }
        })
        .collect()
}

/// Sorted, unique node ids of the boundary faces.
pub fn boundary_nodes(faces: &[BoundaryFace]) -> Vec<u32> {
    let mut nodes: Vec<u32> = faces.iter().flat_map(|f| f.nodes).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}
