//! How an explicit run stops early: the output computed so far written by the observers, then
//! the error: the instability report naming the most strained element, or the halt an observer
//! asked for (a time limit, a signal).

use super::ExplicitSolver;
use crate::dynamics::InstabilityReport;
use crate::error::SolverError;
use crate::kinematics::green_lagrange_from_h;
use crate::output::{Halt, ObserverSet};

impl<'p> ExplicitSolver<'p> {
    /// Has the observers write what was computed (and a last field frame, if the state is
    /// finite), then builds the error that stops the run.
    pub(super) fn stop(
        &mut self,
        (reason, element): (String, Option<usize>),
        observers: &mut ObserverSet,
    ) -> SolverError {
        // The state at the stop may hold NaN; the last good frame is already on disk.
        let wants_fields = self.on_any_rank(observers.wants_fields());
        if wants_fields
            && self
                .whole(&self.u)
                .iter()
                .all(|u| u.iter().all(|x| x.is_finite()))
        {
            // What could not be written is left out of the report's list; the error is the
            // instability.
            let _ = self.field_frame(observers);
        }
        let _ = observers.finish();
        let written = observers.written.clone();
        let e = self.energies;
        SolverError::Unstable(Box::new(InstabilityReport {
            reason,
            step: self.step,
            time: self.time,
            element,
            kinetic: e.kinetic,
            internal_work: e.internal_work,
            external_work: e.external_work,
            energy_error: e.balance_error(),
            time_step: self.dt,
            critical_time_step: self.dt_critical,
            written,
        }))
    }

    /// Has the observers write what was computed, then builds the error for the halt one of them
    /// asked for. A failed write stops an interrupted run with that error instead; a run past its
    /// time limit reports the limit.
    pub(super) fn halt(&mut self, halt: Halt, observers: &mut ObserverSet) -> SolverError {
        let finished = observers.finish();
        match halt {
            Halt::TimeLimit { limit_s } => SolverError::TimeLimit {
                limit_s,
                step: self.step,
                time: self.time,
            },
            Halt::Interrupted => match finished {
                Err(e) => e,
                Ok(()) => SolverError::Interrupted {
                    step: self.step,
                    time: self.time,
                },
            },
        }
    }

    /// The element with the largest Green-Lagrange strain norm (or a non-finite one), of all
    /// ranks' (collective).
    pub(super) fn most_strained_element(&self) -> Option<usize> {
        let model = &self.problem.model;
        let u = self.whole(&self.u);
        let mut worst: Option<(f64, usize)> = None;
        // A rank that keeps its own elements' connectivity looks at those, and the ranks agree.
        for e in model.tets.stored_range() {
            let h = model.strain_gradient(e, &*u);
            let norm = green_lagrange_from_h(&h).norm();
            let norm = if norm.is_finite() {
                norm
            } else {
                f64::INFINITY
            };
            if worst.is_none_or(|(w, _)| norm > w) {
                worst = Some((norm, e));
            }
        }
        let Some(share) = &self.ranks else {
            return worst.map(|(_, e)| e);
        };
        // The largest norm (non-negative: its bits order as its values), then the first element
        // that reaches it, as the scan over every element in order finds it.
        let comm = share.comm();
        let largest = comm.max_u64(worst.map_or(0, |(w, _)| w.to_bits()));
        let first = comm.max_u64(match worst {
            Some((w, e)) if w.to_bits() == largest => u64::MAX - e as u64,
            _ => 0,
        });
        (first != 0).then(|| (u64::MAX - first) as usize)
    }
}
