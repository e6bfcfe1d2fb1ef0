//! Runs over several ranks (processes) that give the bitwise history of the one-process run
//! (issue 22).
//!
//! **Decomposition.** Rank `r` owns the elements of one range of consecutive ids
//! ([`element_ranges`]): it alone computes their forces and advances their material history.
//! Consecutive ids because the one-process assembly folds each node's forces in ascending element
//! order (`model/assembly.rs`): with ranges, every contribution of rank `r` to a node precedes
//! every one of rank `r + 1`, so a node's fold is the fold of its owner (the rank of its first
//! element) continued by the single contributions of the higher ranks, which the owner's partial
//! sum cannot absorb but a receiver can append in order ([`ForceExchange`]). The box meshes number
//! their cells slab by slab, so the ranges are slabs; a mesh whose ids wander would give ranges
//! with a large surface, slower but still exact.
//!
//! **Replicated nodes.** Every rank keeps every node's displacement and velocity and integrates
//! them all from the same forces, so contact, boundary conditions, energies, momenta, reactions
//! and probes run unchanged and agree bit for bit across ranks; only the element loop, the
//! expensive part with the microplane concrete (70 times a linear element's cost), is divided.
//! What that costs is one all-gather of the nodal forces per step and the node loops on every
//! rank: the scaling limit of this first decomposition, measured in the README.
//!
//! **Collectives.** [`Communicator`] is the few collective operations the run needs. The MPI one
//! (`mpi` feature, `mpi_world.rs`) runs under `mpirun`; [`ThreadGroup`] runs the ranks as threads
//! of one process, for tests that need no MPI installation.

mod exchange;
mod history;
#[cfg(feature = "mpi")]
mod mpi_world;
mod threads;

use std::ops::Range;

pub use exchange::ForceExchange;
pub use history::gather_history;
#[cfg(feature = "mpi")]
pub use mpi_world::MpiWorld;
pub use threads::ThreadGroup;

/// The collective operations of a distributed run. Every rank calls each one in the same order
/// (they are collective): the run's control flow is the same on every rank because all of them
/// hold the same nodal state.
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
    /// The largest of every rank's `value`.
    fn max_u64(&self, value: u64) -> u64;
}

/// The element ranges of `size` ranks over `elements` elements: consecutive ids, as equal as
/// integers allow (rank `r` from `r n / size` to `(r + 1) n / size`).
pub fn element_ranges(elements: usize, size: usize) -> Vec<Range<usize>> {
    let size = size.max(1);
    (0..size)
        .map(|r| r * elements / size..(r + 1) * elements / size)
        .collect()
}

#[cfg(test)]
mod tests;
