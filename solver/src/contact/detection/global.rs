//! Global detection (thesis 7.3): which slave nodes lie, at their predicted positions, inside an
//! element of the master's boundary layer (signed volumes, Box 7.2). Boxes skip a pass whose
//! bodies cannot touch and keep only the master elements in the region where the two bodies'
//! boxes overlap; a uniform grid over those tests each node against nearby elements only
//! (7.3.3).

use nalgebra::Vector3;

use super::ContactSurface;
use crate::contact::broad_phase::{Aabb, UniformGrid};
use crate::contact::geometry::tetrahedron_barycentric;
use crate::model::Model;

/// The master elements one pass searches, with the region and length scale local detection
/// reuses.
pub(super) struct GlobalSearch {
    /// Where the slave nodes' box meets the master's boundary layer's box.
    pub(super) overlap: Aabb,
    /// The mean largest side of the searched elements' boxes: the grid cell, and the reach of
    /// local detection's searches.
    pub(super) typical: f64,
    /// The boundary-layer elements whose box meets `overlap`, as indices into `master.layer`.
    near: Vec<u32>,
    element_grid: UniformGrid,
}

impl GlobalSearch {
    /// The search of one pass on the predicted positions `x1`; `None` when no slave node can
    /// reach the master's boundary layer, so the pass finds nothing.
    pub(super) fn new(
        model: &Model,
        slave: &ContactSurface,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
    ) -> Option<Self> {
        let slave_box = Aabb::of_points(slave.nodes.iter().map(|&n| &x1[n as usize]));
        let element_boxes: Vec<Aabb> = master
            .layer
            .iter()
            .map(|&e| Aabb::of_points(model.tets[e as usize].iter().map(|&n| &x1[n as usize])))
            .collect();
        let master_box = element_boxes
            .iter()
            .fold(slave_box.grown(f64::NEG_INFINITY), |a, b| a.union(b));
        if element_boxes.is_empty() || !slave_box.overlaps(&master_box) {
            return None;
        }
        // Only the master elements where the two bodies' boxes overlap can be reached: for two
        // spheres, a thin slab around the contact instead of the whole boundary layer.
        let overlap = slave_box.intersection(&master_box);
        let near: Vec<u32> = (0..element_boxes.len() as u32)
            .filter(|&i| element_boxes[i as usize].overlaps(&overlap))
            .collect();
        if near.is_empty() {
            return None;
        }
        let near_boxes: Vec<Aabb> = near.iter().map(|&i| element_boxes[i as usize]).collect();
        let typical = near_boxes
            .iter()
            .map(|b| (b.max - b.min).max())
            .sum::<f64>()
            / near_boxes.len() as f64;
        let element_grid = UniformGrid::build(&near_boxes, typical);
        Some(Self {
            overlap,
            typical,
            near,
            element_grid,
        })
    }

    /// Whether the predicted position `p` of a slave node lies inside a searched master element,
    /// all barycentric coordinates `>= -tolerance`. `elements` is scratch space.
    pub(super) fn penetrates(
        &self,
        model: &Model,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
        p: &Vector3<f64>,
        tolerance: f64,
        elements: &mut Vec<u32>,
    ) -> bool {
        if !self.overlap.contains(p) {
            return false;
        }
        self.element_grid
            .query(&Aabb { min: *p, max: *p }, elements);
        elements.iter().any(|&i| {
            let e = master.layer[self.near[i as usize] as usize];
            let tet = model.tets[e as usize].map(|n| x1[n as usize]);
            tetrahedron_barycentric(p, &tet)
                .iter()
                .all(|&xi| xi >= -tolerance)
        })
    }
}
