//! Each boundary condition's reaction on a rank of a distributed run, summed over the
//! condition's nodes in the one-process order although its nodes lie on several ranks.
//!
//! A rank integrates a condition's nodes only where its elements use them (a pushed end face
//! lies across every rank of a slab partition): replicating them on every rank would store, for
//! every scattered face node, a page of nodal vectors. The history row needs the reaction of
//! every node of every condition, so at each row the rank that sums a node's leaf
//! ([`NodePlan::leaf_ranks`], which integrates it) sends its reaction, every rank gathers them, and
//! the sums run over the gathered values in the conditions' node order
//! ([`Problem::push_condition_reactions`]): the one-process sums, bit for bit.

use std::ops::Index;

use nalgebra::Vector3;

use crate::distributed::{Communicator, NodePlan, NODE_LEAF};
use crate::nodal::NodeField;
use crate::problem::Problem;

/// Values at a few nodes (the conditions' nodes), read by global node id.
struct AtNodes<'a, T> {
    /// The nodes, ascending.
    ids: &'a [u32],
    values: &'a [T],
}

impl<T> Index<usize> for AtNodes<'_, T> {
    type Output = T;

    fn index(&self, a: usize) -> &T {
        let i = self
            .ids
            .binary_search(&(a as u32))
            .unwrap_or_else(|_| panic!("node {a} is not a boundary condition's node"));
        &self.values[i]
    }
}

/// The gather of the conditions' reactions for the history rows of one rank.
pub(super) struct ConditionReactions {
    /// The conditions' nodes, ascending.
    ids: Vec<u32>,
    /// The components each condition owns at each of `ids` (the problem's constraint map there).
    owner: Vec<[Option<u16>; 3]>,
    /// The rank that sends each node's reaction: the one that sums its leaf.
    sender: Vec<u32>,
    /// Values (`f64`) each rank sends.
    counts: Vec<usize>,
    rank: usize,
}

impl ConditionReactions {
    /// The gather for `problem`'s conditions, with the constraint map `constraint_map` (whole) and
    /// the ranks' node plan `plan` of rank `rank` of `ranks`.
    pub(super) fn new(
        problem: &Problem,
        constraint_map: &[[Option<u16>; 3]],
        plan: &NodePlan,
        rank: usize,
        ranks: usize,
    ) -> Self {
        let mut ids: Vec<u32> = problem
            .constraints
            .iter()
            .flat_map(|c| c.nodes.iter().copied())
            .collect();
        ids.sort_unstable();
        ids.dedup();
        let leaf_ranks = plan.leaf_ranks();
        let sender: Vec<u32> = ids
            .iter()
            .map(|&a| leaf_ranks[a as usize / NODE_LEAF])
            .collect();
        let mut counts = vec![0; ranks];
        for &r in &sender {
            counts[r as usize] += 3;
        }
        let owner = ids.iter().map(|&a| constraint_map[a as usize]).collect();
        Self {
            ids,
            owner,
            sender,
            counts,
            rank,
        }
    }

    /// Appends each condition's reaction, as [`Problem::push_condition_reactions`] on one
    /// process, from every rank's `reaction` at the nodes it integrates. Collective.
    pub(super) fn push(
        &self,
        problem: &Problem,
        comm: &dyn Communicator,
        reaction: &NodeField<Vector3<f64>>,
        row: &mut Vec<f64>,
    ) {
        let ids = &self.ids;
        let mut send = Vec::with_capacity(self.counts[self.rank]);
        for (&a, &r) in ids.iter().zip(&self.sender) {
            if r as usize == self.rank {
                send.extend(reaction[a as usize].iter());
            }
        }
        let mut gathered = vec![0.0; self.counts.iter().sum()];
        comm.all_gather_f64(&send, &self.counts, &mut gathered);
        // Each rank's values start where the lower ranks' end, in ascending node order.
        let mut next: Vec<usize> = self
            .counts
            .iter()
            .scan(0, |start, &c| {
                let here = *start;
                *start += c;
                Some(here)
            })
            .collect();
        let values: Vec<Vector3<f64>> = self
            .sender
            .iter()
            .map(|&r| {
                let i = next[r as usize];
                next[r as usize] += 3;
                Vector3::new(gathered[i], gathered[i + 1], gathered[i + 2])
            })
            .collect();
        let reactions = AtNodes {
            ids,
            values: &values,
        };
        let owner = AtNodes {
            ids,
            values: &self.owner,
        };
        problem.push_condition_reactions(row, &reactions, &owner);
    }
}
