//! Contact detection of one pass (thesis 7.3 and 7.4; FORMULATION section 4): the contact
//! surfaces, and the pass that turns predicted positions into constraints.
//!
//! Global detection (`global`) finds the slave boundary nodes whose predicted position lies
//! inside a master element of the boundary layer (signed volumes, Box 7.2), with a uniform grid
//! so each node is tested only against nearby elements (7.3.3). Local detection (`local`) then
//! picks the master boundary face the node went through and the contact point on it: continuous
//! collision detection first (7.4.4), then the intersection of the node's trajectory with the
//! predicted face (7.4.3), then the closest point (7.4.2); a node none of them resolves is
//! counted. Both work on the primitives of `geometry::proximity`.
//!
//! The per-node part of a pass (whether the node penetrates, its face and contact point, the
//! normal there) reads the positions and the pass's searches only, so it runs in parallel over
//! the slave nodes; the constraints are then gathered in slave-node order, as a sequential loop
//! would make them, so the solvers see the same problem whatever the number of threads.

mod global;
mod local;
pub mod normals;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::ccd::Trajectory;
use super::gauss_seidel::ContactConstraint;
use crate::mesh::{boundary_faces_of, boundary_nodes};
use crate::model::Model;
use global::{GlobalSearch, LayerBoxes};
use local::{FaceBoxes, FaceScratch, LocalSearch, Strategy};
use normals::{contact_normal_with, facet_normal, NormalSettings};

/// The kept grids of detection ([`global::LayerBoxes`], [`local::FaceBoxes`]) are rebuilt once a
/// node moved this fraction of a cell since: the queries grow by that motion, and a small
/// fraction keeps them to the few cells around the query (a rebuild costs one scan of the
/// surface; the sphere-impact scene rebuilds every few hundred steps).
const REBUILD_FRACTION: f64 = 1.0 / 16.0;

/// Fewest slave nodes one task of the parallel node search takes: a penetrating node costs a
/// few microseconds, about what handing a task to another thread costs, so a pass with a handful
/// of nodes near the contact stays on the calling thread.
const NODES_PER_TASK: usize = 8;

/// The contact surface of one body: its boundary faces (outward), boundary nodes and the
/// elements of its boundary layer (those with a node on the boundary).
#[derive(Debug, Clone)]
pub struct ContactSurface {
    /// Index of the body in the model.
    pub body: usize,
    /// Boundary faces as global node indices, counter-clockwise seen from outside (outward
    /// right-hand normal).
    pub faces: Vec<[u32; 3]>,
    /// Sorted boundary nodes.
    pub nodes: Vec<u32>,
    /// Global indices of the boundary-layer elements (a node on the boundary), ascending: the
    /// elements global detection tests slave nodes against (Box 7.2).
    pub layer: Vec<u32>,
    /// Each face's corners as indices into `nodes`.
    corners: Vec<[u32; 3]>,
    /// The faces around each boundary node: `node_faces[offsets[l]..offsets[l + 1]]` for
    /// `nodes[l]`.
    offsets: Vec<u32>,
    node_faces: Vec<u32>,
}

impl ContactSurface {
    /// The surface of body `body` of `model`: its boundary faces, nodes and layer.
    pub fn new(model: &Model, body: usize) -> Self {
        Self::with_faces(model, body, |_| true)
    }

    /// The surface of body `body` of `model` over the boundary faces that `keep` accepts.
    pub fn with_faces(model: &Model, body: usize, keep: impl Fn(&[u32; 3]) -> bool) -> Self {
        let range = model.bodies[body].elements.clone();
        let mut boundary = boundary_faces_of(&model.tets[range.clone()]);
        boundary.retain(|f| keep(&f.nodes));
        let nodes = boundary_nodes(&boundary);
        let faces: Vec<[u32; 3]> = boundary.into_iter().map(|f| f.nodes).collect();
        let layer = range
            .filter(|&e| model.tets[e].iter().any(|n| nodes.binary_search(n).is_ok()))
            .map(|e| e as u32)
            .collect();
        let corners: Vec<[u32; 3]> = faces
            .iter()
            .map(|f: &[u32; 3]| {
                f.map(|n| {
                    nodes
                        .binary_search(&n)
                        .expect("`nodes` holds every node of the boundary faces")
                        as u32
                })
            })
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
        self.faces_at_node(self.corners[face][k] as usize)
    }

    /// The faces around boundary node `nodes[l]`, in ascending order.
    pub fn faces_at_node(&self, l: usize) -> &[u32] {
        &self.node_faces[self.offsets[l] as usize..self.offsets[l + 1] as usize]
    }
}

