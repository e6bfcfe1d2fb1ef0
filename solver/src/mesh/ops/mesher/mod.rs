//! The local remesher (thesis 8.2-8.3, issue 21): the refinement region `Omega_r` is replaced by
//! a finer, better-shaped mesh that stays conforming with the elements around it.
//!
//! # Method and why
//!
//! The thesis remeshed with FEMAP's Delaunay mesher over the region ("the program locally
//! produces a new discretization according to the three-dimensional Delaunay
//! triangularization", 8.3). The maintained library route, TetGen through the `tritet` crate
//! (3.4, AGPL-3.0 for TetGen), cannot keep the interface: the crate runs TetGen with the fixed
//! switches `pzAf` plus `a`/`q` and exposes no `-Y`, so the quality refinement splits the
//! region's boundary facets and the untouched neighbours would hang on the new nodes. The
//! region is therefore remeshed here by a local algorithm in pure Rust:
//!
//! 1. **Edge marking.** Every edge of a region element is split at its midpoint unless it is
//!    shorter than twice [`MesherOptions::min_edge`] or an edge of an element outside the
//!    region (splitting it would leave a hanging node there). So the faces, edges and nodes the
//!    region shares with the rest of the mesh are kept exactly. Edges on the body's outer
//!    boundary are split; their midpoints lie on the boundary facets and move only within them
//!    (step 3), so the boundary keeps its shape.
//! 2. **Subdivision.** An element with all six edges marked takes the regular (red) 1:8
//!    refinement (Bey 1995, "Tetrahedral grid refinement", Computing 55), its inner octahedron
//!    cut along its shortest diagonal (Zhang 1995's choice, the best-shaped of the three). An
//!    element with no marked edge is kept. Any other element (the closure layer, which touches
//!    the interface) has each face triangulated by its marked edges, a quadrilateral cut along
//!    its shorter diagonal (ties: the diagonal through the lowest node id, Dompierre et al. 1999),
//!    a rule that depends on the face only, so both elements of a face cut it alike; the element
//!    is then the cone of those triangles from its centroid, a new node. Every piece has
//!    positive volume (the centroid is inside the convex parent), and the pieces tile the parent,
//!    so the region's volume is kept to round-off.
//! 3. **Shape restoration.** A split alone does not cure a collapsed element: its children are
//!    as flat as it is. Every node inside the region (the region's own old interior nodes, which
//!    the collapse has moved, the midpoints of interior edges and the centroids) is then moved by
//!    constrained ("smart") Laplacian smoothing (Freitag & Ollivier-Gooch 1997) followed by a
//!    pattern search: a node goes to the mean of its neighbours, half-way there, or a step along
//!    an axis, only if that raises the worst quality `min(1 / chi, eta)` of its elements (`chi`
//!    the collapse ratio (8.1), `eta = 12 (3V)^(2/3) / sum l^2` the mean ratio, which also
//!    rejects slivers), so no element ever inverts and a node's worst element only improves.
//!    Nodes on the region's interface do not move. Nodes on the outer boundary slide within the
//!    axis-aligned planes their boundary faces lie in (symmetry planes, undeformed flat faces;
//!    along the line where two such planes meet), which keeps the boundary's shape exactly.
//!    Those on a curved or deformed surface slide on the old surface (projected onto their old
//!    faces) where it moves by at most [`MesherOptions::surface_deviation`], and do not move
//!    where that is 0 (`SurfaceSlide` in `smoothing.rs`). Sweeps run in node order until
//!    nothing moves: the result is deterministic.
//!
//! 4. **Edge collapse** (`collapse.rs`). Where smoothing cannot separate the ends of a short
//!    edge (every placement that lengthens it flattens a neighbour), the edge is merged into
//!    one of its ends, under the link condition, only where the worst element around rises;
//!    an edge shorter than [`MesherOptions::min_edge`] may also merge as long as its
//!    neighbours keep a collapse ratio of about 4 (coarsening). A node on a curved part of the
//!    outer boundary (the cavity around a penetrator's nose, where no smoothing may move it)
//!    merges along a boundary edge only where the boundary moves by at most
//!    [`MesherOptions::surface_deviation`] (0 by default: the surface is kept exactly); the
//!    volume and area that moves is recorded. The nodes then smooth again.
//!
//! 5. **Flips** (`flip.rs`). A sliver, with no short edge to collapse, is reconnected: 2-3 flips
//!    of its faces and 3-2 flips of its edges, each taken only where the worst element it
//!    replaces rises. The nodes then smooth again.
//!
//! 6. **Peeling** (`peel.rs`). An element still collapsed (quality below 0.1) with a face on
//!    the outer boundary, whose nodes none of the steps above may move (a sliver lying on the
//!    curved cavity around a penetrator's nose), is removed where the boundary stays a
//!    manifold (one fan of faces about each node): its inner faces become the boundary, which
//!    moves inward by at most its height. With [`MesherOptions::erode`], every collapsed
//!    element goes, inside the body too, whatever the surface's shape after (erosion). Taken
//!    with the flips (`flip_passes > 0`).
//!
//! Refinement stops at [`MesherOptions::min_edge`]: an edge shorter than twice it is not split.
//! Without that bound, each remeshing at the same place halved the elements there, and the
//! explicit step with them: under the nail the step fell from 3e-8 to 3e-11 s in seven
//! remeshings.
//!
//! A collapsed element is cured when its short edges have an end that can move: grow the run's
//! refinement region by one layer of elements ([`grow_region`]) so that every node of the
//! distorted elements is inside, unless it lies on a curved part of the outer boundary.

