//! Boundary faces and nodes by hashing sorted face keys: linear in the number of elements,
//! instead of the pairwise face comparison of thesis Box 7.1.

use std::collections::HashMap;

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
    let mut count: HashMap<[u32; 3], u32> = HashMap::with_capacity(tets.len() * 2);
    let key = face_key;
    for tet in tets {
        for face in TET_FACES {
            *count.entry(key(face.map(|i| tet[i]))).or_insert(0) += 1;
        }
    }
    let mut faces = Vec::new();
    for (e, tet) in tets.iter().enumerate() {
        for (k, face) in TET_FACES.iter().enumerate() {
            let nodes = face.map(|i| tet[i]);
            if count[&key(nodes)] == 1 {
                faces.push(BoundaryFace {
                    nodes,
                    element: e as u32,
                    local_face: k as u8,
                });
            }
        }
    }
    faces
}

/// Sorted, unique node ids of the boundary faces.
pub fn boundary_nodes(faces: &[BoundaryFace]) -> Vec<u32> {
    let mut nodes: Vec<u32> = faces.iter().flat_map(|f| f.nodes).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}
