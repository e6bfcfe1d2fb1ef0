//! Geometric node selectors: which nodes of a body a condition acts on.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Picks nodes of a body by their reference position or by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Selector {
    /// Every node of the body.
    All,
    /// The nodes on the boundary surface of the body's mesh.
    Boundary,
    /// Nodes inside the axis-aligned box `[min, max]` (closed, with a relative tolerance).
    Box {
        /// Lower corner (m), in the placed body's reference coordinates.
        min: [f64; 3],
        /// Upper corner (m), componentwise at least `min`.
        max: [f64; 3],
    },
    /// Nodes within `tolerance` (m; default a millionth of the body size) of the plane through
    /// `point` with normal `normal`.
    Plane {
        /// A point of the plane (m), in the placed body's reference coordinates.
        point: [f64; 3],
        /// Normal of the plane (any length but zero).
        normal: [f64; 3],
        /// Largest distance from the plane of a selected node (m); default a millionth of the
        /// body size.
        #[serde(default)]
        tolerance: Option<f64>,
    },
    /// A named node set of the mesh (a Gmsh physical group).
    Group(String),
    /// Explicit node ids, local to the body.
    Nodes(Vec<u32>),
}

impl Selector {
    /// Whether a node at reference position `x` is selected (for the geometric selectors);
    /// `scale` is the body size, so tolerances are relative to it.
    pub fn contains(&self, x: &Vector3<f64>, scale: f64) -> Option<bool> {
        match self {
            Selector::All => Some(true),
            Selector::Box { min, max } => {
                let tol = 1e-9 * scale;
                Some((0..3).all(|a| x[a] >= min[a] - tol && x[a] <= max[a] + tol))
            }
            Selector::Plane {
                point,
                normal,
                tolerance,
            } => {
                let n = Vector3::from(*normal);
                let d = (x - Vector3::from(*point)).dot(&n) / n.norm();
                Some(d.abs() <= tolerance.unwrap_or(1e-6 * scale))
            }
            Selector::Group(_) | Selector::Nodes(_) | Selector::Boundary => None,
        }
    }
}
