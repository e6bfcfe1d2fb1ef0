//! Face and edge flips, the remesher's sliver repair (step 5 of the method in `mesher/`).
//!
//! A sliver has four nodes nearly in one plane with edges alike: no short edge to collapse, and
//! smoothing cannot lift a node whose neighbours hold it in the plane (next to a curved
//! boundary whose nodes do not move). Reconnecting its nodes can: the 2-3 flip replaces the two
//! elements of an inner face `(a, b, c)` with apexes `d`, `e` by the three around the new edge
//! `(d, e)`; the 3-2 flip replaces the three elements around an inner edge by the two on the
//! triangle of their other nodes (Freitag & Ollivier-Gooch 1997; Klingner & Shewchuk 2007). A
//! flip keeps the region's volume and boundary exactly (the same union of elements), and is
//! taken only where every new element is positive and the worst quality of the elements it
//! replaces rises.

use nalgebra::Vector3;

use super::quality::shape_quality;
use crate::kinematics::signed_volume;

/// Relative difference of volumes within which new elements tile the old ones (round-off of
/// the sums): an invalid flip overlaps, and its volumes add to more.
const TILING_TOLERANCE: f64 = 1e-12;

/// The elements and, per node, the live elements holding it.
struct Flipper<'a> {
    nodes: &'a [Vector3<f64>],
    tets: Vec<Option<[u32; 4]>>,
    incident: Vec<Vec<usize>>,
    /// Elements that must stay as they are (copies of old ones).
    fixed: Vec<bool>,
}

impl Flipper<'_> {
    fn quality(&self, t: &[u32; 4]) -> f64 {
        shape_quality(&t.map(|n| self.nodes[n as usize]))
    }

    /// The element `t` positively oriented, or `None` where it has no volume.
    fn oriented(&self, mut t: [u32; 4]) -> Option<[u32; 4]> {
        let v = signed_volume(&t.map(|n| self.nodes[n as usize]));
        if v < 0.0 {
            t.swap(2, 3);
        }
        (v != 0.0).then_some(t)
    }

    /// The live, changeable elements holding all of `nodes`.
    fn holding(&self, nodes: &[u32]) -> Vec<usize> {
        self.incident[nodes[0] as usize]
            .iter()
            .copied()
            .filter(|&t| {
                let tet = self.tets[t].expect("incident lists hold live elements");
                nodes.iter().all(|n| tet.contains(n))
            })
            .collect()
    }

    fn volume(&self, t: &[u32; 4]) -> f64 {
        signed_volume(&t.map(|n| self.nodes[n as usize]))
    }

    /// Replaces the elements `old` by `new` (in any orientation) if the new ones tile the same
    /// set (the sum of their volumes is the old one, so none overlaps: the flip's convexity
    /// condition) and their worst quality passes the old ones'; whether it did.
    fn replace(&mut self, old: &[usize], new: &[[u32; 4]]) -> bool {
        if old.iter().any(|&t| self.fixed[t]) {
            return false;
        }
        let old_tets: Vec<[u32; 4]> = old.iter().map(|&t| self.tets[t].expect("live")).collect();
        let before = old_tets
            .iter()
            .map(|t| self.quality(t))
            .fold(f64::INFINITY, f64::min);
        let old_volume: f64 = old_tets.iter().map(|t| self.volume(t)).sum();
        let new_volume: f64 = new.iter().map(|t| self.volume(t).abs()).sum();
        if !((new_volume - old_volume).abs() <= TILING_TOLERANCE * old_volume) {
            return false;
        }
        let mut oriented = Vec::with_capacity(new.len());
        for t in new {
            match self.oriented(*t) {
                Some(t) if self.quality(&t) > before => oriented.push(t),
                _ => return false,
            }
        }
        for &t in old {
            for n in self.tets[t].expect("live") {
                self.incident[n as usize].retain(|&s| s != t);
            }
            self.tets[t] = None;
        }
        for t in oriented {
            let id = self.tets.len();
            self.tets.push(Some(t));
            self.fixed.push(false);
            for n in t {
                self.incident[n as usize].push(id);
            }
        }
        true
    }

    /// The 2-3 flip of the face of element `t` opposite its local node `k`.
    fn flip_face(&mut self, t: usize, k: usize) -> bool {
        let tet = self.tets[t].expect("live");
        let face: Vec<u32> = (0..4).filter(|&i| i != k).map(|i| tet[i]).collect();
        let other: Vec<usize> = self
            .holding(&face)
            .into_iter()
            .filter(|&s| s != t)
            .collect();
        let [s] = other[..] else { return false };
        let d = tet[k];
        let e = self.tets[s]
            .expect("live")
            .into_iter()
            .find(|n| !face.contains(n))
            .expect("a tetrahedron has a node off its face");
        // The new edge (d, e) must not be one already (the mesh would fold over it).
        if !self.holding(&[d, e]).is_empty() {
            return false;
        }
        let (a, b, c) = (face[0], face[1], face[2]);
        self.replace(&[t, s], &[[a, b, d, e], [b, c, d, e], [c, a, d, e]])
    }

    /// The 3-2 flip of the edge `(a, b)` if three elements hold it and their other nodes close a
    /// ring around it (an inner edge).
    fn flip_edge(&mut self, a: u32, b: u32) -> bool {
        let around = self.holding(&[a, b]);
        if around.len() != 3 {
            return false;
        }
        let mut ring: Vec<u32> = Vec::with_capacity(6);
        for &t in &around {
            ring.extend(
                self.tets[t]
                    .expect("live")
                    .into_iter()
                    .filter(|&n| n != a && n != b),
            );
        }
        ring.sort_unstable();
        // An inner edge: each of the three ring nodes is shared by two of the elements.
        let closed = ring.len() == 6 && (0..3).all(|i| ring[2 * i] == ring[2 * i + 1]);
        if !closed || ring[1] == ring[3] || ring[3] == ring[5] {
            return false;
        }
        let (p, q, r) = (ring[0], ring[2], ring[4]);
        // The new face (p, q, r) must not be one already.
        if !self.holding(&[p, q, r]).is_empty() {
            return false;
        }
        self.replace(&around, &[[p, q, r, a], [p, q, r, b]])
    }
}

