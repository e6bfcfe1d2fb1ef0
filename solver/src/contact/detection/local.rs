//! Local detection (thesis 7.4): for a slave node global detection found inside the master, the
//! master boundary face it went through and the contact point on it. Three strategies, in
//! order: continuous collision detection (7.4.4), the intersection of the node's trajectory with
//! the predicted face (7.4.3), the closest point (7.4.2). Candidate faces are those near the
//! region global detection searched whose swept box meets the query, found through a grid of the
//! faces' boxes kept over steps ([`FaceBoxes`]).
//!
//! A pass's [`LocalSearch`] is read-only once built, so the penetrating nodes of a pass are
//! searched in parallel, each with its own [`FaceScratch`]: a node's answer depends on its own
//! trajectory and the positions only, never on the other nodes or on the order they are
//! searched in.

use nalgebra::Vector3;

use super::{CcdCall, ContactSurface, DetectionSettings};
use crate::contact::ccd::{vertex_face_ccd, CcdHit, Trajectory};
use crate::geometry::broad_phase::{Aabb, BoxedGrid};
use crate::geometry::proximity::{against, clamped_triangle_weights, triangle_weights};

/// Which strategy found a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Strategy {
    Ccd,
    Trajectory,
    ClosestPoint,
}

/// The boxes of a master surface's faces at some earlier positions, binned in a grid, kept
/// from step to step. A face's swept box over a step (its corners at the start and predicted
/// positions) lies within its stored box grown by the largest coordinate change `d` of a
/// boundary node since the grid was built, so the faces whose swept box meets a region are
/// among those the grid finds for the region grown by `d`; the grid is rebuilt when `d` exceeds
/// a fraction of its cell.
#[derive(Debug, Clone, Default)]
pub(super) struct FaceBoxes {
    /// Positions of `master.nodes` when the grid was built (`None`: no grid yet).
    anchor: Option<Vec<Vector3<f64>>>,
    /// Each face's box at `anchor`, in the grid's cells.
    grid: Option<BoxedGrid>,
    /// The grid's cell (m).
    cell: f64,
}

/// Scratch space of one thread's face searches: grid query results and the candidate faces of
/// the last query.
#[derive(Debug, Clone, Default)]
pub(super) struct FaceScratch {
    found: Vec<u32>,
    /// The bit set of [`BoxedGrid::query_overlapping`]: a query meets tens of cells, and
    /// marking the faces found is cheaper than sorting them (a surface of a few thousand faces
    /// is a hundred words to read back).
    marks: Vec<u64>,
    /// The candidate faces of the last query, as master face ids, ascending.
    faces: Vec<u32>,
}

impl FaceBoxes {
    /// The largest coordinate change of a master boundary node from the grid's positions to
    /// `x0` or `x1` (the grid is rebuilt on `x1` first when it exceeds
    /// `REBUILD_FRACTION` of a cell).
    fn refit(&mut self, master: &ContactSurface, x0: &[Vector3<f64>], x1: &[Vector3<f64>]) -> f64 {
        let moved = self.moved(master, x0, x1);
        if moved <= super::REBUILD_FRACTION * self.cell {
            return moved;
        }
        let boxes: Vec<Aabb> = master
            .faces
            .iter()
            .map(|f| Aabb::of_points(f.iter().map(|&n| &x1[n as usize])))
            .collect();
        // Half the mean face: a graded mesh's faces are smallest where bodies touch (the
        // spheres' refined poles), and a query there then meets a few faces per cell. The grid
        // is kept over many steps, so its extra cells are paid for once.
        self.cell = 0.5 * boxes.iter().map(|b| (b.max - b.min).max()).sum::<f64>()
            / boxes.len().max(1) as f64;
        self.grid = Some(BoxedGrid::build_with_limit(&boxes, self.cell, 64));
        self.anchor = Some(master.nodes.iter().map(|&n| x1[n as usize]).collect());
        self.moved(master, x0, x1)
    }

    /// The largest coordinate change from the grid's positions (infinite without a grid, or
    /// with a NaN position: `max` skips NaN, the sum of the changes does not).
    fn moved(&self, master: &ContactSurface, x0: &[Vector3<f64>], x1: &[Vector3<f64>]) -> f64 {
        let Some(anchor) = &self.anchor else {
            return f64::INFINITY;
        };
        let (moved, sum) =
            master
                .nodes
                .iter()
                .zip(anchor)
                .fold((0.0f64, 0.0f64), |(moved, sum), (&n, a)| {
                    let d0 = x0[n as usize] - a;
                    let d1 = x1[n as usize] - a;
                    (
                        moved.max(d0.amax()).max(d1.amax()),
                        sum + d0.sum() + d1.sum(),
                    )
                });
        if sum.is_nan() {
            f64::INFINITY
        } else {
            moved
        }
    }
}