/// How each detected contact was resolved in one pass.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DetectionStats {
    /// Slave nodes found inside a master element.
    pub penetrating: usize,
    /// Of those, assigned to a face by continuous collision detection (7.4.4).
    pub by_ccd: usize,
    /// Assigned by the intersection of the node's trajectory with the predicted face (7.4.3).
    pub by_trajectory: usize,
    /// Assigned by the closest point on the master surface (7.4.2).
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
    /// How the constraints' normals are formed.
    pub normals: NormalSettings,
    /// How much a penetration left from an earlier step must shrink in this one (m): a node
    /// found behind a face it did not cross in the step (closest-point detection) may stay
    /// behind it by its depth at the step's start less this
    /// ([`ContactConstraint::allowance`]). `f64::INFINITY`: closed at once.
    pub release: f64,
}

/// One call of [`vertex_face_ccd`](crate::contact::ccd::vertex_face_ccd) made by local detection, with its answer: the input of a
/// cross-check of our CCD against another implementation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdCall {
    /// The slave node's straight-line motion over the step.
    pub node: Trajectory,
    /// The face's node trajectories, in the face's node order.
    pub face: [Trajectory; 3],
    /// The barycentric tolerance passed to [`vertex_face_ccd`](crate::contact::ccd::vertex_face_ccd).
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
    ccd_calls: Option<&mut Vec<CcdCall>>,
) -> (Vec<ContactConstraint>, DetectionStats) {
    Detector::default().detect(model, slave, master, x0, x1, settings, ccd_calls)
}

/// Detection of one pass kept over a run: what it can carry from step to step (the master
/// boundary layer's boxes in a grid, refitted instead of rebuilt; scratch space) so a step pays
/// only for the region where the bodies' boxes overlap. Its answers are bitwise those of
/// [`detect`]. A detector serves one master surface: keep one per pass.
#[derive(Debug, Clone, Default)]
pub struct Detector {
    layer: LayerBoxes,
    faces: FaceBoxes,
    /// Scratch: the slave nodes whose predicted position lies in the pass's overlap region, in
    /// slave-node order, and what the search found for each.
    reachable: Vec<u32>,
    outcomes: Vec<NodeOutcome>,
}

/// What one pass found for one slave node.
#[derive(Debug, Clone, Default)]
struct NodeOutcome {
    contact: NodeContact,
    /// The CCD calls made for the node, when they are recorded.
    ccd_calls: Vec<CcdCall>,
}

/// Whether a slave node penetrates, and where it is assigned when it does.
#[derive(Debug, Clone, Copy, Default)]
enum NodeContact {
    /// Inside no master element: no contact.
    #[default]
    Outside,
    /// Inside, but no local strategy found its face.
    Unresolved,
    /// Inside, assigned to master face `face` at the contact point of `weights`.
    Assigned {
        face: u32,
        weights: [f64; 3],
        strategy: Strategy,
        normal: Vector3<f64>,
    },
}

impl Detector {
    /// [`detect_recording`] for the master surface this detector serves.
    #[allow(clippy::too_many_arguments)]
    pub fn detect(
        &mut self,
        model: &Model,
        slave: &ContactSurface,
        master: &ContactSurface,
        x0: &[Vector3<f64>],
        x1: &[Vector3<f64>],
        settings: &DetectionSettings,
        ccd_calls: Option<&mut Vec<CcdCall>>,
    ) -> (Vec<ContactConstraint>, DetectionStats) {
        let mut stats = DetectionStats::default();
        let mut constraints = Vec::new();
        let Some(global) = GlobalSearch::new(
            model,
            slave,
            master,
            x1,
            &mut self.layer,
            settings.tolerance,
        ) else {
            return (constraints, stats);
        };
        let local = LocalSearch::new(
            master,
            &global.overlap,
            global.typical,
            x0,
            x1,
            &mut self.faces,
        );
        // Only a node in the overlap of the bodies' boxes can be inside a master element: a
        // cheap test that leaves a few nodes around the contact for the parallel search.
        self.reachable.clear();
        self.reachable.extend(
            slave
                .nodes
                .iter()
                .copied()
                .filter(|&s| global.overlap.contains(&x1[s as usize])),
        );
        let record = ccd_calls.is_some();
        self.reachable
            .par_iter()
            .with_min_len(NODES_PER_TASK)
            .map_init(FaceScratch::default, |scratch, &s| {
                let mut calls = Vec::new();
                let contact = node_contact(
                    model,
                    master,
                    &global,
                    &local,
                    s,
                    x0,
                    x1,
                    settings,
                    scratch,
                    record.then_some(&mut calls),
                );
                NodeOutcome {
                    contact,
                    ccd_calls: calls,
                }
            })
            .collect_into_vec(&mut self.outcomes);
        // In slave-node order, as the sequential search made them.
        let mut ccd_calls = ccd_calls;
        for (&s, outcome) in self.reachable.iter().zip(&mut self.outcomes) {
            if let Some(calls) = ccd_calls.as_deref_mut() {
                calls.append(&mut outcome.ccd_calls);
            }
            match outcome.contact {
                NodeContact::Outside => continue,
                NodeContact::Unresolved => {
                    stats.penetrating += 1;
                    stats.unresolved += 1;
                }
                NodeContact::Assigned {
                    face,
                    weights,
                    strategy,
                    normal,
                } => {
                    stats.penetrating += 1;
                    *match strategy {
                        Strategy::Ccd => &mut stats.by_ccd,
                        Strategy::Trajectory => &mut stats.by_trajectory,
                        Strategy::ClosestPoint => &mut stats.by_closest_point,
                    } += 1;
                    let mut constraint = ContactConstraint {
                        slave: s,
                        face: master.faces[face as usize],
                        weights,
                        normal,
                        friction: settings.friction,
                        allowance: 0.0,
                    };
                    // Behind a face it did not cross in this step: the depth it started with,
                    // less the release, may stay (0 when closed at once).
                    if strategy == Strategy::ClosestPoint && settings.release.is_finite() {
                        let start_depth = constraint.gap(x0).dot(&normal);
                        constraint.allowance = (start_depth - settings.release).max(0.0);
                    }
                    constraints.push(constraint);
                }
            }
        }
        (constraints, stats)
    }
}

