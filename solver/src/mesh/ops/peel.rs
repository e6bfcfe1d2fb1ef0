//! Peeling of collapsed boundary elements, the remesher's last repair (step 6 of the method in
//! `mesher/`), and erosion.
//!
//! An element with all four nodes on a curved part of the outer boundary (the cavity around a
//! penetrator's nose) cannot be reshaped: none of its nodes moves (a curved surface would lose
//! its shape), it may have no inner face to flip, and a collapse would move the surface. Such an
//! element, left collapsed with a face on the surface, is removed ("peeled", as boundary slivers
//! are in Delaunay refinement: Cheng, Dey & Shewchuk 2012, *Delaunay Mesh Generation*, 10.4)
//! where the boundary stays a manifold: around each of its nodes the outer faces after the
//! removal make one fan, or none ([`one_fan`]). Its inner faces become the boundary. The surface
//! moves inward by at most the element's height, away from whatever presses on it (material is
//! removed, none added), and the body keeps its mass: the transfer gives the region's new
//! elements exactly the mass of the old ones they replace (`apply/`).
//!
//! With erosion, a collapsed element goes wherever it is, inside the body (a void) or on its
//! surface, with no condition on the surface's shape, as explicit codes erode elements
//! (LS-DYNA's `*MAT_ADD_EROSION` removes an element whatever its neighbours): two parts of the
//! surface may then meet at a node or along an edge, and a piece of the body may hang on the
//! rest by a node. The manifold condition was too strict for the cavity around a nose: its
//! slivers are membranes between two parts of the cavity, 0.3-2 um thick, whose fourth node or
//! one edge lies on the other part, and the nail run stalled on them (at 41.1 us without
//! erosion of such membranes, with the stable step at 3.5e-11 s).

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use nalgebra::Vector3;

use super::fragments::{loose_fragments, shares_a_node};
use super::quality::shape_quality;
use crate::mesh::{face_key, TET_FACES};

/// The quality ([`shape_quality`]) below which a boundary element is peeled: a collapse ratio or
/// inverse mean ratio of 10, the remeshing limit of the thesis (Box 8.1).
pub(crate) const PEEL_QUALITY: f64 = 0.1;

/// A peeled element, its four corners where it was removed, and per local face (opposite local
/// node `k`) whether it was on the outer boundary then (the other faces became boundary). The
/// corners are kept as coordinates because a peeled element may take its last node with it.
pub type PeeledElement = ([Vector3<f64>; 4], [bool; 4]);

/// The outer faces of the elements alive at each node, kept up to date as they are peeled.
#[derive(Default)]
struct Boundary {
    faces_at_node: HashMap<u32, BTreeSet<[u32; 3]>>,
}

impl Boundary {
    /// Adds `face` (a sorted key) to the outer faces, or removes it.
    fn set(&mut self, face: [u32; 3], outer: bool) {
        for n in face {
            let faces = self.faces_at_node.entry(n).or_default();
            if outer {
                faces.insert(face);
            } else {
                faces.remove(&face);
            }
        }
    }
}

