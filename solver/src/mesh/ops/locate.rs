//! Where the points of a new mesh lie in the old one (thesis 8.4.2 step (i), Box 8.3), and which
//! old Gauss point is closest to a new one (8.4.1.2).
//!
//! Both searches run over a bounding-volume hierarchy of the old elements' boxes or centroids
//! (`box_tree.rs`; a uniform grid crowded the fine elements of a graded mesh into a few cells).
//! Every tie is broken towards the lower element id, so the answers do not depend on anything
//! but the meshes.

use nalgebra::Vector3;

use super::box_tree::BoxTree;
use super::mesher::RemeshedRegion;
use crate::error::{Result, SolverError};
use crate::geometry::broad_phase::Aabb;
use crate::geometry::proximity::closest_point_on_triangle;
use crate::kinematics::shape_gradients;

/// Barycentric tolerance of the point location: a point whose smallest barycentric coordinate in
/// an element is at least `-LOCATE_TOLERANCE` lies in that element. Box 8.3 starts from a
/// tolerance and widens it by 1e-3 per failed sweep; here a point found in no element goes to
/// the nearest element instead ([`Locator::locate`]), so the tolerance only has to absorb
/// round-off: 1e-10 is about 10^6 times the round-off of the coordinates and far below any
/// geometric feature.
pub const LOCATE_TOLERANCE: f64 = 1e-10;

/// Where a point lies in the old mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Location {
    /// The old element that holds the point, or the nearest one for a point outside the mesh.
    pub element: usize,
    /// The point's barycentric coordinates `N_a(x)` (3.61) in that element; they sum to one.
    /// For a point just outside the mesh some are negative: interpolating with them extrapolates
    /// the element's linear field, which keeps T3 exact for linear fields.
    pub barycentric: [f64; 4],
    /// Distance from the point to the element (m): 0 inside, else how far outside it is.
    pub distance: f64,
}

/// Point location in an old mesh at its current coordinates (the first step of T1 and T3).
#[derive(Debug, Clone)]
pub struct Locator<'a> {
    nodes: &'a [Vector3<f64>],
    tets: &'a [[u32; 4]],
    grad: Vec<[Vector3<f64>; 4]>,
    tree: BoxTree,
}

impl<'a> Locator<'a> {
    /// The locator of the mesh `tets` over the coordinates `nodes` (the old mesh in the current
    /// configuration). Every element must have a positive volume there: an inverted element
    /// holds no point and no field can be interpolated in it, so it is an error naming it.
    pub fn new(nodes: &'a [Vector3<f64>], tets: &'a [[u32; 4]]) -> Result<Self> {
        if tets.is_empty() {
            return Err(SolverError::Remesh {
                entity: "old mesh".to_string(),
                message: "has no elements to locate points in".to_string(),
            });
        }
        let mut grad = Vec::with_capacity(tets.len());
        let mut boxes = Vec::with_capacity(tets.len());
        for (e, tet) in tets.iter().enumerate() {
            let x = tet.map(|n| nodes[n as usize]);
            let Some((g, _)) = shape_gradients(&x) else {
                return Err(SolverError::Remesh {
                    entity: format!("old element {e}"),
                    message: "its current volume is not positive (inverted or collapsed); \
                              fields cannot be interpolated in it. Remesh earlier (a lower \
                              collapse-ratio limit)"
                        .to_string(),
                });
            };
            grad.push(g);
            // The points whose barycentric coordinates are all at least -t form the element
            // scaled by 1 + 4t about its centroid c (corner a moves to x_a + 4t (x_a - c)), and
            // |x_a - c| is at most 3/4 of the box's extent along each axis: the box grown by
            // 3t times its largest extent holds every point the element may hold.
            let b = Aabb::of_points(&x);
            boxes.push(b.grown(3.0 * LOCATE_TOLERANCE * (b.max - b.min).max()));
        }
        Ok(Self {
            nodes,
            tets,
            grad,
            tree: BoxTree::new(boxes),
        })
    }

    /// Barycentric coordinates `N_a(p)` of `p` in element `e` (3.61):
    /// `N_a(p) = N_a(x_0) + grad N_a . (p - x_0)`, with `N_0 = 1 - N_1 - N_2 - N_3` so that they
    /// sum to one exactly.
    pub fn barycentric(&self, e: usize, p: &Vector3<f64>) -> [f64; 4] {
        let d = p - self.nodes[self.tets[e][0] as usize];
        let g = &self.grad[e];
        let (l1, l2, l3) = (g[1].dot(&d), g[2].dot(&d), g[3].dot(&d));
        [1.0 - l1 - l2 - l3, l1, l2, l3]
    }

