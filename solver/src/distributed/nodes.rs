//! Which nodes a rank keeps up to date, and the sums over nodes that do not depend on who
//! computes them.

use std::ops::Range;

use nalgebra::Vector3;

use super::Communicator;
use crate::nodal::{NodeField, NodeSlots};

/// Nodes per leaf: every sum over nodes (energies, momenta) is the fold, in leaf order, of the
/// folds over consecutive blocks of this many node ids, on one process as on many.
pub const NODE_LEAF: usize = 256;

/// A rank's nodes in a distributed run (module doc of `distributed`).
///
/// The rank integrates its *active* nodes: the nodes of its elements whose forces it assembles
/// alone, and the *exchanged* nodes it needs, whose forces the ranks complete from each other's
/// contributions ([`super::ForceExchange`]) and which every rank holding them therefore
/// integrates alike: the nodes shared between ranks (integrated by the ranks from the lowest to
/// the highest using them), and on every rank the nodes the caller replicates (contact surfaces
/// and layers, probes), nodes without elements, and the nodes of a leaf that no single rank
/// would otherwise hold whole. Each leaf has one rank that holds all its nodes; that rank
/// computes the leaf's share of every sum over nodes and sends it, so that every rank folds the
/// same shares in the same order.
#[derive(Debug, Clone)]
pub struct NodePlan {
    node_count: usize,
    /// Ascending runs of active node ids.
    active: Vec<Range<usize>>,
    /// Whether each node is exchanged (empty on one process: nothing is).
    exchanged: Vec<bool>,
    /// The leaves this rank sums, ascending.
    my_leaves: Vec<u32>,
    /// Active nodes outside this rank's leaves, as ascending runs.
    extra: Vec<Range<usize>>,
    /// Leaves summed by each rank.
    leaf_counts: Vec<usize>,
    /// Position of each leaf in the rank-major order of the gathered shares.
    leaf_slot: Vec<u32>,
    /// Nodes used by the elements of two ranks or more.
    shared_nodes: usize,
}

impl NodePlan {
    /// One process: every node active, every leaf this rank's.
    pub fn single(node_count: usize) -> Self {
        let leaves = node_count.div_ceil(NODE_LEAF);
        Self {
            node_count,
            active: std::iter::once(0..node_count).collect(),
            exchanged: Vec::new(),
            my_leaves: (0..leaves as u32).collect(),
            extra: Vec::new(),
            leaf_counts: vec![leaves],
            leaf_slot: (0..leaves as u32).collect(),
            shared_nodes: 0,
        }
    }

    /// The plan of rank `rank` when the ranks hold the element `ranges` (consecutive, in rank
    /// order) of a mesh of `tets` over `node_count` nodes, with the `replicated` nodes kept on
    /// every rank. Every rank builds the same plan.
    pub fn new(
        tets: &[[u32; 4]],
        node_count: usize,
        ranges: &[Range<usize>],
        rank: usize,
        replicated: &[u32],
    ) -> Self {
        const NONE: u32 = u32::MAX;
        // The lowest and highest rank using each node, and whether another one uses it too.
        let mut span = vec![(NONE, 0u32); node_count];
        let mut exchanged = vec![false; node_count];
        for (r, range) in ranges.iter().enumerate() {
            let r = r as u32;
            for tet in &tets[range.clone()] {
                for &a in tet {
                    let (first, last) = &mut span[a as usize];
                    if *first == NONE {
                        *first = r;
                    } else if *first != r {
                        exchanged[a as usize] = true;
                    }
                    *last = r;
                }
            }
        }
        let shared_nodes = exchanged.iter().filter(|&&x| x).count();
        // The ranks `span[a].0..=span[a].1` integrate node `a`: the ranks using it (and any
        // between, which complete its force from the same gathered contributions), and every
        // rank for a node without elements or replicated.
        let everyone = (0, ranges.len().saturating_sub(1) as u32);
        for (a, s) in span.iter_mut().enumerate() {
            if s.0 == NONE {
                (*s, exchanged[a]) = (everyone, true);
            }
        }
        for &a in replicated {
            (span[a as usize], exchanged[a as usize]) = (everyone, true);
        }
        // A leaf belongs to the lowest rank that integrates all its nodes or, where none does,
        // is integrated and exchanged by every rank (and summed by the first).
        let leaves = node_count.div_ceil(NODE_LEAF);
        let mut leaf_rank = vec![0u32; leaves];
        for (k, owner) in leaf_rank.iter_mut().enumerate() {
            let nodes = k * NODE_LEAF..((k + 1) * NODE_LEAF).min(node_count);
            let lowest = nodes.clone().map(|a| span[a].0).max().unwrap_or(0);
            let highest = nodes.clone().map(|a| span[a].1).min().unwrap_or(0);
            if lowest <= highest {
                *owner = lowest;
            } else {
                for a in nodes {
                    (span[a], exchanged[a]) = (everyone, true);
                }
            }
        }
        let is_mine = |a: usize| span[a].0 <= rank as u32 && rank as u32 <= span[a].1;
        let in_my_leaf = |a: usize| leaf_rank[a / NODE_LEAF] == rank as u32;
        let active = runs(node_count, is_mine);
        let extra = runs(node_count, |a| is_mine(a) && !in_my_leaf(a));
        let mut leaf_counts = vec![0usize; ranges.len()];
        for &r in &leaf_rank {
            leaf_counts[r as usize] += 1;
        }
        let mut next: Vec<u32> = leaf_counts
            .iter()
            .scan(0u32, |start, &c| {
                let here = *start;
                *start += c as u32;
                Some(here)
            })
            .collect();
        let leaf_slot = leaf_rank
            .iter()
            .map(|&r| {
                let slot = next[r as usize];
                next[r as usize] += 1;
                slot
            })
            .collect();
        Self {
            node_count,
            active,
            my_leaves: (0..leaves as u32)
                .filter(|&k| leaf_rank[k as usize] == rank as u32)
                .collect(),
            exchanged,
            extra,
            leaf_counts,
            leaf_slot,
            shared_nodes,
        }
    }

