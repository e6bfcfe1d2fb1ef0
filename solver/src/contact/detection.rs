//! Global and local contact detection (thesis 7.3 and 7.4; FORMULATION section 4).
//!
//! Global detection finds the slave boundary nodes whose predicted position lies inside a
//! master element of the boundary layer (signed volumes, Box 7.2), with a uniform grid so each
//! node is tested only against nearby elements (7.3.3). Local detection then picks the master
//! boundary face the node went through and the contact point on it: continuous collision
//! detection first (7.4.4), then the intersection of the node's trajectory with the predicted
//! face (7.4.3), then the closest point (7.4.2); a node none of them resolves is counted.

use nalgebra::Vector3;

use super::broad_phase::{Aabb, UniformGrid};
use super::ccd::{vertex_face_ccd, Trajectory};
use super::gauss_seidel::ContactConstraint;
use super::normals::{contact_normal, facet_normals, NormalSettings};
use crate::mesh::{boundary_faces_of, boundary_nodes};
use crate::model::Model;

/// The contact surface of one body: its boundary faces (outward), boundary nodes and the
/// elements of its boundary layer (those with a node on the boundary).
#[derive(Debug, Clone)]
pub struct ContactSurface {
    pub body: usize,
    pub faces: Vec<[u32; 3]>,
    /// Sorted boundary nodes.
    pub nodes: Vec<u32>,
    pub layer: Vec<u32>,
    /// Each face's corners as indices into `nodes`.
    corners: Vec<[u32; 3]>,
    /// The faces around each boundary node: `node_faces[offsets[l]..offsets[l + 1]]` for
    /// `nodes[l]`.
    offsets: Vec<u32>,
    node_faces: Vec<u32>,
}

impl ContactSurface {
    pub fn new(model: &Model, body: usize) -> Self {
        let range = model.bodies[body].elements.clone();
        let boundary = boundary_faces_of(&model.tets[range.clone()]);
        let nodes = boundary_nodes(&boundary);
        let faces: Vec<[u32; 3]> = boundary.into_iter().map(|f| f.nodes).collect();
        let layer = range
            .filter(|&e| model.tets[e].iter().any(|n| nodes.binary_search(n).is_ok()))
            .map(|e| e as u32)
            .collect();
        let corners: Vec<[u32; 3]> = faces
            .iter()
            .map(|f: &[u32; 3]| f.map(|n| nodes.binary_search(&n).unwrap() as u32))
            .collect();
        let mut offsets = vec![0u32; nodes.len() + 1];
        for c in corners.iter().flatten() {
            offsets[*c as usize + 1] += 1;
        }
        for l in 0..nodes.len() {
            offsets[l + 1] += offsets[l];
        }
        let mut fill = offsets.clone();
        let mut node_faces = vec![0u32; offsets[nodes.len()] as usize];
        for (f, c) in corners.iter().enumerate() {
            for &l in c {
                node_faces[fill[l as usize] as usize] = f as u32;
                fill[l as usize] += 1;
            }
        }
        Self {
            body,
            faces,
            nodes,
            layer,
            corners,
            offsets,
            node_faces,
        }
    }

    /// The faces that share corner `k` of face `face` (including `face`), in ascending order.
    pub fn faces_at_corner(&self, face: usize, k: usize) -> &[u32] {
        let l = self.corners[face][k] as usize;
        &self.node_faces[self.offsets[l] as usize..self.offsets[l + 1] as usize]
    }
}

/// Barycentric coordinates of `p` in the tetrahedron `x` from signed sub-volumes (3.46):
/// `xi_k = V(x with node k replaced by p) / V(x)`.
pub fn tetrahedron_barycentric(p: &Vector3<f64>, x: &[Vector3<f64>; 4]) -> [f64; 4] {
    let vol = |a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>, d: &Vector3<f64>| {
        (b - a).cross(&(c - a)).dot(&(d - a))
    };
    let v = vol(&x[0], &x[1], &x[2], &x[3]);
    [
        vol(p, &x[1], &x[2], &x[3]) / v,
        vol(&x[0], p, &x[2], &x[3]) / v,
        vol(&x[0], &x[1], p, &x[3]) / v,
        vol(&x[0], &x[1], &x[2], p) / v,
    ]
}

/// How each detected contact was resolved in one pass.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DetectionStats {
    /// Slave nodes found inside a master element.
    pub penetrating: usize,
    pub by_ccd: usize,
    pub by_trajectory: usize,
    pub by_closest_point: usize,
    /// Penetrations no local strategy could assign to a face: reported, never dropped silently.
    pub unresolved: usize,
}

