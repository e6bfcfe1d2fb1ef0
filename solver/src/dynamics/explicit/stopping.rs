//! How an explicit run stops early: the output computed so far written, then the instability
//! report naming the most strained element.

use std::path::PathBuf;

use super::ExplicitSolver;
use crate::dynamics::InstabilityReport;
use crate::error::SolverError;
use crate::kinematics::{displacement_gradient, green_lagrange_from_h};
use crate::output::history::HistoryTable;
use crate::output::vtu::PvdWriter;

impl<'p> ExplicitSolver<'p> {
    /// Writes what was computed, then builds the error that stops the run.
    pub(super) fn stop(
        &mut self,
        (reason, element): (String, Option<usize>),
        history: &mut HistoryTable,
        pvd: Option<&mut PvdWriter>,
        written: &mut Vec<PathBuf>,
    ) -> SolverError {
        if let Some(path) = self.history_path() {
            if history.write_csv(&path).is_ok() {
                written.push(path);
            }
        }
        if let Some(writer) = pvd {
            // The state at the stop may hold NaN; the last good frame is already on disk.
            if self.u.iter().all(|u| u.iter().all(|x| x.is_finite())) {
                if let Ok(p) = self.write_frame(writer) {
                    written.push(p);
                }
            }
        }
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
            written: written.clone(),
        }))
    }

    /// The element with the largest Green-Lagrange strain norm (or a non-finite one).
    pub(super) fn most_strained_element(&self) -> Option<usize> {
        let model = &self.problem.model;
        let mut worst: Option<(f64, usize)> = None;
        for e in 0..model.element_count() {
            let h =
                displacement_gradient(&model.element_displacements(e, &self.u), &model.grad_n[e]);
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
        worst.map(|(_, e)| e)
    }
}