    /// Nodes used by the elements of two ranks or more: about one cross-section of the mesh
    /// per pair of neighbouring ranks when each rank's elements are compact, most nodes when
    /// the numbering wanders through the mesh (a body's `numbering: spatial` orders it by
    /// coordinate bisection).
    pub fn shared_nodes(&self) -> usize {
        self.shared_nodes
    }

    /// The nodes this rank integrates, as ascending runs of ids.
    pub fn active(&self) -> &[Range<usize>] {
        &self.active
    }

    /// Active nodes outside this rank's leaves, as ascending runs (none on one process).
    pub fn extra(&self) -> &[Range<usize>] {
        &self.extra
    }

    /// Whether each node's forces are completed from the ranks' contributions (empty on one
    /// process).
    pub fn exchanged(&self) -> &[bool] {
        &self.exchanged
    }

    /// The leaves this rank sums, ascending.
    pub fn my_leaves(&self) -> &[u32] {
        &self.my_leaves
    }

    /// The rank that sums each leaf, which integrates every node of it.
    pub fn leaf_ranks(&self) -> Vec<u32> {
        // Leaf slots are rank-major: rank `r` holds the slots from the sum of the lower ranks'
        // counts on.
        let mut rank_of_slot = Vec::with_capacity(self.leaf_slot.len());
        for (r, &count) in self.leaf_counts.iter().enumerate() {
            rank_of_slot.extend(std::iter::repeat_n(r as u32, count));
        }
        self.leaf_slot
            .iter()
            .map(|&slot| rank_of_slot[slot as usize])
            .collect()
    }

    /// The node ids of leaf `k`.
    pub fn leaf_nodes(&self, k: u32) -> Range<usize> {
        let start = k as usize * NODE_LEAF;
        start..(start + NODE_LEAF).min(self.node_count)
    }

    /// The fold over all leaves, in leaf order, of their shares `width` values each: `mine`
    /// holds this rank's, in the order of [`Self::my_leaves`]. Collective with `comm`.
    pub fn fold(&self, comm: Option<&dyn Communicator>, width: usize, mine: &[f64]) -> Vec<f64> {
        assert_eq!(
            mine.len(),
            width * self.my_leaves.len(),
            "one share per leaf"
        );
        let gathered;
        let all = match comm {
            Some(comm) if comm.size() > 1 => {
                let counts: Vec<usize> = self.leaf_counts.iter().map(|c| c * width).collect();
                let mut out = vec![0.0; counts.iter().sum()];
                comm.all_gather_f64(mine, &counts, &mut out);
                gathered = out;
                &gathered[..]
            }
            _ => mine,
        };
        let mut total = vec![0.0; width];
        for &slot in &self.leaf_slot {
            let share = &all[slot as usize * width..(slot as usize + 1) * width];
            for (t, s) in total.iter_mut().zip(share) {
                *t += s;
            }
        }
        total
    }

    /// The storage of this rank's node fields ([`NodeField`]): every node on one process, the
    /// pages of its active nodes on a rank.
    pub fn slots(&self) -> NodeSlots {
        if self.exchanged.is_empty() {
            NodeSlots::dense(self.node_count)
        } else {
            NodeSlots::paged(self.node_count, &self.active)
        }
    }

    /// Every node's value of `field` on every rank, each leaf's from the rank that sums it (the
    /// values of a node that several ranks integrate are the same on each). Collective.
    pub fn gather(
        &self,
        comm: &dyn Communicator,
        field: &NodeField<Vector3<f64>>,
    ) -> Vec<Vector3<f64>> {
        const WIDTH: usize = 3;
        let mut mine = Vec::new();
        for &k in &self.my_leaves {
            for a in self.leaf_nodes(k) {
                mine.extend(field[a].iter());
            }
        }
        // The leaves in gathered (rank-major) order, where each starts and what each rank sends.
        let mut by_slot = vec![0..0; self.leaf_slot.len()];
        for (k, &slot) in self.leaf_slot.iter().enumerate() {
            by_slot[slot as usize] = self.leaf_nodes(k as u32);
        }
        let mut counts = Vec::with_capacity(self.leaf_counts.len());
        let mut first = 0;
        for &c in &self.leaf_counts {
            counts.push(
                by_slot[first..first + c]
                    .iter()
                    .map(|r| r.len() * WIDTH)
                    .sum(),
            );
            first += c;
        }
        let mut all = vec![0.0; WIDTH * self.node_count];
        comm.all_gather_f64(&mine, &counts, &mut all);
        let mut whole = vec![Vector3::zeros(); self.node_count];
        let mut values = all.chunks_exact(WIDTH);
        for nodes in by_slot {
            for a in nodes {
                let v = values.next().expect("one value per node");
                whole[a] = Vector3::new(v[0], v[1], v[2]);
            }
        }
        whole
    }
}

/// The ascending runs of `0..n` where `keep` holds.
fn runs(n: usize, keep: impl Fn(usize) -> bool) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    for a in (0..n).filter(|&a| keep(a)) {
        match out.last_mut() {
            Some(run) if run.end == a => run.end += 1,
            _ => out.push(a..a + 1),
        }
    }
    out
}