/// Settings of detection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectionSettings {
    /// Tolerance on barycentric coordinates (inside when all are `>= -tolerance`).
    pub tolerance: f64,
    /// Coulomb coefficient given to the constraints.
    pub friction: f64,
    pub normals: NormalSettings,
}

/// One call of [`vertex_face_ccd`] made by local detection, with its answer: the input of a
/// cross-check of our CCD against another implementation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdCall {
    pub node: Trajectory,
    /// The face's node trajectories, in the face's node order.
    pub face: [Trajectory; 3],
    /// The barycentric tolerance passed to [`vertex_face_ccd`].
    pub tolerance: f64,
    /// The hit time it returned, before detection's filter of nodes that do not move into the
    /// face.
    pub hit: Option<f64>,
}

/// Constraints of the slave surface's nodes against the master surface for one pass, from the
/// positions at the start of the step `x0` and the predicted positions `x1`.
pub fn detect(
    model: &Model,
    slave: &ContactSurface,
    master: &ContactSurface,
    x0: &[Vector3<f64>],
    x1: &[Vector3<f64>],
    settings: &DetectionSettings,
) -> (Vec<ContactConstraint>, DetectionStats) {
    detect_recording(model, slave, master, x0, x1, settings, None)
}

/// [`detect`], appending every CCD call it makes to `ccd_calls` when given. Recording changes
/// nothing in the result.
pub fn detect_recording(
    model: &Model,
    slave: &ContactSurface,
    master: &ContactSurface,
    x0: &[Vector3<f64>],
    x1: &[Vector3<f64>],
    settings: &DetectionSettings,
    mut ccd_calls: Option<&mut Vec<CcdCall>>,
) -> (Vec<ContactConstraint>, DetectionStats) {
    let mut stats = DetectionStats::default();
    let mut constraints = Vec::new();
    // Skip the pass when the slave nodes cannot reach the master's boundary layer.
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
        return (constraints, stats);
    }
    // Only the master elements and faces where the two bodies' boxes overlap can be reached:
    // for two spheres, a thin slab around the contact instead of the whole boundary layer.
    let overlap = slave_box.intersection(&master_box);
    let near: Vec<u32> = (0..element_boxes.len() as u32)
        .filter(|&i| element_boxes[i as usize].overlaps(&overlap))
        .collect();
    if near.is_empty() {
        return (constraints, stats);
    }
    let near_boxes: Vec<Aabb> = near.iter().map(|&i| element_boxes[i as usize]).collect();
    let typical = near_boxes
        .iter()
        .map(|b| (b.max - b.min).max())
        .sum::<f64>()
        / near_boxes.len() as f64;
    let element_grid = UniformGrid::build(&near_boxes, typical);
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
    let (mut elements, mut faces) = (Vec::new(), Vec::new());
    let mut facet: Option<Vec<Vector3<f64>>> = None;
    for &s in &slave.nodes {
        let p = x1[s as usize];
        if !overlap.contains(&p) {
            continue;
        }
        element_grid.query(&Aabb { min: p, max: p }, &mut elements);
        let inside = elements.iter().any(|&i| {
            let e = master.layer[near[i as usize] as usize];
            let tet = model.tets[e as usize].map(|n| x1[n as usize]);
            tetrahedron_barycentric(&p, &tet)
                .iter()
                .all(|&xi| xi >= -settings.tolerance)
        });
        if !inside {
            continue;
        }
        stats.penetrating += 1;
        let node = Trajectory {
            start: x0[s as usize],
            end: p,
        };
        // Faces whose swept box meets `region`, as master face ids.
        let candidates = |region: Aabb, out: &mut Vec<u32>| {
            face_grid.query(&region, out);
            out.retain(|&f| swept_faces[f as usize].overlaps(&region));
            out.iter_mut().for_each(|f| *f = near_faces[*f as usize]);
        };
        // A face the node crosses holds the crossing point, which lies on the node's path: the
        // path's box (grown by the detection tolerance) finds every such face.
        let path = Aabb::of_points([&node.start, &node.end]);
        candidates(path.grown(settings.tolerance * typical), &mut faces);
        let resolved = earliest_ccd(
            master,
            &faces,
            &node,
            x0,
            x1,
            settings.tolerance,
            ccd_calls.as_deref_mut(),
        )
        .map(|(f, w)| (f, w, &mut stats.by_ccd))
        .or_else(|| {
            trajectory_intersection(master, &faces, &node, x1, settings.tolerance)
                .map(|(f, w)| (f, w, &mut stats.by_trajectory))
        })
        .or_else(|| {
            candidates(path.grown(typical), &mut faces);
            closest_point(master, &faces, &p, x1, typical)
                .map(|(f, w)| (f, w, &mut stats.by_closest_point))
        });
        match resolved {
            Some((face, weights, counter)) => {
                *counter += 1;
                let facet = facet.get_or_insert_with(|| facet_normals(master, x1));
                let normal =
                    contact_normal(master, facet, face as usize, &weights, &settings.normals);
                constraints.push(ContactConstraint {
                    slave: s,
                    face: master.faces[face as usize],
                    weights,
                    normal,
                    friction: settings.friction,
                });
            }
            None => stats.unresolved += 1,
        }
    }
    (constraints, stats)
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
fn moves_into(node: &Trajectory, face: &[Trajectory; 3], hit: &super::ccd::CcdHit) -> bool {
    let at = |tr: &Trajectory| tr.start + (tr.end - tr.start) * hit.t;
    let [a, b, c] = [at(&face[0]), at(&face[1]), at(&face[2])];
    let normal = (b - a).cross(&(c - a));
    let relative = (node.end - node.start)
        - (0..3).fold(Vector3::zeros(), |sum, k| {
            sum + (face[k].end - face[k].start) * hit.weights[k]
        });
    relative == Vector3::zeros() || against(&normal, &relative)
}

