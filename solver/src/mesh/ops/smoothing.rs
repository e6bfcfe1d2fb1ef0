//! Node smoothing of the remeshed region (step 3 of the method in `mesher/`): inner nodes
//! move freely, nodes on the outer boundary slide within the axis-aligned planes of their faces
//! (symmetry planes), and a move is taken only where it raises the worst element around.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

use super::quality::shape_quality_capped;
use crate::geometry::proximity::{closest_point_on_triangle, point_triangle_distance};
use crate::kinematics::signed_volume;
use crate::mesh::{boundary_faces_of, face_key, TET_FACES};

/// How far apart (m) two coordinates may be and still put their nodes in one axis plane: a few
/// round-offs of the largest coordinate. A node placed on a symmetry plane by a projection (a
/// surface node moved out of a contact partner) can be off it by 1e-20 m.
pub(crate) fn plane_tolerance(nodes: &[Vector3<f64>]) -> f64 {
    4.0 * f64::EPSILON * nodes.iter().map(|p| p.amax()).fold(0.0, f64::max)
}

/// The nodes on the outer boundary of the remeshed region `tets` that may slide without
/// changing the body's shape, each with the axes along which it may move, and those on a
/// curved part of it.
///
/// A face that only one region element holds is on the outer boundary or on the interface
/// with the untouched mesh; the interface's nodes are `pinned`. A boundary face whose three
/// nodes share a coordinate `k` (to [`plane_tolerance`]) lies in the plane `x_k = const` (a
/// symmetry plane, or a flat face not yet deformed). A node all of whose boundary faces lie
/// in such planes may move along the axes none of those planes fixes: in its plane, or along the line where two
/// planes meet (the axis of a quarter model). It stays in the union of its faces as long as none
/// of its elements inverts, which the smoothing ensures, so the boundary keeps its shape
/// exactly. A node with a face in no axis plane (a curved or deformed surface) moves only on
/// that surface, within a bound ([`SurfaceSlide`]).
/// Without this, an element whose nodes all lie on symmetry planes (at the axis under a
/// penetrator) could not be reshaped: refinement alone gives children as flat as itself.
pub(crate) fn boundary_nodes(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    pinned: &[bool],
) -> BoundaryNodes {
    let mut kinds = BoundaryNodes::default();
    for (n, (axes, curved)) in boundary_planes(nodes, tets, pinned) {
        if curved {
            kinds.surface.push((n, axes));
        } else if axes.iter().filter(|&&h| h).count() < 3 {
            kinds.sliding.push((n, axes.map(|h| !h)));
        }
    }
    kinds
}

/// The nodes on the outer boundary of a remeshed region, by what the remesher may do with them
/// ([`boundary_nodes`]). Both lists ascend.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct BoundaryNodes {
    /// Nodes whose boundary faces all lie in axis planes, with the axes along which they may
    /// slide (smoothing and collapses keep the boundary's shape exactly).
    pub sliding: Vec<(u32, [bool; 3])>,
    /// Nodes with a face on a curved or deformed surface (in no axis plane), each with the axes
    /// its other faces' planes fix (a node where the surface meets a symmetry plane): those an
    /// edge collapse may merge along the surface (`collapse.rs`).
    pub surface: Vec<(u32, [bool; 3])>,
}

/// Per node on the outer boundary of `tets` (less the `pinned`): the axes that the planes of
/// its boundary faces in axis planes fix, and whether it has a face in no axis plane. Ordered
/// by node id, so the callers do not depend on hashing.
fn boundary_planes(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    pinned: &[bool],
) -> BTreeMap<u32, ([bool; 3], bool)> {
    let tolerance = plane_tolerance(nodes);
    let mut count: HashMap<[u32; 3], u32> = HashMap::with_capacity(4 * tets.len());
    for tet in tets {
        for f in TET_FACES {
            *count.entry(face_key(f.map(|i| tet[i]))).or_insert(0) += 1;
        }
    }
    let mut planes: BTreeMap<u32, ([bool; 3], bool)> = BTreeMap::new();
    for tet in tets {
        for f in TET_FACES {
            let face = f.map(|i| tet[i]);
            if count[&face_key(face)] != 1 {
                continue;
            }
            let plane = axis_plane(&face.map(|n| nodes[n as usize]), tolerance);
            for n in face {
                if pinned[n as usize] {
                    continue;
                }
                let (axes, curved) = planes.entry(n).or_insert(([false; 3], false));
                match plane {
                    Some(k) => axes[k] = true,
                    None => *curved = true,
                }
            }
        }
    }
    planes
}