/// Whether the faces `faces` around node `n` make one fan: each edge from `n` in exactly two
/// of them, all joined through those edges (a disc about `n` on the surface); true for none.
fn one_fan(n: u32, faces: &[[u32; 3]]) -> bool {
    if faces.is_empty() {
        return true;
    }
    let others = |f: &[u32; 3]| -> Vec<u32> { f.iter().copied().filter(|&m| m != n).collect() };
    let mut uses: BTreeMap<u32, usize> = BTreeMap::new();
    for f in faces {
        for m in others(f) {
            *uses.entry(m).or_default() += 1;
        }
    }
    if uses.values().any(|&c| c != 2) {
        return false;
    }
    // Walk the fan from the first face; it must reach every face.
    let mut seen = vec![false; faces.len()];
    let mut stack = vec![0];
    seen[0] = true;
    while let Some(k) = stack.pop() {
        for m in others(&faces[k]) {
            for (j, g) in faces.iter().enumerate() {
                if !seen[j] && g.contains(&m) {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
    }
    seen.iter().all(|&s| s)
}

/// The faces `around` node `n` (the outer faces holding it) once `tet` is removed: its faces
/// `outer` (opposite local node `k`) leave the boundary, its other faces join it.
fn faces_after_removal(
    n: u32,
    tet: &[u32; 4],
    outer: &[bool; 4],
    boundary: &Boundary,
) -> Vec<[u32; 3]> {
    let mut around: BTreeSet<[u32; 3]> =
        boundary.faces_at_node.get(&n).cloned().unwrap_or_default();
    for (f, &was_outer) in TET_FACES.iter().zip(outer) {
        let f = face_key(f.map(|i| tet[i]));
        if !f.contains(&n) {
            continue;
        }
        if was_outer {
            around.remove(&f);
        } else {
            around.insert(f);
        }
    }
    around.into_iter().collect()
}

/// Whether removing `tet`, whose faces `outer` (opposite local node `k`) lie on the outer
/// boundary, leaves that boundary a manifold: its outer faces go and its other faces become
/// boundary, and around each of its nodes the boundary must still be one fan ([`one_fan`]) or
/// none. (With one outer face, the opposite node must be inside the body; with two, the edge
/// between their opposite nodes must not be on the boundary already; with three, their common
/// node goes with the element; a loose element always goes.)
fn keeps_manifold(tet: &[u32; 4], outer: &[bool; 4], boundary: &Boundary) -> bool {
    tet.iter()
        .all(|&n| one_fan(n, &faces_after_removal(n, tet, outer, boundary)))
}

/// Removes from `tets` (the whole new mesh) the region's elements (`k >= first`) of quality
/// below [`PEEL_QUALITY`] with at least one face on the outer boundary (held by no other
/// element), whose other faces are held by region elements and whose removal leaves the
/// boundary a manifold ([`keeps_manifold`]), repeatedly up to `passes` times: a layer of
/// collapsed elements on the surface is peeled from the outside in. With `erode`, every
/// collapsed element whose faces are held by region elements or none goes (module's erosion),
/// and then every loose fragment of region elements it left ([`loose_fragments`]).
/// Returns the kept elements' indices and the peeled elements, in the order removed.
/// Deterministic.
#[cfg(test)]
pub(crate) fn peel_boundary_slivers(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    first: usize,
    passes: usize,
    erode: bool,
) -> (Vec<usize>, Vec<PeeledElement>) {
    peel_failed_and_slivers(nodes, tets, first, passes, erode, &|_| false)
}

/// [`peel_boundary_slivers`], where with `erode` a region element at whose corners `failed`
/// holds is taken as a collapsed one is, whatever its shape (failed material:
/// `MesherOptions::erode_stretch`).
pub(crate) fn peel_failed_and_slivers(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    first: usize,
    passes: usize,
    erode: bool,
    failed: &dyn Fn(&[Vector3<f64>; 4]) -> bool,
) -> (Vec<usize>, Vec<PeeledElement>) {
    // Only faces with a node of the region are ever asked about (the region's faces, and the
    // boundary faces around its nodes), and every element holding one has that node: the
    // elements touching the region, and of their faces those, are enough (a map over the
    // whole mesh was 4 % of a nail run's CPU).
    let mut region_node = vec![false; nodes.len()];
    for tet in &tets[first.min(tets.len())..] {
        for &n in tet {
            region_node[n as usize] = true;
        }
    }
    let near: Vec<usize> = (0..tets.len())
        .filter(|&e| e >= first || tets[e].iter().any(|&n| region_node[n as usize]))
        .collect();
    let mut holders: HashMap<[u32; 3], Vec<usize>> = HashMap::with_capacity(4 * near.len());
    let mut boundary = Boundary::default();
    for &e in &near {
        let tet = &tets[e];
        for f in TET_FACES {
            let face = face_key(f.map(|i| tet[i]));
            // A face away from the region may have holders beyond these elements.
            if face.iter().any(|&n| region_node[n as usize]) {
                holders.entry(face).or_default().push(e);
            }
        }
    }
    for (key, _) in holders.iter().filter(|(_, h)| h.len() == 1) {
        boundary.set(*key, true);
    }
    let mut alive = vec![true; tets.len()];
    let mut peeled = Vec::new();
    for _ in 0..passes {
        let before = peeled.len();
        for e in first..tets.len() {
            if !alive[e] {
                continue;
            }
            let tet = tets[e];
            let corners = tet.map(|n| nodes[n as usize]);
            if shape_quality(&corners) >= PEEL_QUALITY && !(erode && failed(&corners)) {
                continue;
            }
            let mut outer = [false; 4];
            let mut inner_ok = true;
            for (k, f) in TET_FACES.iter().enumerate() {
                let others: Vec<usize> = holders[&face_key(f.map(|i| tet[i]))]
                    .iter()
                    .copied()
                    .filter(|&o| o != e && alive[o])
                    .collect();
                match others[..] {
                    [] => outer[k] = true,
                    [o] => inner_ok &= o >= first,
                    _ => inner_ok = false,
                }
            }
            if !inner_ok
                || !(erode || (outer.contains(&true) && keeps_manifold(&tet, &outer, &boundary)))
            {
                continue;
            }
            alive[e] = false;
            for (k, f) in TET_FACES.iter().enumerate() {
                boundary.set(face_key(f.map(|i| tet[i])), !outer[k]);
            }
            peeled.push((tet.map(|n| nodes[n as usize]), outer));
        }
        if peeled.len() == before {
            break;
        }
    }
    if erode {
        erode_loose_fragments(nodes, tets, first, &holders, &mut alive, &mut peeled);
    }
    ((0..tets.len()).filter(|&e| alive[e]).collect(), peeled)
}

/// Erodes every loose fragment ([`loose_fragments`]) of alive region elements (`k >= first`),
/// adding them to `peeled`: erosion leaves them hanging on the body by nodes or edges.
fn erode_loose_fragments(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    first: usize,
    holders: &HashMap<[u32; 3], Vec<usize>>,
    alive: &mut [bool],
    peeled: &mut Vec<PeeledElement>,
) {
    let candidates: Vec<usize> = (first..tets.len()).filter(|&e| alive[e]).collect();
    let fragments = {
        let alive = &*alive;
        let mut face_neighbours = |e: usize| -> Vec<usize> {
            TET_FACES
                .iter()
                .flat_map(|f| &holders[&face_key(f.map(|i| tets[e][i]))])
                .copied()
                .filter(|&o| o != e && alive[o])
                .collect()
        };
        // Every element holding a node of a region element holds a face in `holders`.
        let mut uses: HashMap<u32, usize> = HashMap::new();
        let mut counted: HashSet<usize> = HashSet::new();
        for list in holders.values() {
            for &e in list {
                if alive[e] && counted.insert(e) {
                    for n in tets[e] {
                        *uses.entry(n).or_default() += 1;
                    }
                }
            }
        }
        let hangs = |piece: &[usize]| shares_a_node(tets, piece, &|n| uses[&n]);
        loose_fragments(&candidates, &mut face_neighbours, &hangs)
    };
    // Each element's faces are outer but for those it shares with the fragment's elements not
    // yet gone.
    for e in fragments.into_iter().flatten() {
        let tet = tets[e];
        let outer = TET_FACES.map(|f| {
            holders[&face_key(f.map(|i| tet[i]))]
                .iter()
                .all(|&o| o == e || !alive[o])
        });
        alive[e] = false;
        peeled.push((tet.map(|n| nodes[n as usize]), outer));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::signed_volume;
    use crate::mesh::ops::locate::centroid;

    /// `t` positively oriented over `x`.
    fn oriented(x: &[Vector3<f64>], mut t: [u32; 4]) -> [u32; 4] {
        if signed_volume(&t.map(|n| x[n as usize])) < 0.0 {
            t.swap(2, 3);
        }
        t
    }

    /// A pyramid on the square `a b c d` (apex `e` below), its base split along `a c`, and on
    /// top the sliver `a b c d` (`d` lifted by `lift`), whose top is split along `b d`.
    fn roof(lift: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::new(0.0, 1.0, lift),
            Vector3::new(0.5, 0.5, -1.0),
        ];
        let tets = [[0, 1, 2, 4], [0, 2, 3, 4], [0, 1, 2, 3]]
            .map(|t| oriented(&x, t))
            .to_vec();
        (x, tets)
    }

    #[test]
    fn a_flat_element_with_two_faces_on_the_boundary_is_peeled() {
        let (x, tets) = roof(0.02);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, false);
        assert_eq!(kept, vec![0, 1]);
        assert_eq!(peeled.len(), 1);
        let (corners, outer) = peeled[0];
        let t = tets[2];
        assert_eq!(corners, t.map(|n| x[n as usize]));
        // The outer faces are the two that hold the lifted node and the diagonal b d.
        for (k, f) in TET_FACES.iter().enumerate() {
            let face: Vec<u32> = f.iter().map(|&i| t[i]).collect();
            assert_eq!(outer[k], face.contains(&1) && face.contains(&3), "{face:?}");
        }
    }

    #[test]
    fn a_good_element_or_one_outside_the_region_stays() {
        // Lifted by 1: a well-shaped element on top.
        let (x, tets) = roof(1.0);
        assert!(shape_quality(&tets[2].map(|n| x[n as usize])) > PEEL_QUALITY);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, false);
        assert_eq!((kept.len(), peeled.len()), (3, 0));
        // A sliver outside the region (before `first`) is never changed.
        let (x, tets) = roof(0.02);
        let (kept, _) = peel_boundary_slivers(&x, &tets, 3, 10, false);
        assert_eq!(kept.len(), 3);
        // The sliver alone in the region: its inner face is held by an element outside it, which
        // the search finds among the elements touching the region, so it stays, eroding or not.
        for erode in [false, true] {
            let (kept, peeled) = peel_boundary_slivers(&x, &tets, 2, 10, erode);
            assert_eq!((kept.len(), peeled.len()), (3, 0), "erode {erode}");
        }
    }

    /// The big tetrahedron 1 2 3 4 cut into four from node 0 inside it, which lies `height`
    /// above the face 1 2 3.
    fn star(height: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
        let x = vec![
            Vector3::new(0.3, 0.3, height),
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let tets = [[0, 1, 2, 3], [0, 1, 2, 4], [0, 2, 3, 4], [0, 1, 3, 4]]
            .map(|t| oriented(&x, t))
            .to_vec();
        (x, tets)
    }

    #[test]
    fn a_flat_element_with_one_face_on_the_boundary_goes_when_its_fourth_node_is_inside() {
        let (x, tets) = star(0.01);
        assert!(shape_quality(&tets[0].map(|n| x[n as usize])) < PEEL_QUALITY);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, false);
        assert_eq!(kept, vec![1, 2, 3]);
        assert_eq!(peeled.len(), 1);
        // Its face on the boundary is the one opposite node 0.
        let k0 = tets[0].iter().position(|&n| n == 0).unwrap();
        let outer: Vec<usize> = (0..4).filter(|&k| peeled[0].1[k]).collect();
        assert_eq!(outer, vec![k0]);
        // Without the big element above node 0 (1 3 4 gone), node 0 is on the boundary and the
        // flat element has two faces there (opposite nodes 0 and 2): peeling it opens the edge
        // 0-2, which the other two elements hold inside, and is allowed.
        let (kept, peeled) = peel_boundary_slivers(&x, &tets[..3], 0, 10, false);
        assert_eq!((kept, peeled.len()), (vec![1, 2], 1));
        // With the third element moved off to a node 5 of its own, the edge 0-2 is on the
        // boundary already (faces 0 2 4 and 0 2 5): peeling would hang four faces on it, and
        // does not happen.
        let mut x5 = x.clone();
        x5.push(Vector3::new(1.0, 1.0, 1.0));
        let t = vec![tets[0], tets[1], oriented(&x5, [0, 2, 3, 5])];
        for k in 1..3 {
            assert!(shape_quality(&t[k].map(|n| x5[n as usize])) > PEEL_QUALITY);
        }
        let (kept, peeled) = peel_boundary_slivers(&x5, &t, 0, 10, false);
        assert_eq!((kept, peeled.len()), (vec![0, 1, 2], 0));
    }

    #[test]
    fn a_flat_cap_goes_with_its_apex() {
        // The roof's lower pyramid (well shaped) and a cap on its face a b c whose apex (node 5)
        // lies just above that face and in no other element: three faces on the boundary.
        let (mut x, tets) = roof(1.0);
        x.push(Vector3::new(0.7, 0.3, 0.005));
        let mut t = tets[..2].to_vec();
        t.push(oriented(&x, [0, 1, 2, 5]));
        // Node 5 lies above a b c, away from the pyramid, when its base is flipped below it.
        assert!(signed_volume(&t[2].map(|n| x[n as usize])) > 0.0);
        let (kept, peeled) = peel_boundary_slivers(&x, &t, 0, 10, false);
        assert_eq!((kept, peeled.len()), (vec![0, 1], 1));
        assert_eq!(peeled[0].1.iter().filter(|&&b| b).count(), 3);
    }

    /// How many of the boundary faces of `tets` hold each of their edges.
    fn boundary_edge_uses(tets: &[[u32; 4]]) -> HashMap<[u32; 2], usize> {
        let mut count: HashMap<[u32; 3], usize> = HashMap::new();
        for t in tets {
            for f in TET_FACES {
                *count.entry(face_key(f.map(|i| t[i]))).or_default() += 1;
            }
        }
        let mut edges: HashMap<[u32; 2], usize> = HashMap::new();
        for (f, _) in count.iter().filter(|(_, &c)| c == 1) {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                *edges.entry([a.min(b), a.max(b)]).or_default() += 1;
            }
        }
        edges
    }

    /// Whether every edge of the boundary faces of `tets` lies in exactly two of them.
    fn boundary_is_closed(tets: &[[u32; 4]]) -> bool {
        boundary_edge_uses(tets).values().all(|&c| c == 2)
    }

    /// The outer faces of `tets` as a [`Boundary`].
    fn boundary_of(tets: &[[u32; 4]]) -> Boundary {
        let mut count: HashMap<[u32; 3], usize> = HashMap::new();
        for t in tets {
            for f in TET_FACES {
                *count.entry(face_key(f.map(|i| t[i]))).or_default() += 1;
            }
        }
        let mut boundary = Boundary::default();
        for (f, _) in count.iter().filter(|(_, &c)| c == 1) {
            boundary.set(*f, true);
        }
        boundary
    }

    /// The unit cube in 4 x 4 x 4 cells of six elements.
    fn unit_box() -> crate::mesh::Mesh {
        use crate::mesh::{box_mesh, BoxSpec};
        box_mesh(&BoxSpec {
            origin: [0.0; 3],
            size: [1.0; 3],
            divisions: [4, 4, 4],
            mirror: Vec::new(),
        })
    }

    /// The first element of `mesh` (a unit box) whose four nodes are all inside the box.
    fn inner_element(mesh: &crate::mesh::Mesh) -> usize {
        let inside = |p: &Vector3<f64>| p.iter().all(|&c| c > 1e-9 && c < 1.0 - 1e-9);
        mesh.tets
            .iter()
            .position(|t| t.iter().all(|&n| inside(&mesh.nodes[n as usize])))
            .expect("a box of 2 or more divisions has an inner element")
    }

    #[test]
    fn erosion_removes_a_membrane_between_two_surfaces_where_peeling_may_not() {
        let mesh = unit_box();
        let mut x = mesh.nodes.clone();
        let on_top = |n: u32| (mesh.nodes[n as usize].z - 1.0).abs() < 1e-9;
        let inside = |n: u32| {
            mesh.nodes[n as usize]
                .iter()
                .all(|&c| c > 1e-9 && c < 1.0 - 1e-9)
        };
        // An element with a face on the top and its fourth node d inside, and an element inside
        // the box that shares only d with it: removing that one opens a void at d, so d lies
        // on a second surface, apart from the top's. The first element, flattened, is then the
        // membrane between the two surfaces (the cavity slivers of the nail run, whose fourth
        // node lay on another part of the cavity).
        let membrane = *mesh
            .tets
            .iter()
            .find(|t| t.iter().filter(|&&n| on_top(n)).count() == 3 && t.iter().any(|&n| inside(n)))
            .unwrap();
        let d = *membrane.iter().find(|&&n| inside(n)).unwrap();
        let void = mesh
            .tets
            .iter()
            .position(|t| {
                t.contains(&d)
                    && t.iter()
                        .all(|&n| n == d || (inside(n) && !membrane.contains(&n)))
            })
            .unwrap();
        let tets: Vec<[u32; 4]> = (0..mesh.tets.len())
            .filter(|&k| k != void)
            .map(|k| mesh.tets[k])
            .collect();
        assert!(boundary_is_closed(&tets));
        let boundary = boundary_of(&tets);
        let outer = TET_FACES.map(|f| {
            let key = face_key(f.map(|i| membrane[i]));
            boundary.faces_at_node[&key[0]].contains(&key)
        });
        assert_eq!(outer.iter().filter(|&&o| o).count(), 1);
        // d keeps the void's fan and would gain the membrane's three inner faces: two fans.
        assert!(!keeps_manifold(&membrane, &outer, &boundary));
        // d moved 95 % of the way to the top: the membrane collapses (and the elements between
        // d and the top with it).
        let k = membrane.iter().position(|&n| n == d).unwrap();
        let [a, b, c] = TET_FACES[k].map(|i| x[membrane[i] as usize]);
        let normal = (b - a).cross(&(c - a)).normalize();
        let height = (x[d as usize] - a).dot(&normal);
        x[d as usize] -= 0.95 * height * normal;
        assert!(shape_quality(&membrane.map(|n| x[n as usize])) < PEEL_QUALITY);
        let corners = membrane.map(|n| x[n as usize]);
        let (_, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, false);
        assert!(!peeled.iter().any(|(c, _)| *c == corners));
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, true);
        assert!(peeled.iter().any(|(c, _)| *c == corners));
        for (c, _) in &peeled {
            assert!(shape_quality(c) < PEEL_QUALITY);
        }
        // What is left has a closed surface, which may touch itself.
        let left: Vec<[u32; 4]> = kept.iter().map(|&e| tets[e]).collect();
        assert_eq!(left.len() + peeled.len(), tets.len());
        assert!(boundary_edge_uses(&left).values().all(|&c| c % 2 == 0));
    }

    #[test]
    fn erosion_removes_a_collapsed_element_inside_the_body_and_keeps_the_surface_closed() {
        let mesh = unit_box();
        let mut x = mesh.nodes.clone();
        // An element with its four nodes inside, one of them moved 90 % of the way to the
        // plane of the opposite face.
        let e = inner_element(&mesh);
        let t = mesh.tets[e].map(|n| n as usize);
        let normal = (x[t[2]] - x[t[1]]).cross(&(x[t[3]] - x[t[1]])).normalize();
        let height = (x[t[0]] - x[t[1]]).dot(&normal);
        x[t[0]] -= 0.9 * height * normal;
        assert!(shape_quality(&mesh.tets[e].map(|n| x[n as usize])) < PEEL_QUALITY);
        // Peeling alone leaves it: it has no face on the surface.
        let (_, peeled) = peel_boundary_slivers(&x, &mesh.tets, 0, 10, false);
        assert!(peeled.is_empty());
        // Erosion removes the collapsed elements, none with a good shape, and leaves a closed
        // surface (the void's and the box's), which may touch itself.
        let (kept, peeled) = peel_boundary_slivers(&x, &mesh.tets, 0, 10, true);
        assert!(peeled
            .iter()
            .any(|(c, _)| *c == mesh.tets[e].map(|n| x[n as usize])));
        for (c, _) in &peeled {
            assert!(shape_quality(c) < PEEL_QUALITY);
        }
        let left: Vec<[u32; 4]> = kept.iter().map(|&k| mesh.tets[k]).collect();
        assert_eq!(left.len() + peeled.len(), mesh.tets.len());
        assert!(boundary_edge_uses(&left).values().all(|&c| c % 2 == 0));
    }

    #[test]
    fn erosion_takes_a_well_shaped_element_of_failed_material_and_peeling_does_not() {
        let mesh = unit_box();
        let x = mesh.nodes.clone();
        // An inner element, undistorted: failed material by its centroid.
        let e = inner_element(&mesh);
        let corners = mesh.tets[e].map(|n| x[n as usize]);
        assert!(shape_quality(&corners) >= PEEL_QUALITY);
        let centre = centroid(&corners);
        let failed = |c: &[Vector3<f64>; 4]| (centroid(c) - centre).norm() < 1e-12;
        // Without erosion nothing goes; with it, that element and no other well-shaped one.
        let (kept, peeled) = peel_failed_and_slivers(&x, &mesh.tets, 0, 10, false, &failed);
        assert!(peeled.is_empty() && kept.len() == mesh.tets.len());
        let (kept, peeled) = peel_failed_and_slivers(&x, &mesh.tets, 0, 10, true, &failed);
        assert_eq!(peeled.len(), 1, "{peeled:?}");
        assert_eq!(peeled[0].0, corners);
        // An inner element: no face of it was on the surface.
        assert_eq!(peeled[0].1, [false; 4]);
        let left: Vec<[u32; 4]> = kept.iter().map(|&k| mesh.tets[k]).collect();
        assert!(boundary_edge_uses(&left).values().all(|&c| c % 2 == 0));
    }

    #[test]
    fn erosion_takes_the_element_it_leaves_hanging_by_an_edge() {
        // On a face a b c of the box's top, a flat element a b c p (p just above the face's
        // centre), and on its face a b p a well-shaped element a b p q: once the flat one erodes,
        // that one hangs on the box by the edge a-b (a loose fragment) and goes too, its four
        // faces all outer; the box stays whole.
        let mesh = unit_box();
        let mut x = mesh.nodes.clone();
        let top = *mesh
            .tets
            .iter()
            .find(|t| {
                t.iter()
                    .filter(|&&n| (x[n as usize].z - 1.0).abs() < 1e-9)
                    .count()
                    == 3
            })
            .unwrap();
        let [a, b, c] = {
            let on: Vec<u32> = top
                .iter()
                .copied()
                .filter(|&n| (x[n as usize].z - 1.0).abs() < 1e-9)
                .collect();
            [on[0], on[1], on[2]]
        };
        let centre = (x[a as usize] + x[b as usize] + x[c as usize]) / 3.0;
        x.push(centre + Vector3::new(0.0, 0.0, 0.01));
        x.push(0.5 * (x[a as usize] + x[b as usize]) + Vector3::new(0.0, 0.0, 0.3));
        let (p, q) = (x.len() as u32 - 2, x.len() as u32 - 1);
        let mut tets = mesh.tets.clone();
        tets.push(oriented(&x, [a, b, c, p]));
        tets.push(oriented(&x, [a, b, p, q]));
        let n = mesh.tets.len();
        assert!(shape_quality(&tets[n].map(|k| x[k as usize])) < PEEL_QUALITY);
        assert!(shape_quality(&tets[n + 1].map(|k| x[k as usize])) > PEEL_QUALITY);
        let (kept, peeled) = peel_boundary_slivers(&x, &tets, 0, 10, true);
        assert_eq!(kept, (0..n).collect::<Vec<_>>());
        assert_eq!(peeled.len(), 2);
        assert_eq!(peeled[1], (tets[n + 1].map(|k| x[k as usize]), [true; 4]));
        // The well-shaped element with the box but not the flat one: joined by a face, it stays.
        let joined = [&mesh.tets[..], &[oriented(&x, [a, b, c, q])]].concat();
        let (kept, _) = peel_boundary_slivers(&x, &joined, 0, 10, true);
        assert_eq!(kept.len(), n + 1);
        // Alone, it is a body of its own, not a fragment.
        let (kept, _) = peel_boundary_slivers(&x, &tets[n + 1..], 0, 10, true);
        assert_eq!(kept, vec![0]);
    }
}
