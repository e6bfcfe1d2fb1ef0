//! Runs over several ranks (processes) that give the bitwise history of the one-process run
//! (issue 22).
//!
//! **Decomposition.** Rank `r` owns the elements of one range of consecutive ids
//! ([`element_ranges`]): it alone computes their forces and advances their material history, and
//! it holds the history of those elements only (`crate::model::BodyHistory::held`): its piece of
//! a field frame and its checkpoint read its own elements, so no rank ever gathers another's.
//! Consecutive ids because the one-process assembly folds each node's forces in ascending element
//! order (`model/assembly.rs`): with ranges, every contribution of rank `r` to a node precedes
//! every one of rank `r + 1`, so a node's fold is the fold of its owner (the rank of its first
//! element) continued by the single contributions of the higher ranks, which the owner's partial
//! sum cannot absorb but a receiver can append in order ([`ForceExchange`]). The box meshes number
//! their cells slab by slab, so the ranges are slabs; a mesh whose ids wander would give ranges
//! with a large surface, slower but still exact.
//!
//! **Nodes.** Each rank integrates the nodes of its elements ([`NodePlan`]). The nodes that two
//! ranks share, and those that every rank needs whole (the contact surfaces and the elements
//! under them, probed nodes), are *exchanged*: their contributions travel once per step, and
//! every rank that integrates such a node (the ranks using a shared node, every rank for one
//! needed whole) completes its force as above and integrates it alike, so contact is solved on
//! every rank from the same state and agrees bit for bit wherever the partition cuts the contact
//! zone. Prescribed nodes are integrated where they are used; the history rows gather their
//! reactions. Sums over nodes (energies, momenta) are folds over fixed blocks of node ids,
//! *leaves* ([`NODE_LEAF`]), one process or many: each leaf is summed by one rank that
//! integrates all its nodes (a leaf that no rank holds whole is exchanged and integrated by
//! every rank), and every rank folds the leaves' shares in leaf order. The stored energy is likewise folded over blocks
//! of elements, which the element ranges keep whole. A rank stores the nodal values of its active
//! nodes only ([`crate::nodal::NodeField`]: pages of [`crate::nodal::NODE_PAGE`] ids, indexed by
//! global id), so output that reads every node (history rows need only exchanged nodes, sums and
//! the gathered reactions; field frames, snapshots and the end of a run do) gathers a whole copy from the ranks that sum
//! the nodes' leaves.
//!
//! **Collectives.** [`Communicator`] is the few collective operations the run needs. The MPI one
//! (`mpi` feature, `mpi_world.rs`) runs under `mpirun`; [`ThreadGroup`] runs the ranks as threads
//! of one process, for tests that need no MPI installation.

mod exchange;
#[cfg(feature = "mpi")]
mod mpi_world;
mod nodes;
mod threads;

use std::ops::Range;

pub use exchange::ForceExchange;
#[cfg(feature = "mpi")]
pub use mpi_world::MpiWorld;
pub use nodes::{NodePlan, NODE_LEAF};
pub use threads::ThreadGroup;

use crate::model::ELEMENT_LEAF;

/// The collective operations of a distributed run. Every rank calls each one in the same order
/// (they are collective): the run's control flow is the same on every rank because every
/// decision is taken on values all ranks share (the folded energies, the exchanged nodes).
pub trait Communicator: Send + Sync {
    /// This process's rank, `0..size()`.
    fn rank(&self) -> usize;
    /// Number of ranks.
    fn size(&self) -> usize;
    /// Concatenates every rank's `mine` in rank order into `out` (`counts[r]` values from rank
    /// `r`, `out.len()` their sum).
    fn all_gather_f64(&self, mine: &[f64], counts: &[usize], out: &mut [f64]);
    /// [`Self::all_gather_f64`] of `f32` values.
    fn all_gather_f32(&self, mine: &[f32], counts: &[usize], out: &mut [f32]);
    /// [`Self::all_gather_f64`] of `u32` values (node ids).
    fn all_gather_u32(&self, mine: &[u32], counts: &[usize], out: &mut [u32]);
    /// The largest of every rank's `value`.
    fn max_u64(&self, value: u64) -> u64;
}

/// The element ranges of `size` ranks over `elements` elements of equal cost: consecutive ids,
/// as equal as whole blocks of [`ELEMENT_LEAF`] elements allow.
pub fn element_ranges(elements: usize, size: usize) -> Vec<Range<usize>> {
    element_ranges_by_cost(elements, size, |_| 1.0)
}

/// The element ranges of `size` ranks over `elements` elements, element `e` costing `cost(e)`:
/// consecutive ids, each range ending on a block of [`ELEMENT_LEAF`] elements (so that each
/// block's share of a sum over elements is computed by one rank), at the block boundary nearest
/// to an equal share `r / size` of the total cost.
pub fn element_ranges_by_cost(
    elements: usize,
    size: usize,
    cost: impl Fn(usize) -> f64,
) -> Vec<Range<usize>> {
    let size = size.max(1);
    // The cost before each block boundary.
    let mut before = vec![0.0];
    for start in (0..elements).step_by(ELEMENT_LEAF) {
        let block: f64 = (start..(start + ELEMENT_LEAF).min(elements))
            .map(&cost)
            .sum();
        before.push(before[before.len() - 1] + block);
    }
    let total = before[before.len() - 1];
    let end = |r: usize| {
        if r == size {
            return elements;
        }
        let target = total * r as f64 / size as f64;
        let next = before
            .partition_point(|&c| c < target)
            .min(before.len() - 1);
        // The nearer of the boundaries on either side of the target.
        let b = if next > 0 && target - before[next - 1] < before[next] - target {
            next - 1
        } else {
            next
        };
        (b * ELEMENT_LEAF).min(elements)
    };
    (0..size).map(|r| end(r)..end(r + 1)).collect()
}

#[cfg(test)]
mod tests;