/// The master faces one pass may assign nodes to: those with a corner near the region global
/// detection searched, found through the [`FaceBoxes`] grid by their swept boxes.
pub(super) struct LocalSearch<'a> {
    master: &'a ContactSurface,
    /// The global search's length scale (see `GlobalSearch::typical`).
    typical: f64,
    /// Faces with no corner (at `x1`) in this region are never candidates.
    face_region: Aabb,
    boxes: &'a FaceBoxes,
    /// Largest coordinate change of a boundary node since `boxes` was built.
    moved: f64,
}

impl<'a> LocalSearch<'a> {
    /// The faces of `master` within `3 typical` of `overlap`, on the positions at the start of
    /// the step `x0` and the predicted ones `x1`; `boxes` keeps the faces' grid between calls
    /// (it must always be given the same `master`).
    pub(super) fn new(
        master: &'a ContactSurface,
        overlap: &Aabb,
        typical: f64,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
        boxes: &'a mut FaceBoxes,
    ) -> Self {
        // A node's faces are searched within `typical` of its path, which is shorter than an
        // element (the step is below the stable one), so faces farther out are never candidates.
        let face_region = overlap.grown(3.0 * typical);
        let moved = boxes.refit(master, x0, x1);
        Self {
            master,
            typical,
            face_region,
            boxes,
            moved,
        }
    }

    /// Faces with a corner in `face_region` whose swept box meets `region`, as master face
    /// ids in ascending order, into `scratch.faces`.
    fn candidates(
        &self,
        region: Aabb,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
        scratch: &mut FaceScratch,
    ) {
        let boxes = self.boxes;
        // Rounding of the changes and of the grown box's corners: as in `LayerBoxes::near`.
        let scale = region.min.amax().max(region.max.amax());
        let margin = 2.0 * self.moved + 8.0 * f64::EPSILON * scale;
        let grid = boxes.grid.as_ref().expect("`refit` builds the grid");
        let reach = region.grown(margin);
        grid.query_overlapping(&reach, &mut scratch.marks, &mut scratch.found);
        scratch.faces.clear();
        for &f in &scratch.found {
            let f = f as usize;
            // The swept box and the corners' test are a few comparisons of six points, cheaper
            // than sharing a per-face cache between the threads.
            let corners = &self.master.faces[f];
            let near = corners
                .iter()
                .any(|&n| self.face_region.contains(&x1[n as usize]));
            if !near {
                continue;
            }
            let swept = Aabb::of_points(
                corners
                    .iter()
                    .flat_map(|&n| [&x0[n as usize], &x1[n as usize]]),
            );
            if swept.overlaps(&region) {
                scratch.faces.push(f as u32);
            }
        }
    }

    /// The face the penetrating `node` is assigned to and the weights of its contact point, by
    /// the first strategy that finds one; every CCD call is appended to `ccd_calls` when given.
    pub(super) fn contact_point(
        &self,
        node: &Trajectory,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
        settings: &DetectionSettings,
        scratch: &mut FaceScratch,
        ccd_calls: Option<&mut Vec<CcdCall>>,
    ) -> Option<(u32, [f64; 3], Strategy)> {
        // A face the node crosses holds the crossing point, which lies on the node's path: the
        // path's box (grown by the detection tolerance) finds every such face.
        let path = Aabb::of_points([&node.start, &node.end]);
        self.candidates(
            path.grown(settings.tolerance * self.typical),
            x0,
            x1,
            scratch,
        );
        let master = self.master;
        earliest_ccd(
            master,
            &scratch.faces,
            node,
            x0,
            x1,
            settings.tolerance,
            ccd_calls,
        )
        .map(|(f, w)| (f, w, Strategy::Ccd))
        .or_else(|| {
            trajectory_intersection(master, &scratch.faces, node, x1, settings.tolerance)
                .map(|(f, w)| (f, w, Strategy::Trajectory))
        })
        .or_else(|| {
            self.candidates(path.grown(self.typical), x0, x1, scratch);
            closest_point(master, &scratch.faces, node, x0, x1, self.typical)
                .map(|(f, w)| (f, w, Strategy::ClosestPoint))
        })
    }
}

/// The face (among `candidates`) the node crosses first during the step (7.4.4); every CCD
/// call is appended to `calls` when given.
fn earliest_ccd(
    master: &ContactSurface,
    candidates: &[u32],
    node: &Trajectory,
    x0: &[Vector3<f64>],
    x1: &[Vector3<f64>],
    tolerance: f64,
    mut calls: Option<&mut Vec<CcdCall>>,
) -> Option<(u32, [f64; 3])> {
    let mut best: Option<(f64, u32, [f64; 3])> = None;
    let tolerance = tolerance.max(1e-12);
    for &i in candidates {
        let face = master.faces[i as usize];
        let traj = face.map(|n| Trajectory {
            start: x0[n as usize],
            end: x1[n as usize],
        });
        let found = vertex_face_ccd(node, [&traj[0], &traj[1], &traj[2]], tolerance);
        if let Some(calls) = calls.as_deref_mut() {
            calls.push(CcdCall {
                node: *node,
                face: traj,
                tolerance,
                hit: found.map(|h| h.t),
            });
        }
        if let Some(hit) = found {
            if !moves_into(node, &traj, &hit) {
                continue;
            }
            if best.is_none_or(|(t, _, _)| hit.t < t) {
                best = Some((hit.t, i, hit.weights));
            }
        }
    }
    best.map(|(_, f, w)| (f, w))
}