    /// Distance from `p` to element `e` (m): 0 when its barycentric coordinates are all at least
    /// `-LOCATE_TOLERANCE` (inside, as [`Self::locate`] decides it), else the distance to the
    /// nearest of its faces.
    fn distance(&self, e: usize, p: &Vector3<f64>) -> f64 {
        let l = self.barycentric(e, p);
        if l.iter().all(|&v| v >= -LOCATE_TOLERANCE) {
            return 0.0;
        }
        let x = self.tets[e].map(|n| self.nodes[n as usize]);
        crate::mesh::TET_FACES
            .iter()
            .map(|f| (closest_point_on_triangle(p, &x[f[0]], &x[f[1]], &x[f[2]]) - p).norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// Where `p` lies: the element whose smallest barycentric coordinate is at least
    /// `-LOCATE_TOLERANCE` (the most interior one, then the lowest id, where several qualify, as
    /// on a shared face); failing that, the nearest element, with `distance` how far outside it
    /// the point is (a point of the new boundary just outside the old one).
    pub fn locate(&self, p: &Vector3<f64>) -> Location {
        let mut best: Option<(usize, [f64; 4], f64)> = None;
        self.tree.for_each_holding(p, |e| {
            let e = e as usize;
            let l = self.barycentric(e, p);
            let smallest = l.iter().copied().fold(f64::INFINITY, f64::min);
            let better = best.is_none_or(|b| smallest > b.2 || (smallest == b.2 && e < b.0));
            if smallest >= -LOCATE_TOLERANCE && better {
                best = Some((e, l, smallest));
            }
        });
        if let Some((element, barycentric, _)) = best {
            return Location {
                element,
                barycentric,
                distance: 0.0,
            };
        }
        let (e, distance) = self
            .tree
            .nearest(p, |e| self.distance(e as usize, p))
            .expect("the locator has at least one element (checked when built)");
        let element = e as usize;
        Location {
            element,
            barycentric: self.barycentric(element, p),
            distance,
        }
    }

    /// Whether an element holds `p` with every barycentric coordinate above
    /// `LOCATE_TOLERANCE`: strictly inside the mesh, so a point on its boundary is not.
    pub fn holds_strictly(&self, p: &Vector3<f64>) -> bool {
        let at = self.locate(p);
        at.distance == 0.0 && at.barycentric.iter().all(|&w| w > LOCATE_TOLERANCE)
    }

    /// [`Self::locate`] for every point, with an error naming the first point farther than
    /// `max_distance` (m) outside the old mesh: the new mesh does not fill the same domain.
    pub fn locate_all(&self, points: &[Vector3<f64>], max_distance: f64) -> Result<Vec<Location>> {
        points
            .iter()
            .enumerate()
            .map(|(i, p)| self.locate_within(i, p, max_distance))
            .collect()
    }

    /// [`Self::locate`] of the new point `i` at `p`, or the error of [`Self::locate_all`].
    fn locate_within(&self, i: usize, p: &Vector3<f64>, max_distance: f64) -> Result<Location> {
        let l = self.locate(p);
        if l.distance > max_distance {
            return Err(SolverError::Remesh {
                entity: format!("new point {i} at {:?}", p.as_slice()),
                message: format!(
                    "lies {:.3e} m outside the old mesh (nearest old element {}), more than the \
                     {max_distance:.3e} m allowed: the new mesh must fill the old mesh's current \
                     domain",
                    l.distance, l.element
                ),
            });
        }
        Ok(l)
    }

    /// Where each node of the remeshed mesh `new` lies in this old mesh, whose elements are
    /// `tets`: a kept node sits on its old node (bit for bit), so it gets that node's vertex of
    /// the first old element holding it, barycentric 1 there and 0 elsewhere; the other nodes
    /// are searched, with the error of [`Self::locate_all`] (naming the node) for one farther
    /// than `max_distance` outside. Searching only the region's nodes keeps a remeshing's cost
    /// with the region, not the body.
    pub(crate) fn locate_remeshed_nodes(
        &self,
        tets: &[[u32; 4]],
        new: &RemeshedRegion,
        max_distance: f64,
    ) -> Result<Vec<Location>> {
        let mut holder = vec![None; new.kept_nodes.len()];
        for (e, tet) in tets.iter().enumerate() {
            for (k, &n) in tet.iter().enumerate() {
                holder[n as usize].get_or_insert((e, k));
            }
        }
        let mut at_old_node: Vec<Option<Location>> = vec![None; new.nodes.len()];
        for (o, kept) in new.kept_nodes.iter().enumerate() {
            if let (Some(k), Some((e, i))) = (kept, holder[o]) {
                let mut barycentric = [0.0; 4];
                barycentric[i] = 1.0;
                at_old_node[*k as usize] = Some(Location {
                    element: e,
                    barycentric,
                    distance: 0.0,
                });
            }
        }
        at_old_node
            .into_iter()
            .enumerate()
            .map(|(n, l)| match l {
                Some(l) => Ok(l),
                None => self.locate_within(n, &new.nodes[n], max_distance),
            })
            .collect()
    }
}

/// Nearest-point search among the centroids of an old mesh's elements, the Gauss points of the
/// linear tetrahedron (one point, at the centroid, integrates it exactly; thesis 3.3.3.1).
#[derive(Debug, Clone)]
pub struct CentroidSearch {
    centroids: Vec<Vector3<f64>>,
    tree: BoxTree,
}

impl CentroidSearch {
    /// The search over the points `centroids` (m), the old Gauss points.
    pub fn new(centroids: Vec<Vector3<f64>>) -> Self {
        let boxes: Vec<_> = centroids
            .iter()
            .map(|c| Aabb { min: *c, max: *c })
            .collect();
        let tree = BoxTree::new(boxes);
        Self { centroids, tree }
    }

    /// The index of the centroid closest to `p` (Euclidean distance; the lowest index among
    /// equally close ones), with its distance (m). `None` when there are no centroids.
    pub fn closest(&self, p: &Vector3<f64>) -> Option<(usize, f64)> {
        let (i, d) = self
            .tree
            .nearest(p, |i| (self.centroids[i as usize] - p).norm())?;
        Some((i as usize, d))
    }
}

/// The centroid of a tetrahedron's four corners.
pub fn centroid(corners: &[Vector3<f64>; 4]) -> Vector3<f64> {
    corners.iter().sum::<Vector3<f64>>() / 4.0
}

/// The centroid `(x_0 + x_1 + x_2 + x_3) / 4` of every element of `tets` over `nodes` (m).
pub fn centroids(nodes: &[Vector3<f64>], tets: &[[u32; 4]]) -> Vec<Vector3<f64>> {
    tets.iter()
        .map(|t| centroid(&t.map(|n| nodes[n as usize])))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{box_mesh, BoxSpec};

    fn unit_box(n: usize) -> crate::mesh::Mesh {
        box_mesh(&BoxSpec {
            origin: [0.0; 3],
            size: [1.0, 1.0, 1.0],
            divisions: [n; 3],
            mirror: Vec::new(),
        })
    }

    #[test]
    fn every_node_of_a_finer_mesh_is_found_with_exact_coordinates() {
        let old = unit_box(3);
        let new = unit_box(5);
        let locator = Locator::new(&old.nodes, &old.tets).unwrap();
        for p in &new.nodes {
            let l = locator.locate(p);
            assert_eq!(l.distance, 0.0);
            assert!(l.barycentric.iter().all(|&v| v >= -LOCATE_TOLERANCE));
            let x = old.element_nodes(l.element);
            let q: Vector3<f64> = (0..4).map(|a| x[a] * l.barycentric[a]).sum();
            assert!((q - p).norm() < 1e-15, "{p:?} -> {q:?}");
        }
    }

    #[test]
    fn tree_search_matches_a_brute_force_scan() {
        let old = unit_box(4);
        let locator = Locator::new(&old.nodes, &old.tets).unwrap();
        let mut rng = crate::rng::SplitMix64::new(7);
        for _ in 0..500 {
            // Points inside and up to 0.2 outside the box.
            let p = Vector3::new(
                rng.uniform(-0.2, 1.2),
                rng.uniform(-0.2, 1.2),
                rng.uniform(-0.2, 1.2),
            );
            let l = locator.locate(&p);
            let brute = (0..old.tets.len())
                .map(|e| locator.distance(e, &p))
                .fold(f64::INFINITY, f64::min);
            assert!(
                (l.distance - brute).abs() < 1e-14,
                "{p:?}: {} vs {brute}",
                l.distance
            );
            let inside = (0..3).all(|a| (0.0..=1.0).contains(&p[a]));
            assert_eq!(l.distance == 0.0, inside, "{p:?}");
            // Outside, the distance is the one to the box.
            let to_box = p.map(|v| v.clamp(0.0, 1.0)) - p;
            assert!((l.distance - to_box.norm()).abs() < 1e-14);
        }
    }

    #[test]
    fn inverted_old_element_is_an_error() {
        let mut old = unit_box(1);
        old.tets[3].swap(0, 1);
        let err = Locator::new(&old.nodes, &old.tets).unwrap_err();
        assert!(err.to_string().contains("old element 3"), "{err}");
        let old = unit_box(2);
        let locator = Locator::new(&old.nodes, &old.tets).unwrap();
        let far = [Vector3::new(0.5, 0.5, 0.5), Vector3::new(2.0, 0.5, 0.5)];
        let err = locator.locate_all(&far, 0.1).unwrap_err();
        assert!(err.to_string().contains("new point 1"), "{err}");
    }

    #[test]
    fn closest_centroid_matches_a_brute_force_scan() {
        let old = unit_box(3);
        let c = centroids(&old.nodes, &old.tets);
        let search = CentroidSearch::new(c.clone());
        let mut rng = crate::rng::SplitMix64::new(11);
        for _ in 0..500 {
            let p = Vector3::new(
                rng.uniform(-0.1, 1.1),
                rng.uniform(-0.1, 1.1),
                rng.uniform(-0.1, 1.1),
            );
            let (i, d) = search.closest(&p).unwrap();
            let (j, e) = c
                .iter()
                .enumerate()
                .map(|(j, q)| (j, (q - p).norm_squared()))
                .fold(
                    (usize::MAX, f64::INFINITY),
                    |b, x| if x.1 < b.1 { x } else { b },
                );
            assert_eq!(i, j);
            assert!((d - e.sqrt()).abs() < 1e-15);
        }
    }
}
