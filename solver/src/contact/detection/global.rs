//! Global detection (thesis 7.3): which slave nodes lie, at their predicted positions, inside an
//! element of the master's boundary layer (signed volumes, Box 7.2). Boxes skip a pass whose
//! bodies cannot touch and keep only the master elements in the region where the two bodies'
//! boxes overlap; a uniform grid over those tests each node against nearby elements only
//! (7.3.3).
//!
//! The elements in that region are found through [`LayerBoxes`], a grid of the layer elements'
//! boxes kept over steps (a Verlet-list-style broad phase, e.g. Benson & Hallquist 1990): a box
//! moves by at most the largest node displacement `d` since the grid was built, so the
//! elements whose box meets the region are among those whose stored box meets the region grown
//! by `d`. Only those get their box recomputed; the grid is rebuilt when `d` exceeds a fraction
//! of its cell. The elements found, their order and their boxes are the ones a scan of the
//! whole layer gives, so detection's answers do not change.

use nalgebra::Vector3;

use super::ContactSurface;
use crate::geometry::broad_phase::{Aabb, BoxedGrid, UniformGrid};
use crate::geometry::proximity::tetrahedron_barycentric;
use crate::model::Model;

/// The boxes of a master surface's boundary-layer elements at some earlier positions, binned in
/// a grid, kept from step to step.
#[derive(Debug, Clone, Default)]
pub(super) struct LayerBoxes {
    /// The distinct nodes of the layer elements, ascending (empty until first used).
    nodes: Vec<u32>,
    /// Positions of `nodes` when the grid was built (`None`: no grid yet).
    anchor: Option<Vec<Vector3<f64>>>,
    /// Each layer element's box at `anchor` (ids index `master.layer`), in the grid's cells.
    grid: Option<BoxedGrid>,
    /// The grid's cell (m): the grid is rebuilt once a node moved
    /// `REBUILD_FRACTION` of it.
    cell: f64,
    /// Scratch: grid query results, and the bit set of [`BoxedGrid::query_overlapping`].
    found: Vec<u32>,
    marks: Vec<u64>,
}

impl LayerBoxes {
    /// The master layer's box at `x1` (the union of its elements' boxes, exactly: it is the box
    /// of their nodes) and the largest coordinate change of a layer node since the grid was
    /// built (infinite without a grid).
    fn bounds_and_motion(
        &mut self,
        model: &Model,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
    ) -> (Aabb, f64) {
        if self.nodes.is_empty() {
            self.nodes = master
                .layer
                .iter()
                .flat_map(|&e| model.tets[e as usize])
                .collect();
            self.nodes.sort_unstable();
            self.nodes.dedup();
        }
        let Some(anchor) = &self.anchor else {
            let bounds = Aabb::of_points(self.nodes.iter().map(|&n| &x1[n as usize]));
            return (bounds, f64::INFINITY);
        };
        // One sweep over the nodes for both (each position read once); the box grows in node
        // order as `Aabb::of_points` grows it. `max` skips NaN; the sum of the changes does not,
        // so a NaN position forces a rebuild.
        let mut bounds = Aabb::of_points([]);
        let (moved, sum) =
            self.nodes
                .iter()
                .zip(anchor)
                .fold((0.0f64, 0.0f64), |(moved, sum), (&n, a)| {
                    let x = &x1[n as usize];
                    bounds.min = bounds.min.inf(x);
                    bounds.max = bounds.max.sup(x);
                    let d = x - a;
                    (moved.max(d.amax()), sum + d.sum())
                });
        (bounds, if sum.is_nan() { f64::INFINITY } else { moved })
    }

    /// Rebuilds the grid on the layer elements' boxes at `x1`.
    fn rebuild(&mut self, model: &Model, master: &ContactSurface, x1: &[Vector3<f64>]) {
        let boxes: Vec<Aabb> = master
            .layer
            .iter()
            .map(|&e| element_box(model, e, x1))
            .collect();
        self.cell =
            boxes.iter().map(|b| (b.max - b.min).max()).sum::<f64>() / boxes.len().max(1) as f64;
        // At most 8 cells per box, as `UniformGrid::build`.
        self.grid = Some(BoxedGrid::build_with_limit(&boxes, self.cell, 8));
        self.anchor = Some(self.nodes.iter().map(|&n| x1[n as usize]).collect());
    }

