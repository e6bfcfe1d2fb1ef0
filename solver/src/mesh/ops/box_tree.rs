//! A bounding-volume hierarchy over axis-aligned boxes, for the remesher's point searches
//! (`locate.rs`): which boxes hold a point, and which item is nearest to it.
//!
//! A uniform grid sized by the mean box volume (the contact broad phase's) serves a mesh whose
//! elements are alike; a remeshed body is graded from a tenth of a millimetre at a penetrator to
//! centimetres away from it, and its fine elements crowd into a few cells: locating the nodes
//! of one remeshing of the path-fine nail block (36 000 elements, 0.25 mm to 60 mm) tried
//! thousands of candidates per point: 40 % of the run's samples under perf, about 4 s per
//! remeshing. The tree splits where the boxes are, so
//! a query visits `O(log n)` nodes whatever the grading.
//!
//! Built by median splits along the longest extent of the box centres (ties by id), so the tree
//! depends on the boxes alone; queries answer by rules that do not depend on the visiting order
//! (the lowest id among equals), so their answers depend on the boxes and the point alone.

use nalgebra::Vector3;

use crate::geometry::broad_phase::Aabb;

/// Most items in a leaf.
const LEAF_SIZE: usize = 8;

/// A node of the tree: its bounds and either two children or a run of `items`.
#[derive(Debug, Clone, Copy)]
struct TreeNode {
    bounds: Aabb,
    /// Leaf: first entry in `items`; inner node: the index of the first child (the second
    /// follows its whole subtree, at `second`).
    start: u32,
    /// Leaf: number of items; inner node: 0.
    count: u32,
    /// Inner node: the index of the second child.
    second: u32,
}

/// A bounding-volume hierarchy over boxes identified by their position (see the module).
#[derive(Debug, Clone)]
pub struct BoxTree {
    boxes: Vec<Aabb>,
    nodes: Vec<TreeNode>,
    items: Vec<u32>,
}

impl BoxTree {
    /// The tree over `boxes`; box `i` is item `i`.
    pub fn new(boxes: Vec<Aabb>) -> Self {
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        let centres: Vec<Vector3<f64>> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1);
        if !boxes.is_empty() {
            build(&boxes, &centres, &mut items, 0, &mut nodes);
        }
        Self {
            boxes,
            nodes,
            items,
        }
    }

    /// Calls `visit(i)` for every box `i` that holds `p` (boundary included), in no set order.
    pub fn for_each_holding(&self, p: &Vector3<f64>, mut visit: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !node.bounds.contains(p) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.second);
                stack.push(n + 1);
                continue;
            }
            let run = node.start as usize..(node.start + node.count) as usize;
            for &i in &self.items[run] {
                if self.boxes[i as usize].contains(p) {
                    visit(i);
                }
            }
        }
    }

    /// The item nearest to `p` by `distance`, with that distance (the lowest id among equals);
    /// `None` for an empty tree. `distance(i)` must be at least the distance from `p` to box
    /// `i`: a subtree whose bounds lie farther than the best distance found is not searched.
    pub fn nearest(&self, p: &Vector3<f64>, distance: impl Fn(u32) -> f64) -> Option<(u32, f64)> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best = (u32::MAX, f64::INFINITY);
        let mut stack = vec![(0u32, box_distance(&self.nodes[0].bounds, p))];
        while let Some((n, reach)) = stack.pop() {
            // Equal distances are searched too: a lower id may lie there.
            if reach > best.1 {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.count == 0 {
                let (a, b) = (n + 1, node.second);
                let da = box_distance(&self.nodes[a as usize].bounds, p);
                let db = box_distance(&self.nodes[b as usize].bounds, p);
                // The nearer child is searched first, so the best distance falls sooner.
                if da <= db {
                    stack.push((b, db));
                    stack.push((a, da));
                } else {
                    stack.push((a, da));
                    stack.push((b, db));
                }
                continue;
            }
            let run = node.start as usize..(node.start + node.count) as usize;
            for &i in &self.items[run] {
                if box_distance(&self.boxes[i as usize], p) > best.1 {
                    continue;
                }
                let d = distance(i);
                if d < best.1 || (d == best.1 && i < best.0) {
                    best = (i, d);
                }
            }
        }
        (best.0 != u32::MAX).then_some(best)
    }
}