/// Whether the node, at the contact `hit`, moves into the face relative to its contact point,
/// `n(t) . (d_s - sum_c N_c d_c) < 0`, or does not move relative to it at all (resting). CCD
/// is geometric and also reports a node that slides within the face's plane (a block's side
/// face, when the node runs down that side) or leaves the face; neither crosses it, and taking
/// such a face would push along a normal the motion does not need.
fn moves_into(node: &Trajectory, face: &[Trajectory; 3], hit: &CcdHit) -> bool {
    let at = |tr: &Trajectory| tr.start + (tr.end - tr.start) * hit.t;
    let [a, b, c] = [at(&face[0]), at(&face[1]), at(&face[2])];
    let normal = (b - a).cross(&(c - a));
    let relative = (node.end - node.start)
        - (0..3).fold(Vector3::zeros(), |sum, k| {
            sum + (face[k].end - face[k].start) * hit.weights[k]
        });
    relative == Vector3::zeros() || against(&normal, &relative)
}

/// The predicted face that the segment from the node's start to its predicted position passes
/// through (7.4.3), the crossing nearest the start.
fn trajectory_intersection(
    master: &ContactSurface,
    candidates: &[u32],
    node: &Trajectory,
    x1: &[Vector3<f64>],
    tolerance: f64,
) -> Option<(u32, [f64; 3])> {
    let mut best: Option<(f64, u32, [f64; 3])> = None;
    let d = node.end - node.start;
    for &i in candidates {
        let face = master.faces[i as usize];
        let [a, b, c] = face.map(|n| x1[n as usize]);
        let n = (b - a).cross(&(c - a));
        let denom = n.dot(&d);
        if denom.abs() <= f64::EPSILON * n.norm() * d.norm() {
            continue;
        }
        let s = n.dot(&(a - node.start)) / denom;
        if !(-tolerance..=1.0 + tolerance).contains(&s) {
            continue;
        }
        let w = triangle_weights(&(node.start + d * s), &a, &b, &c);
        if w.iter().all(|&x| x >= -tolerance) && best.is_none_or(|(t, _, _)| s < t) {
            best = Some((s, i, w));
        }
    }
    best.map(|(_, f, w)| (f, w))
}

/// The candidate face whose contact point for the node's predicted position `p` is closest
/// (7.4.2), with that point's weights ([`clamped_triangle_weights`]). Faces the node lies behind
/// come first, if it could have gone that deep in the step: a node that went in near an edge
/// also lies on the plane of the side face there, at distance zero, but it went in through the
/// face it is behind. "Behind" means the offset to the contact point runs mostly along the face's
/// normal (within 45 degrees), not only that the node is behind the face's plane, and "that
/// deep" means within `reach` (the depth of the boundary layer, where global detection found the
/// node) and within a tenth of it or twice the step's motion of the node and the face's nodes,
/// whichever is larger (a node left inside by an earlier step is behind the face it went
/// through by a small part of an element). Without
/// these, nodes on the plate's bottom face at the opening's edge, found inside within the
/// detection tolerance, were given contact points 1.3 mm away (across a block face, at a plane of
/// symmetry) or 1 mm away (on the opening's wall, behind whose plane the whole bottom face
/// lies), and the step closed those gaps (53 and 300 km/s).
fn closest_point(
    master: &ContactSurface,
    candidates: &[u32],
    node: &Trajectory,
    x0: &[Vector3<f64>],
    x1: &[Vector3<f64>],
    reach: f64,
) -> Option<(u32, [f64; 3])> {
    let p = &node.end;
    let node_motion = (node.end - node.start).norm();
    // Key: (not behind, distance), compared lexicographically.
    let mut best: Option<((bool, f64), u32, [f64; 3])> = None;
    for &i in candidates {
        let face = master.faces[i as usize];
        let [a, b, c] = face.map(|n| x1[n as usize]);
        let w = clamped_triangle_weights(p, &a, &b, &c);
        let q = a * w[0] + b * w[1] + c * w[2];
        let normal = (b - a).cross(&(c - a));
        let distance = (q - p).norm();
        let face_motion = face
            .iter()
            .map(|&n| (x1[n as usize] - x0[n as usize]).norm())
            .fold(0.0, f64::max);
        let depth_reachable =
            distance <= reach.min((0.1 * reach).max(2.0 * (node_motion + face_motion)));
        // Behind the face, not only behind its plane (see the function's comment).
        let behind = against(&normal, &(p - q))
            && normal.dot(&(q - p)).abs()
                >= std::f64::consts::FRAC_1_SQRT_2 * normal.norm() * distance;
        let key = (!(behind && depth_reachable), distance);
        if best.is_none_or(|(k, _, _)| key < k) {
            best = Some((key, i, w));
        }
    }
    best.map(|(_, f, w)| (f, w))
}
