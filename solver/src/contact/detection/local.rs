//! Local detection (thesis 7.4): for a slave node global detection found inside the master, the
//! master boundary face it went through and the contact point on it. Three strategies, in
//! order: continuous collision detection (7.4.4), the intersection of the node's trajectory with
//! the predicted face (7.4.3), the closest point (7.4.2). Candidate faces come from a grid of the
//! faces' swept boxes near the region global detection searched.

use nalgebra::Vector3;

use super::{CcdCall, ContactSurface, DetectionSettings};
use crate::contact::broad_phase::{Aabb, UniformGrid};
use crate::contact::ccd::{vertex_face_ccd, CcdHit, Trajectory};
use crate::contact::geometry::{against, clamped_triangle_weights, triangle_weights};

/// Which strategy found a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Strategy {
    Ccd,
    Trajectory,
    ClosestPoint,
}

/// The master faces one pass may assign nodes to, with their swept boxes in a grid.
pub(super) struct LocalSearch<'a> {
    master: &'a ContactSurface,
    /// The global search's length scale (see `GlobalSearch::typical`).
    typical: f64,
    /// Master faces with a corner near the overlap region, as master face ids.
    near_faces: Vec<u32>,
    /// Each near face's box over the step (start and predicted corners).
    swept_faces: Vec<Aabb>,
    face_grid: UniformGrid,
    faces: Vec<u32>,
}

impl<'a> LocalSearch<'a> {
    /// The faces of `master` within `3 typical` of `overlap`, on the positions at the start of
    /// the step `x0` and the predicted ones `x1`.
    pub(super) fn new(
        master: &'a ContactSurface,
        overlap: &Aabb,
        typical: f64,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
    ) -> Self {
        // A node's faces are searched within `typical` of its path, which is shorter than an
        // element (the step is below the stable one), so faces farther out are never candidates.
        let face_region = overlap.grown(3.0 * typical);
        let near_faces: Vec<u32> = (0..master.faces.len() as u32)
            .filter(|&f| {
                master.faces[f as usize]
                    .iter()
                    .any(|&n| face_region.contains(&x1[n as usize]))
            })
            .collect();
        let swept_faces: Vec<Aabb> = near_faces
            .iter()
            .map(|&f| {
                Aabb::of_points(
                    master.faces[f as usize]
                        .iter()
                        .flat_map(|&n| [&x0[n as usize], &x1[n as usize]]),
                )
            })
            .collect();
        let face_grid = UniformGrid::build(&swept_faces, typical);
        Self {
            master,
            typical,
            near_faces,
            swept_faces,
            face_grid,
            faces: Vec::new(),
        }
    }

    /// Faces whose swept box meets `region`, as master face ids, into `self.faces`.
    fn candidates(&mut self, region: Aabb) {
        let out = &mut self.faces;
        self.face_grid.query(&region, out);
        out.retain(|&f| self.swept_faces[f as usize].overlaps(&region));
        out.iter_mut()
            .for_each(|f| *f = self.near_faces[*f as usize]);
    }

    /// The face the penetrating `node` is assigned to and the weights of its contact point, by
    /// the first strategy that finds one; every CCD call is appended to `ccd_calls` when given.
    pub(super) fn contact_point(
        &mut self,
        node: &Trajectory,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
        settings: &DetectionSettings,
        ccd_calls: Option<&mut Vec<CcdCall>>,
    ) -> Option<(u32, [f64; 3], Strategy)> {
        // A face the node crosses holds the crossing point, which lies on the node's path: the
        // path's box (grown by the detection tolerance) finds every such face.
        let path = Aabb::of_points([&node.start, &node.end]);
        self.candidates(path.grown(settings.tolerance * self.typical));
        let master = self.master;
        earliest_ccd(
            master,
            &self.faces,
            node,
            x0,
            x1,
            settings.tolerance,
            ccd_calls,
        )
        .map(|(f, w)| (f, w, Strategy::Ccd))
        .or_else(|| {
            trajectory_intersection(master, &self.faces, node, x1, settings.tolerance)
                .map(|(f, w)| (f, w, Strategy::Trajectory))
        })
        .or_else(|| {
            self.candidates(path.grown(self.typical));
            closest_point(master, &self.faces, &node.end, x1, self.typical)
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

/// The candidate face whose contact point for `p` is closest (7.4.2), with that point's weights
/// ([`clamped_triangle_weights`]). Faces within `reach` (the depth of the boundary layer, where
/// global detection found the node) that the node lies behind (`n . (p - q) < 0`) come first: a
/// node that went in near an edge also lies on the plane of the side face there, at distance
/// zero, but it went in through the face it is behind.
fn closest_point(
    master: &ContactSurface,
    candidates: &[u32],
    p: &Vector3<f64>,
    x1: &[Vector3<f64>],
    reach: f64,
) -> Option<(u32, [f64; 3])> {
    // Key: (not behind, distance), compared lexicographically.
    let mut best: Option<((bool, f64), u32, [f64; 3])> = None;
    for &i in candidates {
        let face = master.faces[i as usize];
        let [a, b, c] = face.map(|n| x1[n as usize]);
        let w = clamped_triangle_weights(p, &a, &b, &c);
        let q = a * w[0] + b * w[1] + c * w[2];
        let behind = against(&(b - a).cross(&(c - a)), &(p - q));
        let distance = (q - p).norm();
        let key = (!(behind && distance <= reach), distance);
        if best.is_none_or(|(k, _, _)| key < k) {
            best = Some((key, i, w));
        }
    }
    best.map(|(_, f, w)| (f, w))
}
