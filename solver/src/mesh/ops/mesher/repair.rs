//! Steps 3 to 6 of the method (module `mesher`), on the subdivided region ([`Draft`]): the
//! smoothing with the boundary's nodes sliding ([`smooth_draft`]), the edge collapses
//! ([`collapse_draft`]), and the flips and peeling ([`flip_and_peel`]).

use std::collections::{BTreeSet, HashMap};

use nalgebra::Vector3;

use super::split::Draft;
use super::{drop_unused_nodes, neighbours_of_region, MesherOptions, COLLAPSE_TARGET};
use crate::mesh::ops::collapse::{collapse_short_edges, CollapseLimits, Removable};
use crate::mesh::ops::flip::flip_slivers;
use crate::mesh::ops::peel::{peel_failed_and_slivers, PeeledElement};
use crate::mesh::ops::smoothing::{
    boundary_nodes, smooth, smooth_on_surface, volume_and_boundary_area, SurfaceSlide,
};

/// What the repairs leave besides the mesh: the nodes still free to move, the pinned ones, the
/// curved boundary's nodes, and what changed of the boundary.
pub(super) struct Repairs {
    /// Nodes free to move, with the axes each may move along.
    pub free: Vec<(u32, [bool; 3])>,
    /// New nodes that are old nodes of elements outside the region.
    pinned: Vec<bool>,
    /// Nodes on a curved part of the outer boundary, with their planes' axes.
    surface: Vec<(u32, [bool; 3])>,
    /// Old boundary nodes merged away (old ids).
    pub merged_nodes: Vec<u32>,
    /// Collapses that removed a node of a curved boundary.
    pub surface_collapses: usize,
    /// The region's volume change by surface slides and collapses (m^3).
    pub surface_volume_change: f64,
    /// The outer boundary's area change by them (m^2).
    pub surface_area_change: f64,
    /// Collapsed boundary elements removed.
    pub peeled: Vec<PeeledElement>,
}