mod repair;
mod split;

use std::collections::BTreeSet;

use nalgebra::Vector3;

use self::repair::{collapse_draft, flip_and_peel, smooth_draft};
use self::split::{split_region, Draft};
use super::peel::PeeledElement;
use crate::error::{Result, SolverError};

/// Default number of smoothing sweeps (an upper bound: sweeps stop when no node moves).
pub const SMOOTHING_SWEEPS: usize = 100;

/// The six edges of a tetrahedron as local node pairs.
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// Settings of [`remesh_region`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MesherOptions {
    /// Largest number of smoothing sweeps over the region's inner nodes (step 3 of the method);
    /// 0 leaves the subdivision as it is.
    pub smoothing_sweeps: usize,
    /// Largest number of edge-collapse passes over the region (step 4 of the method); 0 keeps
    /// the connectivity of the subdivision.
    pub collapse_passes: usize,
    /// Largest number of face- and edge-flip passes over the region (step 5 of the method); 0
    /// flips nothing.
    pub flip_passes: usize,
    /// The shortest edge refinement makes (m): an edge shorter than twice this is not split,
    /// and an element with an edge shorter than this tries to collapse it (coarsening, taken
    /// where its neighbours stay above the collapse target's quality). 0: every edge is split
    /// and only quality drives the collapses. Without it, each remeshing at the same place
    /// halves the elements there, and the explicit step with them (thesis 8.5 bounds the same
    /// shrinking with a smallest volume `V_min`).
    pub min_edge: f64,
    /// How far (m) the remesher may move a curved part of the outer boundary: a node there
    /// may slide on the old surface (step 3), or merge along it into a neighbour (step 4), where
    /// the boundary faces that take it in its place pass within this distance of where it was.
    /// 0: the boundary's curved parts keep every node where it is (their shape exactly).
    pub surface_deviation: f64,
    /// Whether the elements the steps above leave collapsed (quality below 0.1, a collapse
    /// ratio of 10) may be removed wherever they are (step 6), inside the body or on its
    /// surface, whatever the surface's shape after (two parts of it may meet at a node or an
    /// edge): erosion of what the remesher cannot reshape, as explicit codes erode failed
    /// elements (LS-DYNA's `*MAT_ADD_EROSION`), with the body's mass kept. false: only
    /// peeling from the surface, where it stays a manifold.
    pub erode: bool,
    /// With [`Self::erode`], the largest principal stretch of the carried deformation past
    /// which a region element is eroded as failed material, whatever its shape (an element
    /// whose centroid lies in such an old element); 0: none is (only the collapsed ones go).
    /// The remesher itself knows no deformation: `remesh_problem` asks it through `failed`.
    pub erode_stretch: f64,
}

impl Default for MesherOptions {
    fn default() -> Self {
        Self {
            smoothing_sweeps: SMOOTHING_SWEEPS,
            collapse_passes: COLLAPSE_PASSES,
            flip_passes: FLIP_PASSES,
            min_edge: 0.0,
            surface_deviation: 0.0,
            erode: false,
            erode_stretch: 0.0,
        }
    }
}

/// Default number of edge-collapse passes (an upper bound: passes stop when none collapses).
pub const COLLAPSE_PASSES: usize = 10;

/// Default number of flip passes (an upper bound: passes stop when none flips).
pub const FLIP_PASSES: usize = 10;

/// The quality ([`super::quality::shape_quality`]) below which an element tries to collapse its short edges:
/// a collapse ratio of 4, well under the remeshing limit 10 (8.1).
const COLLAPSE_TARGET: f64 = 0.25;

