//! The explicit run over several ranks (`crate::distributed`): each rank computes the forces of
//! its elements, the ranks complete each other's nodal forces, and everything else runs on every
//! rank from the same nodal state.

use std::ops::Range;

use nalgebra::Vector3;

use super::ExplicitSolver;
use crate::distributed::{element_ranges, gather_history, Communicator, ForceExchange};
use crate::error::{Result, SolverError};

/// A rank's part of a distributed run.
pub(super) struct RankShare<'p> {
    comm: &'p dyn Communicator,
    ranges: Vec<Range<usize>>,
    exchange: ForceExchange,
    /// This rank's contributions to nodes of lower ranks, reused from step to step.
    foreign: Vec<Vector3<f64>>,
}

impl<'p> ExplicitSolver<'p> {
    /// Runs this solver as rank `comm.rank()` of `comm.size()`: from the next step on it computes
    /// the forces and advances the history of its elements only ([`element_ranges`]) and
    /// completes the nodal forces with the other ranks, which must make the same call on the same
    /// problem. One rank changes nothing. A run that remeshes cannot be distributed.
    pub fn distribute(&mut self, comm: &'p dyn Communicator) -> Result<()> {
        if comm.size() <= 1 {
            return Ok(());
        }
        let model = &self.problem.model;
        if model.carried.is_some() {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing".into(),
                message: "a run that remeshes runs on one rank (no mpirun)".into(),
            });
        }
        let ranges = element_ranges(model.element_count(), comm.size());
        model.restrict_assembly(ranges[comm.rank()].clone());
        let exchange = ForceExchange::new(&model.tets, model.node_count(), &ranges, comm.rank());
        self.ranks = Some(RankShare {
            comm,
            ranges,
            exchange,
            foreign: Vec::new(),
        });
        Ok(())
    }

    /// The rank and the number of ranks (0 and 1 for a run on one process).
    pub fn rank(&self) -> (usize, usize) {
        self.ranks
            .as_ref()
            .map_or((0, 1), |r| (r.comm.rank(), r.comm.size()))
    }

    /// The elements of this rank in a distributed run (`None` on one process).
    pub fn rank_elements(&self) -> Option<Range<usize>> {
        self.ranks.as_ref().map(|r| r.ranges[r.comm.rank()].clone())
    }

    /// `f64` values each rank sends per step to complete the forces (empty on one process).
    pub fn exchange_counts(&self) -> &[usize] {
        self.ranks.as_ref().map_or(&[], |r| r.exchange.counts())
    }

    /// Completes the internal forces after this rank's element loop and agrees on the lowest
    /// inverted element of all ranks (collective; nothing on one process).
    pub(super) fn complete_forces(&mut self, inverted: Option<usize>) -> Option<usize> {
        let Some(share) = self.ranks.as_mut() else {
            return inverted;
        };
        self.problem.model.foreign_contributions(&mut share.foreign);
        share
            .exchange
            .complete(share.comm, &share.foreign, &mut self.f_int);
        // The lowest element is the largest `u64::MAX - e`; 0 for none.
        let lowest = share
            .comm
            .max_u64(inverted.map_or(0, |e| u64::MAX - e as u64));
        (lowest != 0).then(|| (u64::MAX - lowest) as usize)
    }

    /// Whether `mine` holds on any rank (collective; `mine` on one process).
    pub(super) fn on_any_rank(&self, mine: bool) -> bool {
        match &self.ranks {
            Some(share) => share.comm.max_u64(u64::from(mine)) != 0,
            None => mine,
        }
    }

    /// Gives every rank the whole material history before output reads it (collective; nothing
    /// on one process or without a history).
    pub(super) fn gather_history(&mut self) {
        if let Some(share) = &self.ranks {
            if !self.history.is_empty() {
                gather_history(
                    share.comm,
                    &self.problem.model,
                    &share.ranges,
                    &mut self.history,
                );
            }
        }
    }
}
