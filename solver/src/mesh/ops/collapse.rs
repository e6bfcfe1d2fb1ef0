//! Edge collapse, the remesher's topological repair (step 4 of the method in `mesher/`).
//!
//! Smoothing moves nodes but keeps the connectivity, and refinement of a crushed element gives
//! crushed children: an element with a short edge between two nodes that cannot move apart
//! (every placement that lengthens it flattens a neighbour) stays bad. Collapsing the edge
//! merges its two ends: the elements around the edge (its shell) disappear and the other
//! elements of the removed node take the kept one in its place (Freitag & Ollivier-Gooch 1997,
//! "Tetrahedral mesh improvement using swapping and smoothing", IJNME 40; Klingner & Shewchuk
//! 2007, "Aggressive tetrahedral mesh improvement", edge contraction).
//!
//! A collapse is taken only if
//! * the removed node is inside the region, or slides on the outer boundary within symmetry
//!   planes and merges into a node on the same planes, so the boundary keeps its shape; or it
//!   lies on a curved part of the outer boundary and merges along a boundary edge into a node on
//!   the same axis planes, where every boundary face that takes it in its place passes within a
//!   set distance of it (`surface_deviation`) and turns by less than [`SURFACE_TURN_COS`]: the
//!   surface moves by at most that distance, as the thesis's FEMAP remeshed the deformed
//!   boundary itself (9.3). A node of the interface never goes, so the interface keeps its shape;
//! * the link condition holds (Dey et al. 1999, "Topology preserving edge contraction"): the
//!   vertices and edges that the links of both ends share are exactly those of the edge's link,
//!   so the mesh stays a manifold without duplicated or folded elements; the region's boundary
//!   faces join the links as virtual elements with a vertex at infinity, which keeps the
//!   boundary a manifold too;
//! * every changed element keeps a positive volume and the worst quality of the removed node's
//!   elements rises. The worst element around a node never gets worse: the repair terminates.

use nalgebra::Vector3;

use std::collections::{BTreeMap, BTreeSet, HashSet};

use super::quality::shape_quality;
use crate::kinematics::signed_volume;
use crate::mesh::{face_key, TET_FACES};

/// The smallest cosine of the angle a boundary face may turn by in a surface collapse: about
/// 30 degrees. The face stays on the side of the surface it faced; a collapse along a crease
/// (where the faces turn more) would fold it.
pub(crate) const SURFACE_TURN_COS: f64 = 0.85;

/// How an edge collapse may remove a node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Removable {
    /// Never: a node of the interface with the untouched mesh, or a corner.
    Never,
    /// An inner node (no axis held), or one sliding on the outer boundary within symmetry
    /// planes (the axes they fix held): it merges only into a node on the same planes.
    Sliding([bool; 3]),
    /// A node on a curved part of the outer boundary, with the axes its flat boundary faces fix
    /// (on a symmetry plane as well): it merges along a boundary edge into a node on the same
    /// planes, where the surface moves by at most the collapse's `surface_deviation`.
    Surface([bool; 3]),
}

/// What [`collapse_short_edges`] did.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Collapses {
    /// The elements, `None` where removed (the removed nodes no longer appear in the others).
    pub tets: Vec<Option<[u32; 4]>>,
    /// Number of collapses.
    pub count: usize,
    /// Number of them that removed a node of a curved boundary.
    pub surface: usize,
    /// The region's volume after less before (m^3): zero to round-off unless a surface
    /// collapse moved the boundary.
    pub volume_change: f64,
    /// The region's outer boundary area after less before (m^2), likewise.
    pub area_change: f64,
}

/// Area of the triangle `[a, b, c]` and its unit normal.
fn triangle(nodes: &[Vector3<f64>], [a, b, c]: [u32; 3]) -> (f64, Vector3<f64>) {
    let [a, b, c] = [a, b, c].map(|n| nodes[n as usize]);
    let n = (b - a).cross(&(c - a));
    let norm = n.norm();
    (0.5 * norm, n / norm)
}

/// The six edges of a tetrahedron as local node pairs.
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The edge, with its ends in ascending order.
fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The vertices and edges of the link of node `v` over the elements `around` (those holding
/// it): the other nodes of those elements, and the edges of the faces opposite `v`.
fn link(
    tets: &[Option<[u32; 4]>],
    around: &[usize],
    v: u32,
) -> (BTreeSet<u32>, BTreeSet<(u32, u32)>) {
    let mut vertices = BTreeSet::new();
    let mut edges = BTreeSet::new();
    for &t in around {
        let tet = tets[t].expect("incident lists hold live elements");
        let others: Vec<u32> = tet.iter().copied().filter(|&n| n != v).collect();
        vertices.extend(others.iter().copied());
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            edges.insert(edge(others[i], others[j]));
        }
    }
    (vertices, edges)
}