/// Whether slave node `s` penetrates the master (global detection) and, if it does, its face,
/// contact point and normal (local detection); every CCD call is appended to `ccd_calls` when
/// given.
#[allow(clippy::too_many_arguments)]
fn node_contact(
    model: &Model,
    master: &ContactSurface,
    global: &GlobalSearch,
    local: &LocalSearch,
    s: u32,
    x0: &[Vector3<f64>],
    x1: &[Vector3<f64>],
    settings: &DetectionSettings,
    scratch: &mut FaceScratch,
    ccd_calls: Option<&mut Vec<CcdCall>>,
) -> NodeContact {
    let p = x1[s as usize];
    if !global.penetrates(model, master, x1, &p, settings.tolerance) {
        return NodeContact::Outside;
    }
    let node = Trajectory {
        start: x0[s as usize],
        end: p,
    };
    match local.contact_point(&node, x0, x1, settings, scratch, ccd_calls) {
        Some((face, weights, strategy)) => {
            // Facet normals at `x1`, computed for the facets this contact asks for.
            let normal = contact_normal_with(
                master,
                |g| facet_normal(master, x1, g),
                face as usize,
                &weights,
                &settings.normals,
            );
            NodeContact::Assigned {
                face,
                weights,
                strategy,
                normal,
            }
        }
        None => NodeContact::Unresolved,
    }
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
                mirror: Vec::new(),
            },
            BoxSpec {
                origin: [0.1, 0.15, 0.5 + gap],
                size: [0.7, 0.6, 0.5],
                divisions: [3, 3, 2],
                mirror: Vec::new(),
            },
        ])
    }

    /// A 1 x 1 x 0.5 block on another of the same footprint, meshed 4 x 4 and 3 x 3 across
    /// (non-matching), with their surfaces (lower, upper).
    fn equal_footprints() -> (Model, ContactSurface, ContactSurface) {
        let block = |z: f64, n: usize| BoxSpec {
            origin: [0.0, 0.0, z],
            size: [1.0, 1.0, 0.5],
            divisions: [n, n, 2],
            mirror: Vec::new(),
        };
        let model = elastic_boxes(&[block(0.0, 4), block(0.5, 3)]);
        let (lower, upper) = (
            ContactSurface::new(&model, 0),
            ContactSurface::new(&model, 1),
        );
        (model, lower, upper)
    }

    /// `x` with the upper block (body 1) lowered by `dz`.
    fn upper_lowered(model: &Model, x: &[Vector3<f64>], dz: f64) -> Vec<Vector3<f64>> {
        let mut lowered = x.to_vec();
        for n in model.bodies[1].nodes.clone() {
            lowered[n].z -= dz;
        }
        lowered
    }

    /// Frictionless detection that closes every penetration at once.
    fn closed_at_once() -> DetectionSettings {
        DetectionSettings {
            tolerance: 1e-9,
            friction: 0.0,
            normals: NormalSettings::default(),
            release: f64::INFINITY,
        }
    }

    #[test]
    fn nodes_pushed_into_the_lower_block_are_found_on_the_top_face() {
        let model = two_blocks(1e-3);
        let lower = ContactSurface::new(&model, 0);
        let upper = ContactSurface::new(&model, 1);
        let x0: Vec<Vector3<f64>> = model.reference.to_vec();
        // The upper block moves down by 3 mm: its bottom nodes end 2 mm inside the lower block.
        let x1 = upper_lowered(&model, &x0, 3e-3);
        let settings = closed_at_once();
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
        let (model, lower, upper) = equal_footprints();
        let x0 = model.reference.to_vec();
        let x1 = upper_lowered(&model, &x0, 2e-3);
        let settings = closed_at_once();
        let (constraints, stats) = detect(&model, &upper, &lower, &x0, &x1, &settings);
        assert_eq!(constraints.len(), 16, "all 4 x 4 bottom nodes: {stats:?}");
        assert_eq!(stats.unresolved, 0);
        for c in &constraints {
            assert!((c.normal - Vector3::z()).norm() < 1e-12, "{c:?}");
        }
        // Already inside at the start (no crossing in this step): the closest point takes the
        // face the node is behind, the top face, not the side plane it lies on.
        let x2 = upper_lowered(&model, &x1, 1e-4);
        let (constraints, stats) = detect(&model, &upper, &lower, &x1, &x2, &settings);
        assert_eq!(constraints.len(), 16, "{stats:?}");
        assert_eq!(stats.by_closest_point, 16);
        for c in &constraints {
            assert!((c.normal - Vector3::z()).norm() < 1e-12, "{c:?}");
        }
    }

    #[test]
    fn a_node_a_rounding_outside_the_masters_box_is_still_found() {
        // Both blocks end on the plane x = 0, where a mesher put the upper one's nodes at
        // -1.2e-19 m (cos(pi / 2) r) and the lower one's at 0: the upper block's rim nodes on
        // that plane lie outside the lower block's box by that rounding, and must be found as
        // the others are when the upper block is pushed 2 mm into the lower one.
        let (model, lower, upper) = equal_footprints();
        let mut x0 = model.reference.to_vec();
        for n in model.bodies[1].nodes.clone() {
            if x0[n].x == 0.0 {
                x0[n].x = -1.2246467991473532e-19;
            }
        }
        let x1 = upper_lowered(&model, &x0, 2e-3);
        let settings = closed_at_once();
        let (constraints, stats) = detect(&model, &upper, &lower, &x0, &x1, &settings);
        assert_eq!(constraints.len(), 16, "all 4 x 4 bottom nodes: {stats:?}");
        assert_eq!(stats.unresolved, 0);
        let on_plane = constraints
            .iter()
            .filter(|c| x1[c.slave as usize].x < 0.0)
            .count();
        assert_eq!(on_plane, 4, "the rim nodes on x = 0");
    }

    #[test]
    fn a_penetration_left_from_an_earlier_step_is_released_at_the_set_rate() {
        // The upper block's bottom nodes start the step 2 mm inside the lower block and go
        // 0.1 mm deeper: found by closest point, they may stay behind the top face by their
        // starting depth less the release. Nodes that cross the face in the step (3 mm down
        // from 1 mm above it) are closed at once whatever the release.
        let model = two_blocks(1e-3);
        let (lower, upper) = (
            ContactSurface::new(&model, 0),
            ContactSurface::new(&model, 1),
        );
        let settings = |release: f64| DetectionSettings {
            tolerance: 1e-9,
            friction: 0.0,
            normals: NormalSettings::default(),
            release,
        };
        let (inside, deeper) = (
            upper_lowered(&model, &model.reference, 3e-3),
            upper_lowered(&model, &model.reference, 3.1e-3),
        );
        let release = 5e-4;
        let (held, stats) = detect(&model, &upper, &lower, &inside, &deeper, &settings(release));
        assert!(!held.is_empty());
        assert_eq!(stats.by_closest_point, held.len(), "{stats:?}");
        for c in &held {
            assert!((c.normal - Vector3::z()).norm() < 1e-12, "{c:?}");
            assert!((c.allowance - (2e-3 - release)).abs() < 1e-15, "{c:?}");
            // The gap left to close is the step's 0.1 mm plus the release.
            assert!(
                (c.gap(&deeper).z - (0.1e-3 + release)).abs() < 1e-15,
                "{c:?}"
            );
        }
        let (at_once, _) = detect(
            &model,
            &upper,
            &lower,
            &inside,
            &deeper,
            &settings(f64::INFINITY),
        );
        assert!(at_once.iter().all(|c| c.allowance == 0.0));
        let (crossing, stats) = detect(
            &model,
            &upper,
            &lower,
            &model.reference,
            &inside,
            &settings(release),
        );
        assert_eq!(stats.by_ccd, crossing.len(), "{stats:?}");
        assert!(crossing.iter().all(|c| c.allowance == 0.0));
    }

    #[test]
    fn separated_bodies_skip_detection() {
        let model = two_blocks(0.1);
        let (lower, upper) = (
            ContactSurface::new(&model, 0),
            ContactSurface::new(&model, 1),
        );
        let x = model.reference.to_vec();
        let (c, stats) = detect(&model, &upper, &lower, &x, &x, &closed_at_once());
        assert!(c.is_empty());
        assert_eq!(stats, DetectionStats::default());
    }
}