/// The mesh after a local remeshing ([`remesh_region`]).
///
/// Elements outside the region come first, in their old order; the region's elements follow
/// from [`RemeshedRegion::first_region_element`]. Kept nodes (every node the region shares with
/// the rest of the mesh or the outer boundary, and every node outside it) come first in their
/// old order, at their old coordinates bit for bit; the region's inner nodes follow.
#[derive(Debug, Clone, PartialEq)]
pub struct RemeshedRegion {
    /// Coordinates of the new mesh's nodes (the old current configuration's, m).
    pub nodes: Vec<Vector3<f64>>,
    /// Connectivity of the new mesh, positively oriented.
    pub tets: Vec<[u32; 4]>,
    /// Old node id -> new node id for the nodes kept at their coordinates; `None` for the old
    /// nodes inside the region and those on its outer boundary that slid (`slid_nodes`), which
    /// the smoothing moved: they are new nodes now, whose fields come from the transfer (T3).
    pub kept_nodes: Vec<Option<u32>>,
    /// New element -> the old element it copies unchanged (every element outside the region,
    /// and a region element with no edge to split); `None` for a new element, whose fields come
    /// from the transfer (T1/T2).
    pub element_origin: Vec<Option<u32>>,
    /// Index of the first element that replaces the region.
    pub first_region_element: usize,
    /// Old boundary nodes that the smoothing slid within the axis-aligned planes of their
    /// boundary faces, as (old id, new id): they keep their place in the numbering but are not
    /// kept (`kept_nodes` is `None`); their fields come from the transfer, as a new node's.
    pub slid_nodes: Vec<(u32, u32)>,
    /// Old boundary nodes that an edge collapse merged into a neighbour on the same symmetry
    /// planes, or along a curved surface (old ids, ascending): they are gone from the new mesh
    /// (`kept_nodes` is `None`).
    pub merged_nodes: Vec<u32>,
    /// Edge collapses that removed a node of a curved boundary (step 4,
    /// [`MesherOptions::surface_deviation`]).
    pub surface_collapses: usize,
    /// The region's volume change by those collapses and by the nodes that slid on a curved
    /// surface (step 3) (m^3, after less before); the other moves keep the volume to round-off.
    pub surface_volume_change: f64,
    /// The outer boundary's area change by those collapses and slides (m^2, after less before).
    pub surface_area_change: f64,
    /// Collapsed boundary elements removed from the region (step 6, `peel.rs`), by their
    /// corners, each with the faces that were on the outer boundary: the region's volume and
    /// boundary area change by theirs.
    pub peeled: Vec<PeeledElement>,
}

impl RemeshedRegion {
    /// Whether element `e` of the new mesh is new (not a copy of an old element).
    pub fn is_new_element(&self, e: usize) -> bool {
        self.element_origin[e].is_none()
    }

    /// Ids of the new mesh's new nodes (those not kept from the old mesh), ascending.
    pub fn new_nodes(&self) -> Vec<u32> {
        let mut kept = vec![false; self.nodes.len()];
        for n in self.kept_nodes.iter().flatten() {
            kept[*n as usize] = true;
        }
        (0..self.nodes.len() as u32)
            .filter(|&n| !kept[n as usize])
            .collect()
    }
}

fn remesh_error(entity: &str, message: String) -> SolverError {
    SolverError::Remesh {
        entity: entity.to_string(),
        message,
    }
}

fn edge_key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The region grown by `layers` layers of elements: each layer adds every element that shares a
/// node with the region. Ascending, without duplicates. One layer around the distorted elements
/// makes all their nodes inner nodes of the region (except those on the outer boundary), which
/// the remesher can move (see the module's method).
pub fn grow_region(tets: &[[u32; 4]], region: &[usize], layers: usize) -> Vec<usize> {
    let mut set: BTreeSet<usize> = region.iter().copied().collect();
    for _ in 0..layers {
        let nodes: BTreeSet<u32> = set.iter().flat_map(|&e| tets[e]).collect();
        for (e, tet) in tets.iter().enumerate() {
            if tet.iter().any(|n| nodes.contains(n)) {
                set.insert(e);
            }
        }
    }
    set.into_iter().collect()
}

