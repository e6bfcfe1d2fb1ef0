//! Edge collapse, the remesher's topological repair (step 4 of the method in `mesher.rs`).
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
//!   planes and merges into a node on the same planes (never a node of the interface or of a
//!   curved boundary), so the boundary and the interface keep their shape;
//! * the link condition holds (Dey et al. 1999, "Topology preserving edge contraction"): the
//!   vertices and edges that the links of both ends share are exactly those of the edge's link,
//!   so the mesh stays a manifold without duplicated or folded elements; the region's boundary
//!   faces join the links as virtual elements with a vertex at infinity, which keeps the
//!   boundary a manifold too;
//! * every changed element keeps a positive volume and the worst quality of the removed node's
//!   elements rises. The worst element around a node never gets worse: the repair terminates.

use nalgebra::Vector3;

use std::collections::{BTreeMap, BTreeSet};

use super::mesher::shape_quality;
use crate::mesh::{face_key, TET_FACES};

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
}

impl Collapser<'_> {
    /// The shape quality of an element; `None` for a virtual one (no geometry).
    fn quality(&self, t: &[u32; 4]) -> Option<f64> {
        (!t.contains(&self.omega)).then(|| shape_quality(&t.map(|n| self.nodes[n as usize])))
    }

    /// Merges node `gone` into node `keep` if the conditions of the module hold; whether it did.
    /// The changed elements' quality must pass the worst before, or (`floor`, for a coarsening
    /// collapse) reach `floor`.
    fn try_collapse(&mut self, keep: u32, gone: u32, floor: f64) -> bool {
        let around: Vec<usize> = self.incident[gone as usize].clone();
        let live = |t: usize| self.tets[t].expect("incident lists hold live elements");
        let (shell, moved): (Vec<usize>, Vec<usize>) =
            around.iter().partition(|&&t| live(t).contains(&keep));
        if shell.is_empty() {
            return false;
        }
        let before = around
            .iter()
            .filter_map(|&t| self.quality(&live(t)))
            .fold(f64::INFINITY, f64::min);
        let mut changed = Vec::with_capacity(moved.len());
        for &t in &moved {
            let new = live(t).map(|n| if n == gone { keep } else { n });
            if let Some(q) = self.quality(&new) {
                if !(q > before || q >= floor) {
                    return false;
                }
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
            return false;
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
        true
    }
}

/// Collapses short edges of the elements `tets` over the coordinates `nodes` (module's method):
/// every element whose quality ([`shape_quality`]) is below `target`, or with an edge shorter
/// than `min_edge`, tries its edges from the shortest, in element order, in up to `passes` passes until none collapses. An end `n` may
/// be removed where `held[n]` is given: the axes along which it may not move (none for an inner
/// node; those of its symmetry planes for a node sliding on the boundary, which then merges only
/// into a node on the same planes, so the boundary keeps its shape). Returns the elements,
/// `None` where removed (the removed nodes no longer appear in the others), and the number of
/// collapses. Deterministic.
pub(super) fn collapse_short_edges(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    held: &[Option<[bool; 3]>],
    target: f64,
    min_edge: f64,
    passes: usize,
) -> (Vec<Option<[u32; 4]>>, usize) {
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
    let may_merge = |keep: u32, gone: u32| match held[gone as usize] {
        None => false,
        Some(axes) => (0..3).all(|k| {
            !axes[k] || (nodes[keep as usize][k] - nodes[gone as usize][k]).abs() <= tolerance
        }),
    };
    let mut c = Collapser {
        nodes,
        tets: all,
        incident,
        omega,
    };
    let mut count = 0;
    for _ in 0..passes {
        let before = count;
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
                    if may_merge(keep, gone) && c.try_collapse(keep, gone, floor) {
                        count += 1;
                        break 'edges;
                    }
                }
            }
        }
        if count == before {
            break;
        }
    }
    c.tets.truncate(tets.len());
    (c.tets, count)
}