/// Euclidean distance from `p` to box `b` (m); 0 inside.
fn box_distance(b: &Aabb, p: &Vector3<f64>) -> f64 {
    let outside = Vector3::from_fn(|a, _| (b.min[a] - p[a]).max(p[a] - b.max[a]).max(0.0));
    outside.norm()
}

/// Builds the subtree over `items` (a run of the tree's items starting at `first`), pushing its
/// nodes in depth-first order; returns nothing, its root is the first node pushed.
fn build(
    boxes: &[Aabb],
    centres: &[Vector3<f64>],
    items: &mut [u32],
    first: usize,
    nodes: &mut Vec<TreeNode>,
) {
    let bounds = items.iter().fold(boxes[items[0] as usize], |acc, &i| {
        acc.union(&boxes[i as usize])
    });
    let me = nodes.len();
    nodes.push(TreeNode {
        bounds,
        start: first as u32,
        count: items.len() as u32,
        second: 0,
    });
    if items.len() <= LEAF_SIZE {
        return;
    }
    let spread = items
        .iter()
        .fold(Aabb::of_points(std::iter::empty()), |acc, &i| {
            let c = centres[i as usize];
            acc.union(&Aabb { min: c, max: c })
        });
    let axis = (spread.max - spread.min).imax();
    let half = items.len() / 2;
    items.select_nth_unstable_by(half, |&i, &j| {
        centres[i as usize][axis]
            .total_cmp(&centres[j as usize][axis])
            .then(i.cmp(&j))
    });
    let (low, high) = items.split_at_mut(half);
    build(boxes, centres, low, first, nodes);
    let second = nodes.len() as u32;
    build(boxes, centres, high, first + half, nodes);
    nodes[me].count = 0;
    nodes[me].start = 0;
    nodes[me].second = second;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    fn random_boxes(rng: &mut SplitMix64, n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|_| {
                // Graded sizes, from 1e-4 to 1e-1, as in a mesh refined at a point.
                let c = Vector3::new(
                    rng.uniform(0.0, 1.0),
                    rng.uniform(0.0, 1.0),
                    rng.uniform(0.0, 1.0),
                );
                let h = 10f64.powf(rng.uniform(-4.0, -1.0));
                Aabb {
                    min: c.add_scalar(-h),
                    max: c.add_scalar(h),
                }
            })
            .collect()
    }

    #[test]
    fn the_boxes_holding_a_point_are_those_a_scan_finds() {
        let mut rng = SplitMix64::new(3);
        let boxes = random_boxes(&mut rng, 3000);
        let tree = BoxTree::new(boxes.clone());
        for _ in 0..500 {
            let p = Vector3::new(
                rng.uniform(-0.1, 1.1),
                rng.uniform(-0.1, 1.1),
                rng.uniform(-0.1, 1.1),
            );
            let mut found = Vec::new();
            tree.for_each_holding(&p, |i| found.push(i));
            found.sort_unstable();
            let scan: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].contains(&p))
                .collect();
            assert_eq!(found, scan, "{p:?}");
        }
    }

    #[test]
    fn the_nearest_item_is_the_scan_s_with_the_lowest_id_among_equals() {
        let mut rng = SplitMix64::new(5);
        let boxes = random_boxes(&mut rng, 2000);
        let tree = BoxTree::new(boxes.clone());
        // Distances rounded to a coarse step, so that ties are common and the id decides.
        let distance =
            |i: u32, p: &Vector3<f64>| (box_distance(&boxes[i as usize], p) * 20.0).ceil();
        for _ in 0..500 {
            let p = Vector3::new(
                rng.uniform(-0.5, 1.5),
                rng.uniform(-0.5, 1.5),
                rng.uniform(-0.5, 1.5),
            );
            let got = tree.nearest(&p, |i| distance(i, &p)).unwrap();
            let scan = (0..boxes.len() as u32).map(|i| (i, distance(i, &p))).fold(
                (u32::MAX, f64::INFINITY),
                |b, x| if x.1 < b.1 { x } else { b },
            );
            assert_eq!(got, scan, "{p:?}");
        }
        assert!(BoxTree::new(Vec::new())
            .nearest(&Vector3::zeros(), |_| 0.0)
            .is_none());
    }
}