/// The state of the collapse pass: the elements (a removed one is `None`) and, per node, the
/// elements that hold it.
struct Collapser<'a> {
    nodes: &'a [Vector3<f64>],
    /// The elements, then the virtual ones: each boundary face of the region with the vertex
    /// `omega` (the point at infinity that closes the region's link, Dey et al. 1999).
    tets: Vec<Option<[u32; 4]>>,
    incident: Vec<Vec<usize>>,
    omega: u32,
    /// The faces of the elements outside that touch these.
    neighbour_faces: HashSet<[u32; 3]>,
}

impl Collapser<'_> {
    /// The shape quality of an element; `None` for a virtual one (no geometry).
    fn quality(&self, t: &[u32; 4]) -> Option<f64> {
        (!t.contains(&self.omega)).then(|| shape_quality(&t.map(|n| self.nodes[n as usize])))
    }

    /// The face of a virtual element (its three real nodes, in its order).
    fn face_of(&self, t: &[u32; 4]) -> [u32; 3] {
        let mut face = [0; 3];
        let mut k = 0;
        for &n in t {
            if n != self.omega {
                face[k] = n;
                k += 1;
            }
        }
        face
    }

    /// Merges node `gone` into node `keep` if the conditions of the module hold; the change of
    /// the region's volume and boundary area if it did. The changed elements' quality must pass
    /// the worst before, or (`floor`, for a coarsening collapse) reach `floor`. `surface` is
    /// the largest distance the boundary may move where `gone` lies on a curved boundary
    /// (`None` otherwise): the edge must then be a boundary edge.
    fn try_collapse(
        &mut self,
        keep: u32,
        gone: u32,
        floor: f64,
        surface: Option<f64>,
    ) -> Option<(f64, f64)> {
        let around: Vec<usize> = self.incident[gone as usize].clone();
        let live = |t: usize| self.tets[t].expect("incident lists hold live elements");
        let (shell, moved): (Vec<usize>, Vec<usize>) =
            around.iter().partition(|&&t| live(t).contains(&keep));
        if shell.is_empty() {
            return None;
        }
        let xg = self.nodes[gone as usize];
        let xk = self.nodes[keep as usize];
        if let Some(deviation) = surface {
            if !shell.iter().any(|&t| live(t).contains(&self.omega)) {
                return None;
            }
            for &t in &moved {
                let old = live(t);
                if !old.contains(&self.omega) {
                    continue;
                }
                let new = old.map(|n| if n == gone { keep } else { n });
                let (_, n_old) = triangle(self.nodes, self.face_of(&old));
                let (_, n_new) = triangle(self.nodes, self.face_of(&new));
                if !(n_new.dot(&(xg - xk)).abs() <= deviation
                    && n_new.dot(&n_old) >= SURFACE_TURN_COS)
                {
                    return None;
                }
            }
        }
        let before = around
            .iter()
            .filter_map(|&t| self.quality(&live(t)))
            .fold(f64::INFINITY, f64::min);
        let shell_faces: HashSet<[u32; 3]> = shell
            .iter()
            .flat_map(|&t| {
                let tet = live(t);
                TET_FACES.map(|f| face_key(f.map(|i| tet[i])))
            })
            .collect();
        let mut changed = Vec::with_capacity(moved.len());
        for &t in &moved {
            let new = live(t).map(|n| if n == gone { keep } else { n });
            if let Some(q) = self.quality(&new) {
                if !(q > before || q >= floor) {
                    return None;
                }
            }
            // Nor may it duplicate an element (real, or a boundary face as a virtual one): a
            // loose element, all four faces on the boundary, would fold onto its own face.
            let mut sorted = new;
            sorted.sort_unstable();
            if self.incident[keep as usize].iter().any(|&o| {
                let mut other = live(o);
                other.sort_unstable();
                other == sorted
            }) {
                return None;
            }
            // Its faces through `keep` are new (the others it had already). Such a face may be
            // a neighbour's only where a shell element held it (the element takes the shell's
            // place on the interface, as every collapse zips the shell's faces).
            if self.quality(&new).is_some()
                && TET_FACES.iter().any(|f| {
                    let face = face_key(f.map(|i| new[i]));
                    face.contains(&keep)
                        && self.neighbour_faces.contains(&face)
                        && !shell_faces.contains(&face)
                })
            {
                return None;
            }
            changed.push((t, new));
        }
        let (keep_vertices, keep_edges) = link(&self.tets, &self.incident[keep as usize], keep);
        let (gone_vertices, gone_edges) = link(&self.tets, &around, gone);
        let mut edge_vertices = BTreeSet::new();
        let mut edge_edges = BTreeSet::new();
        for &t in &shell {
            let others: Vec<u32> = live(t)
                .iter()
                .copied()
                .filter(|&n| n != keep && n != gone)
                .collect();
            edge_vertices.extend(others.iter().copied());
            edge_edges.insert(edge(others[0], others[1]));
        }
        let mut shared_vertices: BTreeSet<u32> = keep_vertices
            .intersection(&gone_vertices)
            .copied()
            .collect();
        shared_vertices.remove(&keep);
        shared_vertices.remove(&gone);
        let shared_edges: BTreeSet<(u32, u32)> =
            keep_edges.intersection(&gone_edges).copied().collect();
        if shared_vertices != edge_vertices || shared_edges != edge_edges {
            return None;
        }
        // The volume and boundary area the collapse changes: the shell goes, the moved
        // elements and faces change shape.
        let volume = |t: &[u32; 4]| signed_volume(&t.map(|n| self.nodes[n as usize]));
        let (mut dv, mut da) = (0.0, 0.0);
        for &t in &shell {
            let tet = live(t);
            if tet.contains(&self.omega) {
                da -= triangle(self.nodes, self.face_of(&tet)).0;
            } else {
                dv -= volume(&tet);
            }
        }
        for &(t, new) in &changed {
            let old = live(t);
            if old.contains(&self.omega) {
                da += triangle(self.nodes, self.face_of(&new)).0
                    - triangle(self.nodes, self.face_of(&old)).0;
            } else {
                dv += volume(&new) - volume(&old);
            }
        }
        let removed: Vec<(usize, [u32; 4])> = shell.iter().map(|&t| (t, live(t))).collect();
        for (t, tet) in removed {
            for n in tet {
                self.incident[n as usize].retain(|&s| s != t);
            }
            self.tets[t] = None;
        }
        for (t, new) in changed {
            self.tets[t] = Some(new);
            self.incident[keep as usize].push(t);
        }
        self.incident[keep as usize].sort_unstable();
        self.incident[gone as usize].clear();
        Some((dv, da))
    }
}

