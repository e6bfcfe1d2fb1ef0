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

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

use super::collapse::{collapse_short_edges, CollapseLimits, Removable};
use super::flip::flip_slivers;
use super::peel::{peel_failed_and_slivers, PeeledElement};
use super::smoothing::{
    boundary_nodes, smooth, smooth_on_surface, volume_and_boundary_area, SurfaceSlide,
};
use super::subdivision::{face_triangles, red_refinement};
use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;
use crate::mesh::{face_key, TET_FACES};

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

    // Faces: how many region and other elements hold each one.
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

    // Fixed old nodes: those of elements outside the region, and those of the region's faces on
    // the outer boundary. Boundary edges of the region (for midpoints that must not move).
    let mut fixed = vec![false; x.len()];
    // Nodes of elements outside the region: they never move (the interface stays conforming).
    let mut outside = vec![false; x.len()];
    let mut region_node = vec![false; x.len()];
    for &e in &region {
        for n in tets[e] {
            region_node[n as usize] = true;
        }
    }
    let mut boundary_edges = BTreeSet::new();
    for &e in &region {
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
    // Edges of region elements, less those of elements outside (which must not be split).
    // Edges of region elements long enough to halve (`min_edge`), less those of elements
    // outside (which must not be split).
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

    // Numbering: kept old nodes in old order, then the region's inner old nodes, then the
    // midpoints (ascending edge), then the centroids (ascending element).
    let mut new_id = vec![0u32; x.len()];
    let mut kept_nodes = vec![None; x.len()];
    let mut nodes = Vec::with_capacity(x.len() + marked.len() + region.len());
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
    for &(a, b) in &marked {
        let id = nodes.len() as u32;
        midpoint.insert((a, b), id);
        if !boundary_edges.contains(&(a, b)) {
            movable.push(id);
        }
        nodes.push(0.5 * (x[a as usize] + x[b as usize]));
    }

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

    // Inner nodes move freely; nodes on the outer boundary slide within the axis-aligned planes
    // of their boundary faces where they have any (symmetry planes, flat faces).
    let mut free: Vec<(u32, [bool; 3])> = movable.iter().map(|&n| (n, [true; 3])).collect();
    let pinned: Vec<bool> = {
        let mut p = vec![false; nodes.len()];
        for (o, k) in kept_nodes.iter().enumerate() {
            if let (Some(k), true) = (k, outside[o]) {
                p[*k as usize] = true;
            }
        }
        p
    };
    let boundary = boundary_nodes(&nodes, &out_tets[first_region_element..], &pinned);
    free.extend(boundary.sliding);
    // Nodes on a curved part of the boundary slide on it, moving it by at most the surface
    // deviation; the volume and area that changes is booked with the surface collapses'.
    let region_tets = &out_tets[first_region_element..];
    let slide = SurfaceSlide::new(
        &nodes,
        region_tets,
        &boundary.surface,
        options.surface_deviation,
    );
    let with_surface: Vec<(u32, [bool; 3])> = free
        .iter()
        .copied()
        .chain(slide.movable(&boundary.surface))
        .collect();
    // Without sliding nodes the smoothing keeps the volume and the boundary (no sums needed).
    let measure = |nodes: &[Vector3<f64>]| {
        if slide.is_empty() {
            (0.0, 0.0)
        } else {
            volume_and_boundary_area(nodes, region_tets)
        }
    };
    let (volume_before, area_before) = measure(&nodes);
    smooth_on_surface(
        &mut nodes,
        region_tets,
        &with_surface,
        options.smoothing_sweeps,
        &slide,
    );
    let (volume_after, area_after) = measure(&nodes);
    let mut merged_nodes = Vec::new();
    let (mut surface_collapses, mut surface_volume_change, mut surface_area_change) =
        (0, volume_after - volume_before, area_after - area_before);
    if options.collapse_passes > 0 {
        let mut removable = vec![Removable::Never; nodes.len()];
        // Surface nodes that slid are on the old surface: a collapse measures from there.
        for &(n, axes) in &boundary.surface {
            removable[n as usize] = Removable::Surface(axes);
        }
        for &(n, axes) in &free {
            removable[n as usize] = Removable::Sliding(axes.map(|f| !f));
        }
        let collapses = collapse_short_edges(
            &nodes,
            &out_tets[first_region_element..],
            &neighbours_of_region(&nodes, &out_tets, first_region_element),
            &removable,
            CollapseLimits {
                target: COLLAPSE_TARGET,
                min_edge: options.min_edge,
                surface_deviation: options.surface_deviation,
                passes: options.collapse_passes,
            },
        );
        surface_collapses = collapses.surface;
        surface_volume_change += collapses.volume_change;
        surface_area_change += collapses.area_change;
        let left = collapses.tets;
        if collapses.count > 0 {
            let (mut tets_left, mut origin_left) = (Vec::new(), Vec::new());
            for (t, o) in left.into_iter().zip(&origin[first_region_element..]) {
                if let Some(t) = t {
                    tets_left.push(t);
                    origin_left.push(*o);
                }
            }
            out_tets.truncate(first_region_element);
            out_tets.extend(tets_left);
            origin.truncate(first_region_element);
            origin.extend(origin_left);
            // A merge on the surface gives the nodes around it new boundary faces: a node that
            // slid in a plane may now hold a face of the curved surface, which sliding it would
            // move (the region's volume then changed by 2.5e-6 of itself, unrecorded, in a nail
            // run). Only nodes whose boundary faces still lie in the same planes slide now.
            let now = boundary_nodes(&nodes, &out_tets[first_region_element..], &pinned);
            let sliding: HashMap<u32, [bool; 3]> = now.sliding.into_iter().collect();
            let surface: BTreeSet<u32> = now.surface.into_iter().map(|(n, _)| n).collect();
            free.retain(|(n, axes)| match sliding.get(n) {
                Some(a) => a == axes,
                None => !surface.contains(n),
            });
            smooth(
                &mut nodes,
                &out_tets[first_region_element..],
                &free,
                options.smoothing_sweeps,
            );
            drop_unused_nodes(
                &mut nodes,
                &mut out_tets,
                &mut free,
                &mut kept_nodes,
                &mut merged_nodes,
            );
        }
    }
    let mut peeled = Vec::new();
    if options.flip_passes > 0 {
        // Region elements that copy an old one unchanged, which the flips leave alone.
        let fixed: Vec<bool> = origin[first_region_element..]
            .iter()
            .map(Option::is_some)
            .collect();
        let (after, flips) = flip_slivers(
            &nodes,
            &out_tets[first_region_element..],
            &fixed,
            &neighbours_of_region(&nodes, &out_tets, first_region_element),
            COLLAPSE_TARGET,
            options.flip_passes,
        );
        if flips > 0 {
            let old_origin = origin.split_off(first_region_element);
            out_tets.truncate(first_region_element);
            for (k, t) in after.into_iter().enumerate() {
                if let Some(t) = t {
                    out_tets.push(t);
                    origin.push(old_origin.get(k).copied().flatten());
                }
            }
            smooth(
                &mut nodes,
                &out_tets[first_region_element..],
                &free,
                options.smoothing_sweeps,
            );
        }
        // A region element copied unchanged may be peeled too: an unsplit one (its edges too
        // short, or kept where a contact partner lies across them) is as collapsed as it came.
        let (kept, removed) = peel_failed_and_slivers(
            &nodes,
            &out_tets,
            first_region_element,
            options.flip_passes,
            options.erode,
            failed,
        );
        if !removed.is_empty() {
            out_tets = kept.iter().map(|&e| out_tets[e]).collect();
            origin = kept.iter().map(|&e| origin[e]).collect();
            peeled = removed;
            // A peeled element may take its last node with it.
            drop_unused_nodes(
                &mut nodes,
                &mut out_tets,
                &mut free,
                &mut kept_nodes,
                &mut merged_nodes,
            );
        }
    }
    merged_nodes.sort_unstable();
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
        surface_collapses,
        surface_volume_change,
        surface_area_change,
        peeled,
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