/// The axis `k` whose plane `x_k = const` holds the triangle `[a, b, c]` (its three `k`
/// coordinates within `tolerance`), the first if several.
fn axis_plane([a, b, c]: &[Vector3<f64>; 3], tolerance: f64) -> Option<usize> {
    (0..3).find(|&k| {
        let (lo, hi) = (a[k].min(b[k]).min(c[k]), a[k].max(b[k]).max(c[k]));
        hi - lo <= tolerance
    })
}

/// Constrained Laplacian smoothing of the nodes `movable` over the elements `tets` (step 3 of
/// the method): a move is taken only if it raises the worst quality of the node's elements.
/// Each node moves only along the axes its flags free (all three inside the region); each is
/// listed once.
pub(crate) fn smooth(
    nodes: &mut [Vector3<f64>],
    tets: &[[u32; 4]],
    movable: &[(u32, [bool; 3])],
    sweeps: usize,
) {
    smooth_on_surface(nodes, tets, movable, sweeps, &SurfaceSlide::default());
}

/// [`smooth`], with the nodes of `slide` also moving, on the old surface around them
/// ([`SurfaceSlide`]); their flags in `movable` hold the axes their symmetry planes fix.
pub(crate) fn smooth_on_surface(
    nodes: &mut [Vector3<f64>],
    tets: &[[u32; 4]],
    movable: &[(u32, [bool; 3])],
    sweeps: usize,
    slide: &SurfaceSlide,
) {
    let mut incident: BTreeMap<u32, Vec<usize>> =
        movable.iter().map(|&(n, _)| (n, vec![])).collect();
    for (t, tet) in tets.iter().enumerate() {
        for n in tet {
            if let Some(list) = incident.get_mut(n) {
                list.push(t);
            }
        }
    }
    let neighbours: BTreeMap<u32, Vec<u32>> = incident
        .iter()
        .map(|(&n, list)| {
            let set: BTreeSet<u32> = list
                .iter()
                .flat_map(|&t| tets[t])
                .filter(|&m| m != n)
                .collect();
            (n, set.into_iter().collect())
        })
        .collect();
    let worst = |nodes: &[Vector3<f64>], list: &[usize]| {
        list.iter().fold(f64::INFINITY, |lowest, &t| {
            shape_quality_capped(&tets[t].map(|n| nodes[n as usize]), lowest)
        })
    };
    // The worst quality of the elements `list` if it is above `floor`, else `None`: the
    // first element at or below `floor` ends the count, as the candidate cannot be taken then
    // (the same choice as comparing the full minimum, at a fraction of the quality evaluations).
    let worst_above = |nodes: &[Vector3<f64>], list: &[usize], floor: f64| {
        let mut lowest = f64::INFINITY;
        for &t in list {
            // The lowest so far stays above the floor, so this is at or below it only when the
            // element's own quality is.
            lowest = shape_quality_capped(&tets[t].map(|n| nodes[n as usize]), lowest);
            if lowest <= floor {
                return None;
            }
        }
        (lowest > floor).then_some(lowest)
    };
    // A node is looked at again only once it or a node of its elements has moved since it was
    // last looked at: otherwise it would find the same candidates and qualities, and stay (the
    // result is bitwise that of visiting every node in every sweep).
    let index: HashMap<u32, usize> = movable
        .iter()
        .enumerate()
        .map(|(i, &(n, _))| (n, i))
        .collect();
    debug_assert_eq!(index.len(), movable.len(), "a movable node is listed twice");
    let mut stale = vec![true; movable.len()];
    for _ in 0..sweeps {
        let mut moved = false;
        for (i, &(n, free)) in movable.iter().enumerate() {
            if !std::mem::replace(&mut stale[i], false) {
                continue;
            }
            let list = &incident[&n];
            let around = &neighbours[&n];
            if around.is_empty() {
                continue;
            }
            let current = nodes[n as usize];
            let mean = around
                .iter()
                .map(|&m| nodes[m as usize])
                .sum::<Vector3<f64>>()
                / around.len() as f64;
            let mut best = (worst(nodes, list), current);
            // The Laplacian candidates, then a pattern search along the axes with a step of a
            // tenth of the mean distance to the neighbours, halved until one improves.
            let spacing = around
                .iter()
                .map(|&m| (nodes[m as usize] - current).norm())
                .sum::<f64>()
                / around.len() as f64;
            let mut candidates = vec![mean, 0.5 * (current + mean)];
            for step in [0.1, 0.05, 0.025] {
                for axis in (0..3).filter(|&k| free[k]) {
                    for sign in [1.0, -1.0] {
                        let mut c = current;
                        c[axis] += sign * step * spacing;
                        candidates.push(c);
                    }
                }
            }
            for candidate in candidates {
                // A sliding node keeps its held coordinates bit for bit.
                let candidate = match slide.nodes.get(&n) {
                    Some(on) => on.project(&candidate),
                    None => candidate,
                };
                let candidate =
                    Vector3::from_fn(|k, _| if free[k] { candidate[k] } else { current[k] });
                nodes[n as usize] = candidate;
                // The quality first: it rejects most candidates after an element or two, and
                // the surface's deviation is asked only of those it would take.
                if let Some(q) = worst_above(nodes, list, best.0) {
                    if slide.within(n, nodes) {
                        best = (q, candidate);
                    }
                }
            }
            nodes[n as usize] = best.1;
            if best.1 != current {
                moved = true;
                stale[i] = true;
                for m in around {
                    if let Some(&j) = index.get(m) {
                        stale[j] = true;
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// The nodes on a curved part of the outer boundary that the smoothing may slide along it (the
/// cavity around a penetrator's nose), and how far the surface may move.
///
/// Such a node is held in its place by the surface's shape alone, and a cavity wall whose nodes
/// cannot move keeps its collapsed elements: the remesher then peels or erodes them, and the
/// cavity grows away from the penetrator. Here a node's candidate place is projected onto its
/// old fan of boundary faces (the closest point on them, Ericson 2005, 5.1.5: the node stays on
/// the old surface), with the coordinates its symmetry planes fix kept, and taken only where
/// each old place `x_0` stays within `deviation` of the node's new faces in no axis plane
/// (`min_f dist(x_0, f) <= deviation`). Both surfaces are piecewise flat through the same
/// neighbours, so they are furthest apart at the old or the new place of the node: the first is
/// the bound, the second lies on the old surface. Neighbours that both slide may each use the
/// bound, so the surface moves by about it (the same bound as a surface collapse's,
/// [`super::mesher::MesherOptions::surface_deviation`]); the volume and area it changes are
/// recorded with the collapses'. This is how mesh improvers treat a boundary vertex on a curved
/// surface (Freitag & Ollivier-Gooch 1997, 4.2: boundary vertices smoothed within the boundary).
#[derive(Debug, Default)]
pub(crate) struct SurfaceSlide {
    nodes: BTreeMap<u32, SurfaceNode>,
    deviation: f64,
}

/// A node of a [`SurfaceSlide`]: where it was, the old faces around it, and its faces in no axis
/// plane (by node ids; the smoothing changes no connectivity).
#[derive(Debug)]
struct SurfaceNode {
    origin: Vector3<f64>,
    fan: Vec<[Vector3<f64>; 3]>,
    curved: Vec<[u32; 3]>,
    /// The axes its symmetry planes fix.
    held: [bool; 3],
    /// For a node on a symmetry plane (where the surface meets it), the old edges from it of its
    /// faces in no axis plane that lie in the same planes (the seam): it slides along them, and
    /// the planes keep their shape.
    seam: Option<Vec<[Vector3<f64>; 2]>>,
}

impl SurfaceNode {
    /// The point of the old fan nearest `p` (the first on a tie, in face order), or of the
    /// old seam for a node on a symmetry plane.
    fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let mut best = (f64::INFINITY, self.origin);
        if let Some(seam) = &self.seam {
            for [a, b] in seam {
                let ab = b - a;
                let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
                let q = a + t * ab;
                let d = (q - p).norm_squared();
                if d < best.0 {
                    best = (d, q);
                }
            }
            return best.1;
        }
        for [a, b, c] in &self.fan {
            let q = closest_point_on_triangle(p, a, b, c);
            let d = (q - p).norm_squared();
            if d < best.0 {
                best = (d, q);
            }
        }
        best.1
    }
}

impl SurfaceSlide {
    /// The nodes `surface` (from [`boundary_nodes`]) over the region `tets` with coordinates
    /// `nodes`, the surface moving by at most `deviation` (m); none for a deviation of 0.
    pub(crate) fn new(
        nodes: &[Vector3<f64>],
        tets: &[[u32; 4]],
        surface: &[(u32, [bool; 3])],
        deviation: f64,
    ) -> Self {
        let mut slide = Self {
            nodes: BTreeMap::new(),
            deviation,
        };
        if !(deviation > 0.0) {
            return slide;
        }
        for &(n, held) in surface {
            slide.nodes.insert(
                n,
                SurfaceNode {
                    origin: nodes[n as usize],
                    fan: vec![],
                    curved: vec![],
                    held,
                    seam: held.contains(&true).then(Vec::new),
                },
            );
        }
        let tolerance = plane_tolerance(nodes);
        for face in region_boundary_faces(tets) {
            let corners = face.map(|n| nodes[n as usize]);
            let in_plane = axis_plane(&corners, tolerance).is_some();
            for (i, n) in face.into_iter().enumerate() {
                let Some(on) = slide.nodes.get_mut(&n) else {
                    continue;
                };
                on.fan.push(corners);
                if !in_plane {
                    on.curved.push(face);
                }
                if let (Some(seam), false) = (&mut on.seam, in_plane) {
                    for m in [face[(i + 1) % 3], face[(i + 2) % 3]] {
                        let other = nodes[m as usize];
                        let same = (0..3)
                            .all(|k| !on.held[k] || (other[k] - on.origin[k]).abs() <= tolerance);
                        if same && !seam.contains(&[on.origin, other]) {
                            seam.push([on.origin, other]);
                        }
                    }
                }
            }
        }
        slide
    }

    /// Whether node `n`, placed in `nodes`, keeps the surface within the deviation of its old
    /// place (true for a node that does not slide on a surface).
    ///
    /// Both ways: the old place lies within the deviation of the new faces, and the new faces
    /// do not pass outside the old surface by more than it. The corners of a new face all lie
    /// on the old surface, but a flat face across a curved one is farthest from it inside: on
    /// the concave cavity wall around a penetrator a face whose corners slid apart bulged into
    /// the cavity, and an inner node smoothed up to it lay 12.5 um outside the old mesh with a
    /// deviation of 10 um, farther than the transfer allows. So the face's centroid and the
    /// midpoints of its two edges at the node may lie outside the old fans of the face's
    /// sliding corners by at most the deviation. Inward (a face across a convex surface) they
    /// lie in the old mesh, whose elements give them their fields.
    fn within(&self, n: u32, nodes: &[Vector3<f64>]) -> bool {
        let Some(on) = self.nodes.get(&n) else {
            return true;
        };
        let old_place_kept = on
            .curved
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|m| nodes[m as usize]);
                point_triangle_distance(&on.origin, &a, &b, &c)
            })
            .fold(f64::INFINITY, f64::min)
            <= self.deviation;
        // The old surface about a face: the old fans of its sliding corners (a face's centroid
        // may lie over a neighbour's old faces rather than the node's own).
        // Only the outward side counts: a point of the new surface inside the old mesh takes
        // its fields from the element it lies in, one outside has them extrapolated (a face
        // across a convex surface lies inside it, across a concave one outside).
        let near_old_surface = |q: Vector3<f64>, face: &[u32; 3]| {
            let fans = || {
                face.iter()
                    .filter_map(|m| self.nodes.get(m))
                    .flat_map(|corner| corner.fan.iter())
            };
            let (distance, outward) = fans()
                .map(|[a, b, c]| {
                    let p = closest_point_on_triangle(&q, a, b, c);
                    let normal = (b - a).cross(&(c - a));
                    ((q - p).norm(), (q - p).dot(&normal) > 0.0)
                })
                .fold(
                    (f64::INFINITY, false),
                    |best, d| if d.0 < best.0 { d } else { best },
                );
            !outward || distance <= self.deviation
        };
        old_place_kept
            && on.curved.iter().all(|f| {
                let [a, b, c] = f.map(|m| nodes[m as usize]);
                let x = nodes[n as usize];
                near_old_surface((a + b + c) / 3.0, f)
                    && f.iter()
                        .filter(|&&m| m != n)
                        .all(|&m| near_old_surface(0.5 * (x + nodes[m as usize]), f))
            })
    }

    /// Whether no node slides (a deviation of 0, or no node on a curved surface).
    pub(crate) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The nodes that slide, with the axes their symmetry planes leave free (for [`smooth`]).
    pub(crate) fn movable(&self, surface: &[(u32, [bool; 3])]) -> Vec<(u32, [bool; 3])> {
        surface
            .iter()
            .filter(|(n, _)| self.nodes.contains_key(n))
            .map(|&(n, held)| (n, held.map(|h| !h)))
            .collect()
    }
}

/// The faces that one element of `tets` alone holds (the region's outer boundary and its
/// interface with the rest), each in its element's orientation, in element order.
pub(crate) fn region_boundary_faces(tets: &[[u32; 4]]) -> Vec<[u32; 3]> {
    boundary_faces_of(tets)
        .into_iter()
        .map(|f| f.nodes)
        .collect()
}

/// The volume of `tets` and the area of the faces one of them alone holds (m^3, m^2).
pub(crate) fn volume_and_boundary_area(nodes: &[Vector3<f64>], tets: &[[u32; 4]]) -> (f64, f64) {
    let volume = tets
        .iter()
        .map(|t| signed_volume(&t.map(|n| nodes[n as usize])))
        .sum();
    let area = region_boundary_faces(tets)
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|n| nodes[n as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum();
    (volume, area)
}

#[cfg(test)]
mod tests {
    use super::super::quality::{mean_ratio, shape_quality};
    use super::*;

    /// The capped quality is the quality's minimum with the cap, bit for bit, for elements from
    /// regular to slivers and needles, and caps above, near and below their quality (the cube
    /// comparison skips the power only well clear of a tie).
    #[test]
    fn capped_quality_is_bitwise_the_minimum_with_the_cap() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut skipped, mut checked) = (0, 0);
        for k in 0..20_000 {
            let squash = [1.0, 0.1, 1e-3, 1e-6][k % 4];
            let x: [Vector3<f64>; 4] =
                std::array::from_fn(|_| Vector3::new(next(), next(), squash * next()));
            let q = shape_quality(&x);
            for cap in [
                f64::INFINITY,
                2.0 * q,
                q * (1.0 + 1e-12),
                q,
                q * (1.0 - 1e-12),
                0.5 * q,
                next(),
            ] {
                let capped = shape_quality_capped(&x, cap);
                assert_eq!(
                    capped.to_bits(),
                    q.min(cap).to_bits(),
                    "element {x:?}, cap {cap}"
                );
                checked += 1;
                // Where the result lies clearly below the mean ratio, the power is skipped.
                skipped += usize::from(capped > 0.0 && capped < mean_ratio(&x) * (1.0 - 1e-6));
            }
        }
        // The shortcut is exercised, not only the full path.
        assert!(
            checked == 140_000 && skipped > 1000,
            "{skipped} of {checked}"
        );
    }

    /// A node `s` on a bent surface `z = -0.1 x^2`, pushed 0.7 of the way to its ring node at
    /// x = 1, over four elements down to an apex below: the ring and the apex are held. Returns
    /// the nodes, the elements (positively oriented) and `s`.
    fn pushed_surface_node() -> (Vec<Vector3<f64>>, Vec<[u32; 4]>, u32) {
        let z = |x: f64| -0.1 * x * x;
        let mut nodes = vec![Vector3::new(0.7, 0.0, z(0.7))];
        for (x, y) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
            nodes.push(Vector3::new(x, y, z(x)));
        }
        nodes.push(Vector3::new(0.0, 0.0, -1.0));
        let tets = (1..5u32)
            .map(|i| {
                let mut t = [0, i, i % 4 + 1, 5];
                if signed_volume(&t.map(|n| nodes[n as usize])) < 0.0 {
                    t.swap(1, 2);
                }
                t
            })
            .collect();
        (nodes, tets, 0)
    }

    fn worst(nodes: &[Vector3<f64>], tets: &[[u32; 4]]) -> f64 {
        tets.iter()
            .map(|t| shape_quality(&t.map(|n| nodes[n as usize])))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn a_surface_node_slides_on_the_old_surface_within_the_deviation() {
        let (old, tets, s) = pushed_surface_node();
        let fan: Vec<[Vector3<f64>; 3]> = region_boundary_faces(&tets)
            .into_iter()
            .filter(|f| f.contains(&s))
            .map(|f| f.map(|n| old[n as usize]))
            .collect();
        assert_eq!(fan.len(), 4);
        for deviation in [1e-2, 0.05, 1.0] {
            let surface = [(s, [false; 3])];
            let slide = SurfaceSlide::new(&old, &tets, &surface, deviation);
            let mut nodes = old.clone();
            smooth_on_surface(&mut nodes, &tets, &slide.movable(&surface), 100, &slide);
            let p = nodes[s as usize];
            assert!(
                p != old[s as usize],
                "deviation {deviation}: the node did not move"
            );
            assert!(worst(&nodes, &tets) > worst(&old, &tets));
            // On the old surface, to round-off.
            let off = fan
                .iter()
                .map(|[a, b, c]| point_triangle_distance(&p, a, b, c))
                .fold(f64::INFINITY, f64::min);
            assert!(
                off < 1e-15,
                "deviation {deviation}: {off:e} off the old surface"
            );
            // The new surface passes within the deviation of the old place.
            let gap = region_boundary_faces(&tets)
                .into_iter()
                .filter(|f| f.contains(&s))
                .map(|f| {
                    let [a, b, c] = f.map(|n| nodes[n as usize]);
                    point_triangle_distance(&old[s as usize], &a, &b, &c)
                })
                .fold(f64::INFINITY, f64::min);
            assert!(gap <= deviation, "deviation {deviation}: gap {gap:e}");
        }
        // The bound binds: the smaller one stops the node earlier.
        let place = |deviation: f64| {
            let surface = [(s, [false; 3])];
            let slide = SurfaceSlide::new(&old, &tets, &surface, deviation);
            let mut nodes = old.clone();
            smooth_on_surface(&mut nodes, &tets, &slide.movable(&surface), 100, &slide);
            nodes[s as usize]
        };
        assert!(place(1e-2)[0] > place(1.0)[0]);
    }

    #[test]
    fn without_a_deviation_a_surface_node_stays() {
        let (old, tets, s) = pushed_surface_node();
        let surface = [(s, [false; 3])];
        let slide = SurfaceSlide::new(&old, &tets, &surface, 0.0);
        assert!(slide.movable(&surface).is_empty());
        let mut nodes = old.clone();
        smooth_on_surface(&mut nodes, &tets, &slide.movable(&surface), 100, &slide);
        assert_eq!(nodes, old);
    }

    #[test]
    fn a_node_on_a_symmetry_plane_slides_along_its_seam() {
        // The same surface cut by the plane y = 0: the node and the ring nodes at x = +-1 lie
        // on it, the node held in y. It slides along the seam, in the plane bit for bit.
        let (old, tets, s) = pushed_surface_node();
        let keep: Vec<[u32; 4]> = tets
            .into_iter()
            .filter(|t| t.iter().all(|&n| old[n as usize][1] >= 0.0))
            .collect();
        assert_eq!(keep.len(), 2);
        let surface = [(s, [false, true, false])];
        let slide = SurfaceSlide::new(&old, &keep, &surface, 1.0);
        let mut nodes = old.clone();
        smooth_on_surface(&mut nodes, &keep, &slide.movable(&surface), 100, &slide);
        let p = nodes[s as usize];
        assert!(p[0] < 0.7 && p[1] == 0.0, "{p:?}");
        // On the old seam, the chord from the node's old place to the ring node at x = -1.
        let (a, b) = (old[s as usize], old[3]);
        let t = (p - a).dot(&(b - a)) / (b - a).norm_squared();
        assert!((a + t * (b - a) - p).norm() < 1e-15 && (0.0..=1.0).contains(&t));
    }
}