/// Replaces the elements `region` (indices into `tets`) of the mesh with current coordinates
/// `x` by a finer, better-shaped mesh conforming with the rest (method in the module's
/// documentation). Deterministic: the same input gives the same output, bit for bit.
///
/// Errors (naming the element): an empty region, an element id out of range, a region element
/// whose volume is not positive (an inverted element cannot be remeshed: the run must stop), a
/// face shared by more than two elements (the input is not a conforming mesh).
pub fn remesh_region(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    options: &MesherOptions,
) -> Result<RemeshedRegion> {
    remesh_region_keeping_edges(x, tets, region, options, &|_, _| false, &|_| false)
}

/// [`remesh_region`] with the edges for which `keep_edge(a, b)` holds left unsplit: a boundary
/// edge whose midpoint would lie inside a contact partner (a chord of the cavity around a
/// penetrator's curved nose, whose midpoint lies inside the nose by the sagitta `L^2 / 8R`:
/// 46 um under the nail's tip, where moving such nodes out inverted an element). With
/// [`MesherOptions::erode`], a region element at whose corners `failed` holds is eroded in
/// step 6 as a collapsed one is (failed material, [`MesherOptions::erode_stretch`]).
pub fn remesh_region_keeping_edges(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    options: &MesherOptions,
    keep_edge: &dyn Fn(u32, u32) -> bool,
    failed: &dyn Fn(&[Vector3<f64>; 4]) -> bool,
) -> Result<RemeshedRegion> {
    let mut draft = split_region(x, tets, region, options, keep_edge)?;
    let mut repairs = smooth_draft(&mut draft, options);
    if options.collapse_passes > 0 {
        collapse_draft(&mut draft, &mut repairs, options);
    }
    if options.flip_passes > 0 {
        flip_and_peel(&mut draft, &mut repairs, options, failed);
    }
    let Draft {
        nodes,
        tets: out_tets,
        origin,
        first_region_element,
        mut kept_nodes,
        ..
    } = draft;
    let mut merged_nodes = repairs.merged_nodes;
    merged_nodes.sort_unstable();
    // An old boundary node the smoothing moved is a new node now: its fields come from the
    // transfer.
    let mut slid_nodes = Vec::new();
    for (o, k) in kept_nodes.iter_mut().enumerate() {
        if let Some(n) = *k {
            if nodes[n as usize] != x[o] {
                *k = None;
                slid_nodes.push((o as u32, n));
            }
        }
    }
    Ok(RemeshedRegion {
        nodes,
        tets: out_tets,
        kept_nodes,
        element_origin: origin,
        first_region_element,
        slid_nodes,
        merged_nodes,
        surface_collapses: repairs.surface_collapses,
        surface_volume_change: repairs.surface_volume_change,
        surface_area_change: repairs.surface_area_change,
        peeled: repairs.peeled,
    })
}

/// The elements before `first` (outside the region) that hold a node of the region's elements
/// (from `first` on).
fn neighbours_of_region(nodes: &[Vector3<f64>], tets: &[[u32; 4]], first: usize) -> Vec<[u32; 4]> {
    let mut region_node = vec![false; nodes.len()];
    for t in &tets[first..] {
        for &n in t {
            region_node[n as usize] = true;
        }
    }
    tets[..first]
        .iter()
        .filter(|t| t.iter().any(|&n| region_node[n as usize]))
        .copied()
        .collect()
}

/// Removes the nodes no element of `tets` holds (those an edge collapse merged away, or a
/// peeled element took with it) and renumbers the rest in order; an old node among them is
/// recorded in `merged` (it is gone from the new mesh).
fn drop_unused_nodes(
    nodes: &mut Vec<Vector3<f64>>,
    tets: &mut [[u32; 4]],
    free: &mut Vec<(u32, [bool; 3])>,
    kept_nodes: &mut [Option<u32>],
    merged: &mut Vec<u32>,
) {
    let mut used = vec![false; nodes.len()];
    for t in tets.iter() {
        for &n in t {
            used[n as usize] = true;
        }
    }
    let mut renumber = vec![None; nodes.len()];
    let mut compact = Vec::with_capacity(nodes.len());
    for (n, p) in nodes.iter().enumerate() {
        if used[n] {
            renumber[n] = Some(compact.len() as u32);
            compact.push(*p);
        }
    }
    *nodes = compact;
    for t in tets.iter_mut() {
        *t = t.map(|n| renumber[n as usize].expect("a node of an element is used"));
    }
    *free = free
        .iter()
        .filter_map(|&(n, axes)| renumber[n as usize].map(|m| (m, axes)))
        .collect();
    for (o, k) in kept_nodes.iter_mut().enumerate() {
        if let Some(n) = *k {
            *k = renumber[n as usize];
            if k.is_none() {
                merged.push(o as u32);
            }
        }
    }
}
