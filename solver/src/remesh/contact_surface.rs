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

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::geometry::proximity::closest_point_on_triangle;
use crate::mesh::boundary_faces_of;
use crate::mesh::ops::locate::Locator;
use crate::mesh::ops::peel::PEEL_QUALITY;
use crate::mesh::ops::quality::shape_quality;
use crate::model::Model;

/// What `separate_new_surface_nodes` moved.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SurfaceSeparation {
    /// New surface nodes moved out of a contact partner.
    pub moved: usize,
    /// The largest distance moved (m).
    pub largest_depth: f64,
    /// New surface nodes left inside a partner, because the move would have inverted one of
    /// their elements or collapsed it past the remeshing limit (the contact then pushes them
    /// out).
    pub left_inside: usize,
}

/// Moves each of the `candidates` (ids into `nodes`, the remeshed body's new nodes, current
/// coordinates) that lies inside one of the contact partners onto the nearest point of that
/// partner's boundary. `partners` gives each partner's body in `model` with a locator over its
/// elements at the current coordinates `x`. A node counts as inside when the partner holds it
/// strictly ([`Locator::holds_strictly`]), so a node on the partner's surface stays where it is.
///
/// A move that would give one of the node's elements in `tets` (the new mesh) a volume that is
/// not positive, or a shape worse than both the remeshing limit and its worst element's before,
/// is not made ([`move_keeps_elements_shaped`]): a node generated a little inside a partner,
/// behind which the element is thinner than the depth, stays, and the contact pushes it out
/// over the next steps; moved, it turned the element inside out, or left it flat: a move of
/// 62 um gave an element a distortion of 1119 (the nail, 46.7 us, once cavity nodes slid on
/// the chords of the cavity, which lie inside the nose), whose stable step then took 4.5e-4 kg
/// of mass scaling.
pub(super) fn separate_new_surface_nodes(
    model: &Model,
    x: &[Vector3<f64>],
    partners: &[(usize, Locator)],
    nodes: &mut [Vector3<f64>],
    tets: &[[u32; 4]],
    candidates: &[u32],
) -> SurfaceSeparation {
    let mut out = SurfaceSeparation::default();
    let mut held_by: HashMap<u32, Vec<usize>> =
        candidates.iter().map(|&n| (n, Vec::new())).collect();
    for (e, t) in tets.iter().enumerate() {
        for n in t {
            if let Some(list) = held_by.get_mut(n) {
                list.push(e);
            }
        }
    }
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
            let elements: Vec<[u32; 4]> = held_by[&n].iter().map(|&e| tets[e]).collect();
            if !move_keeps_elements_shaped(nodes, &elements, n, best.1) {
                out.left_inside += 1;
                continue;
            }
            nodes[n as usize] = best.1;
            out.moved += 1;
            out.largest_depth = out.largest_depth.max(best.0);
        }
    }
    out
}

/// Whether every element of `elements` (those holding node `n`) keeps a positive volume with
/// `n` at `to`, and their worst [`shape_quality`] stays at or above the lower of the remeshing
/// limit ([`PEEL_QUALITY`], a collapse ratio of 10) and its value with `n` where it is.
fn move_keeps_elements_shaped(
    nodes: &[Vector3<f64>],
    elements: &[[u32; 4]],
    n: u32,
    to: Vector3<f64>,
) -> bool {
    let worst = |at: Vector3<f64>| {
        elements
            .iter()
            .map(|t| shape_quality(&t.map(|m| if m == n { at } else { nodes[m as usize] })))
            .fold(f64::INFINITY, f64::min)
    };
    let moved = worst(to);
    moved > 0.0 && moved >= worst(nodes[n as usize]).min(PEEL_QUALITY)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_through_or_onto_the_opposite_face_is_refused() {
        let nodes = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.2, 0.2, 0.8),
        ];
        let tet = [[0, 1, 2, 3]];
        let at = |d: f64| nodes[3] - Vector3::new(0.0, 0.0, d);
        let quality =
            |d: f64| shape_quality(&tet[0].map(|m| if m == 3 { at(d) } else { nodes[m as usize] }));
        // Node 3 lies 0.8 above the face 0 1 2: a move of 0.3 down keeps a good element, one
        // of 0.8 flattens it and one of 0.9 inverts it.
        assert!(quality(0.3) > PEEL_QUALITY);
        assert!(move_keeps_elements_shaped(&nodes, &tet, 3, at(0.3)));
        assert!(!move_keeps_elements_shaped(&nodes, &tet, 3, at(0.8)));
        assert!(!move_keeps_elements_shaped(&nodes, &tet, 3, at(0.9)));
        // 0.79 down keeps a positive volume but leaves the element flat (a height of 0.01
        // over edges of about 1): refused too.
        assert!(quality(0.79) > 0.0 && quality(0.79) < PEEL_QUALITY);
        assert!(!move_keeps_elements_shaped(&nodes, &tet, 3, at(0.79)));
        // From an element already past the limit, a move that raises it is taken and one
        // that flattens it further is not.
        let flat = [nodes[0], nodes[1], nodes[2], at(0.78)];
        let lift = |d: f64| flat[3] + Vector3::new(0.0, 0.0, d);
        assert!(shape_quality(&flat) < PEEL_QUALITY);
        assert!(move_keeps_elements_shaped(&flat, &tet, 3, lift(0.005)));
        assert!(!move_keeps_elements_shaped(&flat, &tet, 3, lift(-0.005)));
    }
}