/// Flips faces and edges of the elements `tets` over `nodes` (module's method): every element
/// whose quality ([`shape_quality`]) is below `target` tries the 2-3 flip of each face and the
/// 3-2 flip of each edge, in element order, in up to `passes` passes until none flips.
/// Elements flagged `fixed` (copies of old ones) are never changed; nor are the `neighbours`
/// (the elements outside that touch them), whose edges and faces a flip may not duplicate.
/// Returns the elements (live ones in order, `None` where replaced, the new ones after; the
/// neighbours left out) and the number of flips. Deterministic.
pub(crate) fn flip_slivers(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    fixed: &[bool],
    neighbours: &[[u32; 4]],
    target: f64,
    passes: usize,
) -> (Vec<Option<[u32; 4]>>, usize) {
    // The neighbours go after the elements, fixed: never changed, but their edges and faces
    // count as existing ones (a region element's faces may fold onto a neighbour's boundary
    // face across a flat pit of the surface, which the region alone does not see).
    let all: Vec<[u32; 4]> = tets.iter().chain(neighbours).copied().collect();
    let mut incident = vec![Vec::new(); nodes.len()];
    for (t, tet) in all.iter().enumerate() {
        for &n in tet {
            incident[n as usize].push(t);
        }
    }
    let mut f = Flipper {
        nodes,
        tets: all.iter().copied().map(Some).collect(),
        incident,
        fixed: fixed
            .iter()
            .copied()
            .chain(neighbours.iter().map(|_| true))
            .collect(),
    };
    let mut count = 0;
    for _ in 0..passes {
        let before = count;
        let mut t = 0;
        // Each flip raises the worst element it replaces; the bound only guards the pass.
        while t < f.tets.len() && count - before <= tets.len() {
            if let Some(tet) = f.tets[t] {
                if !f.fixed[t] && f.quality(&tet) < target {
                    let flipped = (0..4).any(|k| f.tets[t].is_some() && f.flip_face(t, k))
                        || [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
                            .iter()
                            .any(|&[i, j]| f.tets[t].is_some() && f.flip_edge(tet[i], tet[j]));
                    if flipped {
                        count += 1;
                    }
                }
            }
            t += 1;
        }
        if count == before {
            break;
        }
    }
    let mut out = f.tets;
    out.drain(tets.len()..tets.len() + neighbours.len());
    (out, count)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring of three nodes (unit equilateral triangle about the z axis at z = 0) and the
    /// nodes 3 = (0, 0, h), 4 = (0, 0, -h).
    fn nodes(h: f64) -> Vec<Vector3<f64>> {
        let ring = (0..3).map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 3.0;
            Vector3::new(a.cos(), a.sin(), 0.0)
        });
        ring.chain([Vector3::new(0.0, 0.0, h), Vector3::new(0.0, 0.0, -h)])
            .collect()
    }

    fn worst(x: &[Vector3<f64>], tets: &[[u32; 4]]) -> f64 {
        tets.iter()
            .map(|t| shape_quality(&t.map(|n| x[n as usize])))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn two_flat_caps_on_a_triangle_become_three_elements_round_an_edge() {
        // Two caps of height 0.1 on the ring's triangle (altitude ratio 14): the 2-3 flip
        // replaces their common face by the edge (3, 4): three wedges round it, collapse ratio
        // 8.7 and altitude ratio about 7 (their smallest altitude is twice the caps'). The
        // quality weighs the altitude because the stable step does: the 3-2 flip back, which
        // trades the short edge for the caps' altitude, is refused.
        let x = nodes(0.1);
        let positive = |mut t: [u32; 4]| {
            if signed_volume(&t.map(|n| x[n as usize])) < 0.0 {
                t.swap(2, 3);
            }
            t
        };
        let caps = [[0, 1, 2, 3], [0, 1, 2, 4]].map(positive);
        let before = worst(&x, &caps);
        let (after, flips) = flip_slivers(&x, &caps, &[false; 2], &[], 0.25, 5);
        let live: Vec<[u32; 4]> = after.into_iter().flatten().collect();
        assert_eq!((flips, live.len()), (1, 3), "{live:?}");
        assert!(live.iter().all(|t| t.contains(&3) && t.contains(&4)));
        assert!(
            worst(&x, &live) > before,
            "{} <= {before}",
            worst(&x, &live)
        );
        let volume = |t: &[[u32; 4]]| -> f64 {
            t.iter()
                .map(|t| signed_volume(&t.map(|n| x[n as usize])))
                .sum()
        };
        assert!(live
            .iter()
            .all(|t| signed_volume(&t.map(|n| x[n as usize])) > 0.0));
        assert!((volume(&live) - volume(&caps)).abs() < 1e-15);
        // The wedges are better than the 3-2 flip back: nothing flips.
        let (again, none) = flip_slivers(&x, &live, &[false; 3], &[], 0.3, 5);
        assert_eq!(none, 0);
        assert_eq!(again.into_iter().flatten().collect::<Vec<_>>(), live);
        // A copied element is never changed.
        let (kept, zero) = flip_slivers(&x, &caps, &[false, true], &[], 0.25, 5);
        assert_eq!(zero, 0);
        assert_eq!(kept.into_iter().flatten().count(), 2);
        // Nor is a neighbour, and no flip makes one of its edges again: with an element outside
        // holding the edge (3, 4) (as across a flat pit of a surface), the caps stay, and the
        // output holds the region's elements only.
        let mut x = x;
        x.push(Vector3::new(-2.0, 0.5, 0.0));
        let (kept, zero) = flip_slivers(&x, &caps, &[false; 2], &[[3, 4, 5, 0]], 0.25, 5);
        assert_eq!(zero, 0);
        assert_eq!(kept, caps.map(Some).to_vec());
    }
}