/// Step 3: inner nodes move freely; nodes on the outer boundary slide within the axis-aligned
/// planes of their boundary faces where they have any (symmetry planes, flat faces), and
/// nodes on a curved part of it slide on it, moving it by at most the surface deviation; the
/// volume and area that changes is booked with the surface collapses'.
pub(super) fn smooth_draft(draft: &mut Draft, options: &MesherOptions) -> Repairs {
    let first = draft.first_region_element;
    let mut free: Vec<(u32, [bool; 3])> = draft.movable.iter().map(|&n| (n, [true; 3])).collect();
    let pinned: Vec<bool> = {
        let mut p = vec![false; draft.nodes.len()];
        for (o, k) in draft.kept_nodes.iter().enumerate() {
            if let (Some(k), true) = (k, draft.outside[o]) {
                p[*k as usize] = true;
            }
        }
        p
    };
    let boundary = boundary_nodes(&draft.nodes, &draft.tets[first..], &pinned);
    free.extend(boundary.sliding);
    let region_tets = &draft.tets[first..];
    let slide = SurfaceSlide::new(
        &draft.nodes,
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
    let (volume_before, area_before) = measure(&draft.nodes);
    smooth_on_surface(
        &mut draft.nodes,
        region_tets,
        &with_surface,
        options.smoothing_sweeps,
        &slide,
    );
    let (volume_after, area_after) = measure(&draft.nodes);
    Repairs {
        free,
        pinned,
        surface: boundary.surface,
        merged_nodes: Vec::new(),
        surface_collapses: 0,
        surface_volume_change: volume_after - volume_before,
        surface_area_change: area_after - area_before,
        peeled: Vec::new(),
    }
}

/// Step 4: short edges merged (`collapse.rs`); then the nodes whose boundary faces still lie
/// in the same planes smooth again, and the nodes no element holds are dropped.
pub(super) fn collapse_draft(draft: &mut Draft, repairs: &mut Repairs, options: &MesherOptions) {
    let first = draft.first_region_element;
    let mut removable = vec![Removable::Never; draft.nodes.len()];
    // Surface nodes that slid are on the old surface: a collapse measures from there.
    for &(n, axes) in &repairs.surface {
        removable[n as usize] = Removable::Surface(axes);
    }
    for &(n, axes) in &repairs.free {
        removable[n as usize] = Removable::Sliding(axes.map(|f| !f));
    }
    let collapses = collapse_short_edges(
        &draft.nodes,
        &draft.tets[first..],
        &neighbours_of_region(&draft.nodes, &draft.tets, first),
        &removable,
        CollapseLimits {
            target: COLLAPSE_TARGET,
            min_edge: options.min_edge,
            surface_deviation: options.surface_deviation,
            passes: options.collapse_passes,
        },
    );
    repairs.surface_collapses = collapses.surface;
    repairs.surface_volume_change += collapses.volume_change;
    repairs.surface_area_change += collapses.area_change;
    let left = collapses.tets;
    if collapses.count == 0 {
        return;
    }
    let (mut tets_left, mut origin_left) = (Vec::new(), Vec::new());
    for (t, o) in left.into_iter().zip(&draft.origin[first..]) {
        if let Some(t) = t {
            tets_left.push(t);
            origin_left.push(*o);
        }
    }
    draft.tets.truncate(first);
    draft.tets.extend(tets_left);
    draft.origin.truncate(first);
    draft.origin.extend(origin_left);
    // A merge on the surface gives the nodes around it new boundary faces: a node that slid in
    // a plane may now hold a face of the curved surface, which sliding it would move (the
    // region's volume then changed by 2.5e-6 of itself, unrecorded, in a nail run). Only nodes
    // whose boundary faces still lie in the same planes slide now.
    let now = boundary_nodes(&draft.nodes, &draft.tets[first..], &repairs.pinned);
    let sliding: HashMap<u32, [bool; 3]> = now.sliding.into_iter().collect();
    let surface: BTreeSet<u32> = now.surface.into_iter().map(|(n, _)| n).collect();
    repairs.free.retain(|(n, axes)| match sliding.get(n) {
        Some(a) => a == axes,
        None => !surface.contains(n),
    });
    smooth(
        &mut draft.nodes,
        &draft.tets[first..],
        &repairs.free,
        options.smoothing_sweeps,
    );
    drop_unused_nodes(
        &mut draft.nodes,
        &mut draft.tets,
        &mut repairs.free,
        &mut draft.kept_nodes,
        &mut repairs.merged_nodes,
    );
}

/// Steps 5 and 6: slivers flipped (`flip.rs`) and the nodes smoothed again; then collapsed
/// boundary elements, and with erosion every collapsed or failed one, peeled (`peel.rs`).
pub(super) fn flip_and_peel(
    draft: &mut Draft,
    repairs: &mut Repairs,
    options: &MesherOptions,
    failed: &dyn Fn(&[Vector3<f64>; 4]) -> bool,
) {
    let first = draft.first_region_element;
    // Region elements that copy an old one unchanged, which the flips leave alone.
    let fixed: Vec<bool> = draft.origin[first..].iter().map(Option::is_some).collect();
    let (after, flips) = flip_slivers(
        &draft.nodes,
        &draft.tets[first..],
        &fixed,
        &neighbours_of_region(&draft.nodes, &draft.tets, first),
        COLLAPSE_TARGET,
        options.flip_passes,
    );
    if flips > 0 {
        let old_origin = draft.origin.split_off(first);
        draft.tets.truncate(first);
        for (k, t) in after.into_iter().enumerate() {
            if let Some(t) = t {
                draft.tets.push(t);
                draft.origin.push(old_origin.get(k).copied().flatten());
            }
        }
        smooth(
            &mut draft.nodes,
            &draft.tets[first..],
            &repairs.free,
            options.smoothing_sweeps,
        );
    }
    // A region element copied unchanged may be peeled too: an unsplit one (its edges too
    // short, or kept where a contact partner lies across them) is as collapsed as it came.
    let (kept, removed) = peel_failed_and_slivers(
        &draft.nodes,
        &draft.tets,
        first,
        options.flip_passes,
        options.erode,
        failed,
    );
    if !removed.is_empty() {
        draft.tets = kept.iter().map(|&e| draft.tets[e]).collect();
        draft.origin = kept.iter().map(|&e| draft.origin[e]).collect();
        repairs.peeled = removed;
        // A peeled element may take its last node with it.
        drop_unused_nodes(
            &mut draft.nodes,
            &mut draft.tets,
            &mut repairs.free,
            &mut draft.kept_nodes,
            &mut repairs.merged_nodes,
        );
    }
}
