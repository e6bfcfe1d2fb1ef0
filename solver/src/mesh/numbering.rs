//! Renumbering a mesh so that consecutive ids lie close together in space.
//!
//! A distributed run gives each rank a range of consecutive element ids (the order in which the
//! one-process assembly folds the forces, `crate::distributed`), and sums over nodes in blocks of
//! consecutive node ids. On a mesh whose numbering wanders (a Delaunay mesher's output), those
//! ranges are scattered through the body and nearly every node is shared. Renumbered here, the
//! ranges are the parts of a recursive coordinate bisection (Berger & Bokhari 1987): compact
//! boxes whose shared nodes are those of their faces.

use nalgebra::Vector3;

use super::Mesh;

/// Elements below which a bisection stops: the blocks of the stored energy's fold
/// (`crate::model::ELEMENT_LEAF`) need no finer order.
const SMALLEST_PART: usize = 32;

impl Mesh {
    /// Renumbers the elements in recursive-coordinate-bisection order of their centroids, then
    /// the nodes in the order the new elements first use them (nodes no element uses keep their
    /// relative order, after the others); node sets follow their nodes and stay ascending. The
    /// same mesh gives the same numbering on every machine: ties are broken by the old ids.
    pub fn renumber_spatially(&mut self) {
        let centroids: Vec<Vector3<f64>> = (0..self.tets.len())
            .map(|e| self.element_nodes(e).iter().sum::<Vector3<f64>>() / 4.0)
            .collect();
        let mut order: Vec<u32> = (0..self.tets.len() as u32).collect();
        bisect(&mut order, &centroids);
        self.tets = order.iter().map(|&e| self.tets[e as usize]).collect();

        const UNSET: u32 = u32::MAX;
        let mut new_id = vec![UNSET; self.nodes.len()];
        let mut next = 0u32;
        for n in self.tets.iter().flatten() {
            if new_id[*n as usize] == UNSET {
                new_id[*n as usize] = next;
                next += 1;
            }
        }
        for id in new_id.iter_mut().filter(|id| **id == UNSET) {
            *id = next;
            next += 1;
        }
        let mut nodes = vec![Vector3::zeros(); self.nodes.len()];
        for (old, &new) in new_id.iter().enumerate() {
            nodes[new as usize] = self.nodes[old];
        }
        self.nodes = nodes;
        for tet in &mut self.tets {
            *tet = tet.map(|n| new_id[n as usize]);
        }
        for set in self.node_sets.values_mut() {
            for n in set.iter_mut() {
                *n = new_id[*n as usize];
            }
            set.sort_unstable();
        }
    }
}

/// Orders `elements` by recursive coordinate bisection: each part is split at the median of its
/// centroids along the axis of its largest extent, the lower half first.
fn bisect(elements: &mut [u32], centroids: &[Vector3<f64>]) {
    if elements.len() <= SMALLEST_PART {
        elements.sort_unstable();
        return;
    }
    let (lo, hi) = elements.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), &e| {
            let c = &centroids[e as usize];
            (lo.inf(c), hi.sup(c))
        },
    );
    let axis = (hi - lo).imax();
    let key = |e: &u32| (centroids[*e as usize][axis], *e);
    let by_key = |a: &u32, b: &u32| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0).then(ka.1.cmp(&kb.1))
    };
    let middle = elements.len() / 2;
    elements.select_nth_unstable_by(middle, by_key);
    let (lower, upper) = elements.split_at_mut(middle);
    bisect(lower, centroids);
    bisect(upper, centroids);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distributed::NodePlan;
    use crate::mesh::{box_mesh, BoxSpec};

    /// Nodes that the elements of the two halves of `mesh` share, as the distributed runs count
    /// them ([`NodePlan::shared_nodes`]).
    fn shared_by_halves(mesh: &Mesh) -> usize {
        let half = mesh.tets.len() / 2;
        let ranges = [0..half, half..mesh.tets.len()];
        NodePlan::new(&mesh.tets, mesh.nodes.len(), &ranges, 0, &[]).shared_nodes()
    }

    /// A box mesh with its elements and nodes numbered at random (a deterministic shuffle).
    fn scrambled_box(divisions: usize) -> Mesh {
        let mut mesh = box_mesh(&BoxSpec {
            origin: [0.0; 3],
            size: [2.0, 1.0, 1.0],
            divisions: [2 * divisions, divisions, divisions],
            mirror: Vec::new(),
        });
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        for i in (1..mesh.tets.len()).rev() {
            let j = next(i + 1);
            mesh.tets.swap(i, j);
        }
        let mut perm: Vec<u32> = (0..mesh.nodes.len() as u32).collect();
        for i in (1..perm.len()).rev() {
            let j = next(i + 1);
            perm.swap(i, j);
        }
        let mut nodes = vec![Vector3::zeros(); mesh.nodes.len()];
        for (old, &new) in perm.iter().enumerate() {
            nodes[new as usize] = mesh.nodes[old];
        }
        mesh.nodes = nodes;
        for tet in &mut mesh.tets {
            *tet = tet.map(|n| perm[n as usize]);
        }
        mesh.node_sets
            .insert("corner".into(), vec![perm[0], perm[perm.len() - 1]]);
        mesh
    }

    #[test]
    fn renumbering_keeps_the_mesh_and_its_node_sets() {
        let before = scrambled_box(6);
        let mut after = before.clone();
        after.renumber_spatially();
        assert_eq!(after.nodes.len(), before.nodes.len());
        // The same elements (as sets of corner coordinates, in the same corner order, so every
        // volume keeps its sign) and the same named points.
        let key = |m: &Mesh, e: usize| {
            m.element_nodes(e)
                .map(|x| [x.x.to_bits(), x.y.to_bits(), x.z.to_bits()])
        };
        let mut a: Vec<_> = (0..before.tets.len()).map(|e| key(&before, e)).collect();
        let mut b: Vec<_> = (0..after.tets.len()).map(|e| key(&after, e)).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
        let points = |m: &Mesh| {
            let mut p: Vec<_> = m.node_sets["corner"]
                .iter()
                .map(|&n| {
                    let x = m.nodes[n as usize];
                    [x.x.to_bits(), x.y.to_bits(), x.z.to_bits()]
                })
                .collect();
            p.sort_unstable();
            p
        };
        assert_eq!(points(&before), points(&after));
        after.validate("renumbered", 1e-6).unwrap();
        // Deterministic: renumbering again from the same input gives the same ids.
        let mut again = before.clone();
        again.renumber_spatially();
        assert_eq!(again.tets, after.tets);
        assert_eq!(again.nodes, after.nodes);
    }

    #[test]
    fn halves_of_a_renumbered_mesh_share_only_a_cross_section() {
        let divisions = 8;
        let mut mesh = scrambled_box(divisions);
        let half = mesh.tets.len() / 2;
        let scattered = shared_by_halves(&mesh);
        mesh.renumber_spatially();
        let compact = shared_by_halves(&mesh);
        // The first bisection cuts the 16 x 8 x 8 box across x at its middle: one plane of
        // 9 x 9 nodes.
        let section = (divisions + 1) * (divisions + 1);
        assert_eq!(compact, section, "shared {compact}, scattered {scattered}");
        assert!(scattered > 10 * section, "scattered {scattered}");
        // And the nodes of each half come first in its own order: the first half's nodes are
        // the lowest ids but for those it shares.
        let first_half_nodes = mesh.tets[..half].iter().flatten().max().copied().unwrap();
        assert!((first_half_nodes as usize) < mesh.nodes.len() / 2 + section);
    }
}
