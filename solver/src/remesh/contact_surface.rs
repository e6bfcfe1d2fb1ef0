//! New surface nodes of a remeshed body that start inside a contact partner.
//!
//! Two faceted surfaces in contact cross each other between their nodes: node-to-segment
//! contact keeps each slave node on the master's faces, not the faces themselves apart. A node
//! that the refinement adds on a face of the remeshed body (an edge's midpoint) can so lie
//! inside the other body, by the gap between a facet and the partner's curved or kinked faceted
//! surface (of order `kappa h^2 / 8` for a curvature `kappa` and cell `h`). Left there, the
//! first contact correction after the remeshing pushes it out within one step, at a velocity
//! `depth / dt`: for 10 um over a step of 50 ns, 200 m/s. So the node is placed on the partner's
//! surface before the transfer: the new mesh's geometry moves by that depth at such nodes, its
//! fields do not (the carried `F_0` and the velocities are transferred to the moved position).

use nalgebra::Vector3;

use super::locate::Locator;
use crate::contact::geometry::closest_point_on_triangle;
use crate::mesh::boundary_faces_of;
use crate::model::Model;

/// What [`separate_new_surface_nodes`] moved.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SurfaceSeparation {
    /// New surface nodes moved out of a contact partner.
    pub moved: usize,
    /// The largest distance moved (m).
    pub largest_depth: f64,
}

/// Moves each of the `candidates` (ids into `nodes`, the remeshed body's new nodes, current
/// coordinates) that lies inside one of the contact partners onto the nearest point of that
/// partner's boundary. `partners` gives each partner's body in `model` with a locator over its
/// elements at the current coordinates `x`. A node counts as inside when the partner holds it
/// strictly ([`Locator::holds_strictly`]), so a node on the partner's surface stays where it is.
pub(super) fn separate_new_surface_nodes(
    model: &Model,
    x: &[Vector3<f64>],
    partners: &[(usize, Locator)],
    nodes: &mut [Vector3<f64>],
    candidates: &[u32],
) -> SurfaceSeparation {
    let mut out = SurfaceSeparation::default();
    for (o, locator) in partners {
        let faces = boundary_faces_of(&model.tets[model.bodies[*o].elements.clone()]);
        for &n in candidates {
            let p = nodes[n as usize];
            if !locator.holds_strictly(&p) {
                continue;
            }
            let mut best = (f64::INFINITY, p);
            for f in &faces {
                let [a, b, c] = f.nodes.map(|i| x[i as usize]);
                let q = closest_point_on_triangle(&p, &a, &b, &c);
                let d = (q - p).norm();
                if d < best.0 {
                    best = (d, q);
                }
            }
            nodes[n as usize] = best.1;
            out.moved += 1;
            out.largest_depth = out.largest_depth.max(best.0);
        }
    }
    out
}
