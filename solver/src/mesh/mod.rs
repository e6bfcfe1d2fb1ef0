//! Meshes of linear tetrahedra: storage, validation, boundary, quality, generators and readers.

mod boundary;
mod generate;
pub mod gmsh;
mod gmsh_tags;
mod numbering;
pub mod ops;
mod quality;

use std::collections::BTreeMap;

use nalgebra::Vector3;

pub use boundary::{boundary_faces, boundary_faces_of, boundary_nodes, face_key, BoundaryFace};
pub use generate::{box_mesh, perturb_interior, Axis, BoxSpec};
pub use quality::{edge_extremes, element_quality, ElementQuality};

use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;

/// The four faces of a tetrahedron `(0,1,2,3)` as local node triples, each ordered so that its
/// right-hand normal points out of a positively oriented element. Face `k` is opposite node `k`.
pub const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// A mesh of linear tetrahedra in its reference configuration.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Reference coordinates of the nodes (m).
    pub nodes: Vec<Vector3<f64>>,
    /// Connectivity, numbered so that every volume is positive (thesis 3.3).
    pub tets: Vec<[u32; 4]>,
    /// Named node sets, for example Gmsh physical groups, usable by boundary-condition selectors.
    pub node_sets: BTreeMap<String, Vec<u32>>,
}

impl Mesh {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of tetrahedra.
    pub fn element_count(&self) -> usize {
        self.tets.len()
    }

    /// Reference coordinates of element `e`'s four nodes.
    pub fn element_nodes(&self, e: usize) -> [Vector3<f64>; 4] {
        self.tets[e].map(|n| self.nodes[n as usize])
    }

    /// Checks the connectivity, the orientation and the shape of every element.
    ///
    /// Rejects (with the element id): a node index out of range, a volume that is not positive,
    /// and an element whose smallest altitude is below `min_altitude_ratio` times its longest edge
    /// (a sliver that would throttle the stable time step). `name` labels the mesh in messages.
    pub fn validate(&self, name: &str, min_altitude_ratio: f64) -> Result<()> {
        for (e, tet) in self.tets.iter().enumerate() {
            if let Some(&node) = tet.iter().find(|&&n| n as usize >= self.nodes.len()) {
                return Err(SolverError::NodeOutOfRange {
                    mesh: name.to_string(),
                    element: e,
                    node,
                    count: self.nodes.len(),
                });
            }
            let x = self.element_nodes(e);
            let volume = signed_volume(&x);
            if !(volume > 0.0) {
                return Err(SolverError::InvertedElement {
                    mesh: name.to_string(),
                    element: e,
                    volume,
                    nodes: *tet,
                });
            }
            let q = element_quality(&x);
            let ratio = q.min_altitude / q.max_edge;
            if ratio < min_altitude_ratio {
                return Err(SolverError::DegenerateElement {
                    mesh: name.to_string(),
                    element: e,
                    altitude: q.min_altitude,
                    edge: q.max_edge,
                    ratio,
                    limit: min_altitude_ratio,
                });
            }
        }
        Ok(())
    }

    /// Axis-aligned bounding box `(min, max)` of the reference nodes.
    pub fn bounding_box(&self) -> (Vector3<f64>, Vector3<f64>) {
        bounding_box(&self.nodes)
    }

    /// Total reference volume (m^3).
    pub fn volume(&self) -> f64 {
        (0..self.tets.len())
            .map(|e| signed_volume(&self.element_nodes(e)))
            .sum()
    }
}

/// Default lower bound on (smallest altitude / longest edge) accepted by [`Mesh::validate`].
pub const DEFAULT_MIN_ALTITUDE_RATIO: f64 = 1e-6;

/// Axis-aligned bounding box `(min, max)` of `points` (infinities for none).
pub fn bounding_box(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for x in points {
        lo = lo.inf(x);
        hi = hi.sup(x);
    }
    (lo, hi)
}