/// The bounds of [`collapse_short_edges`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct CollapseLimits {
    /// Elements below this quality ([`shape_quality`]) try their edges.
    pub target: f64,
    /// Edges shorter than this (m) may coarsen.
    pub min_edge: f64,
    /// How far a surface collapse may move the boundary (m).
    pub surface_deviation: f64,
    /// The most passes over the elements.
    pub passes: usize,
}

/// Collapses short edges of the elements `tets` over the coordinates `nodes` (module's method):
/// every element whose quality ([`shape_quality`]) is below `limits.target`, or with an edge
/// shorter than `limits.min_edge`, tries its edges from the shortest, in element order, in up to
/// `limits.passes` passes until none collapses. `removable[n]` says whether and how node `n` may
/// go; a node of a curved boundary goes only where the boundary moves by at most
/// `limits.surface_deviation` (m). No changed element may take a face of the `neighbours` (the
/// elements outside `tets` that touch them): across a flat pit of the surface, a collapse onto
/// a node of the interface would glue the region onto a neighbour's boundary face, which the
/// link condition over `tets` alone does not see. Deterministic.
pub(crate) fn collapse_short_edges(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    neighbours: &[[u32; 4]],
    removable: &[Removable],
    limits: CollapseLimits,
) -> Collapses {
    let CollapseLimits {
        target,
        min_edge,
        surface_deviation,
        passes,
    } = limits;
    let neighbour_faces: HashSet<[u32; 3]> = neighbours
        .iter()
        .flat_map(|t| TET_FACES.map(|f| face_key(f.map(|i| t[i]))))
        .collect();
    let omega = nodes.len() as u32;
    let mut all: Vec<Option<[u32; 4]>> = tets.iter().copied().map(Some).collect();
    let mut faces: BTreeMap<[u32; 3], (u32, [u32; 3])> = BTreeMap::new();
    for tet in tets {
        for f in TET_FACES {
            let face = f.map(|i| tet[i]);
            faces.entry(face_key(face)).or_insert((0, face)).0 += 1;
        }
    }
    all.extend(
        faces
            .values()
            .filter(|(c, _)| *c == 1)
            .map(|(_, [a, b, c])| Some([*a, *b, *c, omega])),
    );
    let mut incident = vec![Vec::new(); nodes.len() + 1];
    for (t, tet) in all.iter().enumerate() {
        for &n in tet.iter().flatten() {
            incident[n as usize].push(t);
        }
    }
    let tolerance = super::smoothing::plane_tolerance(nodes);
    let same_planes = |axes: [bool; 3], keep: u32, gone: u32| {
        (0..3).all(|k| {
            !axes[k] || (nodes[keep as usize][k] - nodes[gone as usize][k]).abs() <= tolerance
        })
    };
    // Whether `gone` may merge into `keep`, and the surface deviation allowed if on a surface.
    let may_merge = |keep: u32, gone: u32| match removable[gone as usize] {
        Removable::Never => None,
        Removable::Sliding(axes) => same_planes(axes, keep, gone).then_some(None),
        Removable::Surface(axes) => (surface_deviation > 0.0 && same_planes(axes, keep, gone))
            .then_some(Some(surface_deviation)),
    };
    let mut c = Collapser {
        nodes,
        tets: all,
        incident,
        omega,
        neighbour_faces,
    };
    let mut out = Collapses {
        tets: Vec::new(),
        count: 0,
        surface: 0,
        volume_change: 0.0,
        area_change: 0.0,
    };
    for _ in 0..passes {
        let before = out.count;
        for t in 0..tets.len() {
            let Some(tet) = c.tets[t] else { continue };
            let mut edges: Vec<(f64, u32, u32)> = TET_EDGES
                .iter()
                .map(|&[i, j]| {
                    let (a, b) = (tet[i], tet[j]);
                    ((nodes[a as usize] - nodes[b as usize]).norm(), a, b)
                })
                .collect();
            edges.sort_by(|p, q| p.0.total_cmp(&q.0).then((p.1, p.2).cmp(&(q.1, q.2))));
            let poor = c.quality(&tet).is_some_and(|q| q < target);
            let small = edges[0].0 < min_edge;
            if !poor && !small {
                continue;
            }
            'edges: for (length, a, b) in edges {
                // A short edge may coarsen down to the target quality; a poor element's other
                // edges only where quality rises.
                let floor = if length < min_edge {
                    target
                } else {
                    f64::INFINITY
                };
                for (keep, gone) in [(a, b), (b, a)] {
                    let Some(surface) = may_merge(keep, gone) else {
                        continue;
                    };
                    if let Some((dv, da)) = c.try_collapse(keep, gone, floor, surface) {
                        out.count += 1;
                        out.surface += usize::from(surface.is_some());
                        out.volume_change += dv;
                        out.area_change += da;
                        break 'edges;
                    }
                }
            }
        }
        if out.count == before {
            break;
        }
    }
    c.tets.truncate(tets.len());
    out.tets = c.tets;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> CollapseLimits {
        CollapseLimits {
            target: 0.25,
            min_edge: 0.1,
            surface_deviation: 1.0,
            passes: 5,
        }
    }

    /// `t` positively oriented over `x`.
    fn oriented(x: &[Vector3<f64>], mut t: [u32; 4]) -> [u32; 4] {
        if signed_volume(&t.map(|n| x[n as usize])) < 0.0 {
            t.swap(2, 3);
        }
        t
    }

    #[test]
    fn a_loose_element_does_not_fold_onto_its_own_face() {
        // One element alone (all four faces on the boundary, as erosion can leave one), its
        // edge 0-1 far below the shortest edge. Merging 1 into 0 would leave its face 0 2 3
        // twice on the boundary and no element: the area bookkeeping then misses that face.
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.02, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let tets = vec![oriented(&x, [0, 1, 2, 3])];
        let mut removable = vec![Removable::Never; 4];
        removable[1] = Removable::Surface([false; 3]);
        let out = collapse_short_edges(&x, &tets, &[], &removable, limits());
        assert_eq!(out.count, 0);
        assert_eq!(out.tets, vec![Some(tets[0])]);
    }

    #[test]
    fn a_collapse_does_not_glue_the_region_onto_a_neighbours_face() {
        // Node g lies just above k, so the region's face g a b and the neighbour's face k a b
        // (outside the region, below the plane z = 0) enclose a flat pit g k a b. Merging g into
        // k passes the link condition over the region alone, and would glue the region's
        // element g a b c onto the neighbour as k a b c.
        let (k, a, b, c, p, g) = (0, 1, 2, 3, 4, 5);
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.3, 0.3, 1.0),
            Vector3::new(0.3, 0.3, -1.0),
            Vector3::new(0.01, 0.01, 0.005),
        ];
        let region = vec![oriented(&x, [g, k, a, c]), oriented(&x, [g, a, b, c])];
        let neighbour = oriented(&x, [k, a, b, p]);
        let mut removable = vec![Removable::Never; x.len()];
        removable[g as usize] = Removable::Surface([false; 3]);
        let out = collapse_short_edges(&x, &region, &[neighbour], &removable, limits());
        assert_eq!(out.count, 0);
        // Without the neighbour the same collapse is taken: the test sees the case it guards.
        let out = collapse_short_edges(&x, &region, &[], &removable, limits());
        assert_eq!(out.count, 1);
    }
}