/// Whether `v` points against the (unnormalised) normal `n`, beyond rounding.
fn against(n: &Vector3<f64>, v: &Vector3<f64>) -> bool {
    n.dot(v) < -1e-12 * n.norm() * v.norm()
}

/// Barycentric weights of the point of the triangle `(a, b, c)`'s plane nearest `p`.
fn triangle_weights(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> [f64; 3] {
    let n = (b - a).cross(&(c - a));
    let area2 = n.norm_squared();
    let wa = (b - p).cross(&(c - p)).dot(&n) / area2;
    let wb = (c - p).cross(&(a - p)).dot(&n) / area2;
    [wa, wb, 1.0 - wa - wb]
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

/// The candidate face whose nearest point to `p` is closest (7.4.2), with the weights of that
/// point clamped into the triangle. Faces within `reach` (the depth of the boundary layer,
/// where global detection found the node) that the node lies behind (`n . (p - q) < 0`) come
/// first: a node that went in near an edge also lies on the plane of the side face there, at
/// distance zero, but it went in through the face it is behind.
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
        let mut w = triangle_weights(p, &a, &b, &c).map(|x| x.max(0.0));
        let sum: f64 = w.iter().sum();
        w.iter_mut().for_each(|x| *x /= sum);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::test_blocks::elastic_boxes;
    use crate::mesh::BoxSpec;

    fn two_blocks(gap: f64) -> Model {
        elastic_boxes(&[
            BoxSpec {
                origin: [0.0; 3],
                size: [1.0, 1.0, 0.5],
                divisions: [4, 4, 2],
            },
            BoxSpec {
                origin: [0.1, 0.15, 0.5 + gap],
                size: [0.7, 0.6, 0.5],
                divisions: [3, 3, 2],
            },
        ])
    }

    #[test]
    fn barycentric_coordinates_sum_to_one_and_locate_points() {
        let x = [Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()];
        let xi = tetrahedron_barycentric(&Vector3::new(0.1, 0.2, 0.3), &x);
        assert!((xi.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!(
            (xi[1] - 0.1).abs() < 1e-15
                && (xi[2] - 0.2).abs() < 1e-15
                && (xi[3] - 0.3).abs() < 1e-15
        );
        assert!(tetrahedron_barycentric(&Vector3::new(0.6, 0.6, 0.1), &x)[0] < 0.0);
    }

    #[test]
    fn nodes_pushed_into_the_lower_block_are_found_on_the_top_face() {
        let model = two_blocks(1e-3);
        let lower = ContactSurface::new(&model, 0);
        let upper = ContactSurface::new(&model, 1);
        let x0: Vec<Vector3<f64>> = model.reference.clone();
        // The upper block moves down by 3 mm: its bottom nodes end 2 mm inside the lower block.
        let mut x1 = x0.clone();
        for n in model.bodies[1].nodes.clone() {
            x1[n].z -= 3e-3;
        }
        let settings = DetectionSettings {
            tolerance: 1e-9,
            friction: 0.0,
            normals: NormalSettings::default(),
        };
        let (constraints, stats) = detect(&model, &upper, &lower, &x0, &x1, &settings);
        let bottom = model.bodies[1]
            .nodes
            .clone()
            .filter(|&n| (model.reference[n].z - 0.501).abs() < 1e-12)
            .count();
        assert_eq!(stats.penetrating, bottom, "{stats:?}");
        assert_eq!(stats.by_ccd, bottom);
        assert_eq!(stats.unresolved, 0);
        for c in &constraints {
            assert!(
                (c.normal - Vector3::z()).norm() < 1e-12,
                "the top face's outward normal is +z"
            );
            let g = c.gap(&x1);
            assert!(
                (g - Vector3::new(0.0, 0.0, 2e-3)).norm() < 1e-12,
                "gap {g:?}"
            );
            assert!(c.weights.iter().all(|&w| w >= -1e-9));
        }
        // The other pass (roles swapped, 7.2): the lower block's top nodes under the upper
        // block's footprint are now 2 mm inside it and go back through its bottom face (-z).
        let (reverse, stats) = detect(&model, &lower, &upper, &x0, &x1, &settings);
        let under = model.bodies[0]
            .nodes
            .clone()
            .filter(|&n| {
                let x = model.reference[n];
                (x.z - 0.5).abs() < 1e-12
                    && (0.1..=0.8).contains(&x.x)
                    && (0.15..=0.75).contains(&x.y)
            })
            .count();
        assert!(under > 0);
        assert_eq!(reverse.len(), under, "{stats:?}");
        // Nodes strictly inside the footprint cross the bottom face; those on its rim may be
        // assigned to a side face, which is as close.
        for c in &reverse {
            let x = model.reference[c.slave as usize];
            if x.y < 0.75 - 1e-9 {
                assert!((c.normal + Vector3::z()).norm() < 1e-12, "node {x:?}");
                assert!((c.gap(&x1) - Vector3::new(0.0, 0.0, -2e-3)).norm() < 1e-12);
            }
        }
    }

    #[test]
    fn nodes_on_the_rim_of_equal_blocks_go_through_the_top_face_not_the_side() {
        // Same footprint, non-matching meshes: the upper block's rim nodes run down the lower
        // block's side planes. CCD sees them coplanar with the side faces all step long; only
        // the top face is crossed, and the closest point must not take a side face either.
        let block = |z: f64, n: usize| BoxSpec {
            origin: [0.0, 0.0, z],
            size: [1.0, 1.0, 0.5],
            divisions: [n, n, 2],
        };
        let model = elastic_boxes(&[block(0.0, 4), block(0.5, 3)]);
        let (lower, upper) = (
            ContactSurface::new(&model, 0),
            ContactSurface::new(&model, 1),
        );
        let x0 = model.reference.clone();
        let mut x1 = x0.clone();
        for n in model.bodies[1].nodes.clone() {
            x1[n].z -= 2e-3;
        }
        let settings = DetectionSettings {
            tolerance: 1e-9,
            friction: 0.0,
            normals: NormalSettings::default(),
        };
        let (constraints, stats) = detect(&model, &upper, &lower, &x0, &x1, &settings);
        assert_eq!(constraints.len(), 16, "all 4 x 4 bottom nodes: {stats:?}");
        assert_eq!(stats.unresolved, 0);
        for c in &constraints {
            assert!((c.normal - Vector3::z()).norm() < 1e-12, "{c:?}");
        }
        // Already inside at the start (no crossing in this step): the closest point takes the
        // face the node is behind, the top face, not the side plane it lies on.
        let x_inside: Vec<Vector3<f64>> = x1.clone();
        let mut x2 = x_inside.clone();
        for n in model.bodies[1].nodes.clone() {
            x2[n].z -= 1e-4;
        }
        let (constraints, stats) = detect(&model, &upper, &lower, &x_inside, &x2, &settings);
        assert_eq!(constraints.len(), 16, "{stats:?}");
        assert_eq!(stats.by_closest_point, 16);
        for c in &constraints {
            assert!((c.normal - Vector3::z()).norm() < 1e-12, "{c:?}");
        }
    }

    #[test]
    fn separated_bodies_skip_detection() {
        let model = two_blocks(0.1);
        let (lower, upper) = (
            ContactSurface::new(&model, 0),
            ContactSurface::new(&model, 1),
        );
        let x = model.reference.clone();
        let (c, stats) = detect(
            &model,
            &upper,
            &lower,
            &x,
            &x,
            &DetectionSettings {
                tolerance: 1e-9,
                friction: 0.0,
                normals: NormalSettings::default(),
            },
        );
        assert!(c.is_empty());
        assert_eq!(stats, DetectionStats::default());
    }
}