    /// The layer elements (indices into `master.layer`, ascending) whose box at `x1` meets
    /// `region`, with those boxes; `moved` is the largest coordinate change of a layer node
    /// since the grid was built.
    fn near(
        &mut self,
        model: &Model,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
        region: &Aabb,
        moved: f64,
    ) -> (Vec<u32>, Vec<Aabb>) {
        let mut moved = moved;
        if !(moved <= super::REBUILD_FRACTION * self.cell) {
            self.rebuild(model, master, x1);
            moved = 0.0;
        }
        // A box moved by at most `moved` on each axis (up to the rounding of the differences,
        // covered twice over with the slack for the rounding of the grown box's corners).
        let scale = region.min.amax().max(region.max.amax());
        let margin = 2.0 * moved + 8.0 * f64::EPSILON * scale;
        let grid = self.grid.as_ref().expect("rebuilt above when missing");
        let reach = region.grown(margin);
        // The stored boxes tell most elements in the cells the region meets apart without
        // reading their nodes.
        grid.query_overlapping(&reach, &mut self.marks, &mut self.found);
        let mut near = Vec::new();
        let mut near_boxes = Vec::new();
        for &i in &self.found {
            let b = element_box(model, master.layer[i as usize], x1);
            if b.overlaps(region) {
                near.push(i);
                near_boxes.push(b);
            }
        }
        (near, near_boxes)
    }
}

/// The box of element `e` at positions `x`.
fn element_box(model: &Model, e: u32, x: &[Vector3<f64>]) -> Aabb {
    Aabb::of_points(model.tets[e as usize].iter().map(|&n| &x[n as usize]))
}

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
    /// reach the master's boundary layer, so the pass finds nothing. `layer` keeps the master
    /// layer's boxes between calls (it must always be given the same `master`). `tolerance`
    /// is the barycentric tolerance of [`Self::penetrates`]: the boxes are grown by it times
    /// the master's extent, so a node that test would accept is never outside them.
    pub(super) fn new(
        model: &Model,
        slave: &ContactSurface,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
        layer: &mut LayerBoxes,
        tolerance: f64,
    ) -> Option<Self> {
        if master.layer.is_empty() {
            return None;
        }
        let slave_box = Aabb::of_points(slave.nodes.iter().map(|&n| &x1[n as usize]));
        let (master_box, moved) = layer.bounds_and_motion(model, master, x1);
        // A node on a face of the master's box may lie a rounding outside it: two bodies cut by
        // one symmetry plane x = 0 put their nodes there at 0 and at -1.2e-19 m (a mesher's
        // cos(pi / 2) r), and a slave node at -1.2e-19 slid into the master unseen (a block
        // node 0.4 mm inside a nail).
        let margin = tolerance * (master_box.max - master_box.min).max();
        let master_box = master_box.grown(margin);
        if !slave_box.overlaps(&master_box) {
            return None;
        }
        // Only the master elements where the two bodies' boxes overlap can be reached: for two
        // spheres, a thin slab around the contact instead of the whole boundary layer.
        let overlap = slave_box.intersection(&master_box);
        let (near, mut near_boxes) = layer.near(model, master, x1, &overlap, moved);
        if near.is_empty() {
            return None;
        }
        let typical = near_boxes
            .iter()
            .map(|b| (b.max - b.min).max())
            .sum::<f64>()
            / near_boxes.len() as f64;
        for b in &mut near_boxes {
            *b = b.grown(margin);
        }
        let element_grid = UniformGrid::build(&near_boxes, typical);
        Some(Self {
            overlap,
            typical,
            near,
            element_grid,
        })
    }

    /// Whether the predicted position `p` of a slave node lies inside a searched master element,
    /// all barycentric coordinates `>= -tolerance`: the elements binned into the grid cell of
    /// `p` (every element whose box holds `p` is among them).
    pub(super) fn penetrates(
        &self,
        model: &Model,
        master: &ContactSurface,
        x1: &[Vector3<f64>],
        p: &Vector3<f64>,
        tolerance: f64,
    ) -> bool {
        if !self.overlap.contains(p) {
            return false;
        }
        let Some(elements) = self.element_grid.items_at(p) else {
            return false;
        };
        elements.iter().any(|&i| {
            let e = master.layer[self.near[i as usize] as usize];
            let tet = model.tets[e as usize].map(|n| x1[n as usize]);
            tetrahedron_barycentric(p, &tet)
                .iter()
                .all(|&xi| xi >= -tolerance)
        })
    }
}
