//! The state one rank of a distributed run ([`super::ExplicitSolver::new_rank`]) holds between
//! two steps, for its own checkpoint ([`crate::restart`]): what its next steps read and nothing
//! the other ranks hold. A rank reads and writes the nodal values of its *active* nodes only
//! (its elements' nodes and the exchanged ones, `crate::distributed::NodePlan`), the only ones its
//! nodal fields store besides the rest of their pages (`crate::nodal::NodeField`), and the
//! material history of its own elements only. So a rank's part is those values, in the
//! order of its active runs and element range, with the values every rank shares (the step and
//! time, the folded energy ledger, the contact totals, the output schedule).

use std::ops::Range;

use super::{ExplicitSolver, OutputSchedule, RestartState, ScheduleRecord};
use crate::error::{Result, SolverError};
use crate::model::{body_part, MaterialHistory};
use crate::nodal::NodeField;

impl<'p> ExplicitSolver<'p> {
    /// The nodes this rank integrates, as ascending runs of ids (every node on one process).
    pub fn active_nodes(&self) -> &[Range<usize>] {
        self.nodes.active()
    }

    /// This rank's part of the state between two steps ([`RestartState`] whose nodal vectors
    /// hold the values of [`Self::active_nodes`] one run after the other, and whose histories
    /// hold the elements of [`Self::rank_elements`] only), with the run's output schedule. On
    /// one process: the whole state.
    pub fn rank_restart_state(&self, schedule: &OutputSchedule) -> RestartState {
        let Some(elements) = self.rank_elements() else {
            return self.restart_state(schedule);
        };
        let active = self.nodes.active();
        let pick = |v: &NodeField<nalgebra::Vector3<f64>>| -> Vec<nalgebra::Vector3<f64>> {
            active
                .iter()
                .flat_map(|r| v.run(r.clone()).iter().copied())
                .collect()
        };
        // The rank holds the history of its own elements only (`Self::new_rank`).
        let model = &self.problem.model;
        for (body, h) in model.bodies.iter().zip(&self.history.bodies) {
            if let Some(h) = h {
                assert_eq!(h.held(), body_part(&body.elements, &elements));
            }
        }
        let history = self.history.clone();
        RestartState {
            u: pick(&self.u),
            v_half: pick(&self.v_half),
            v_full: pick(&self.v_full),
            du_prev: pick(&self.du_prev),
            reaction: pick(&self.reaction),
            step: self.step,
            time: self.time,
            time_step: self.dt,
            step_origin: self.step_origin,
            time_origin: self.time_origin,
            dt_before_resume: self.dt_before_resume,
            energies: self.energies,
            pending: self.pending,
            history,
            contact_totals: self.contact_totals,
            schedule: ScheduleRecord::from(schedule),
        }
    }

    /// Puts back this rank's part `state` ([`Self::rank_restart_state`] of the same rank of the
    /// same run) into this new, distributed solver, which then goes on as the one that wrote
    /// it; returns the run's output schedule. Errors when the part does not
    /// fit this rank (its node count, its histories) or the time step differs.
    pub fn restore_rank(&mut self, state: RestartState) -> Result<OutputSchedule> {
        let misfit = |message: String| SolverError::InvalidScene {
            entity: "checkpoint".into(),
            message,
        };
        let Some(elements) = self.rank_elements() else {
            return Err(misfit("a rank's part restored on one process".into()));
        };
        let active: Vec<Range<usize>> = self.nodes.active().to_vec();
        let count: usize = active.iter().map(Range::len).sum();
        let lengths = state.nodal_lengths();
        if lengths.iter().any(|&l| l != count) {
            return Err(misfit(format!(
                "{lengths:?} nodal values for the {count} nodes this rank integrates"
            )));
        }
        if self.dt.to_bits() != state.time_step.to_bits() || state.step < state.step_origin {
            return Err(misfit(format!(
                "written with a time step of {:e} s at step {} (segment from step {}), but this \
                 scene gives {:e} s",
                state.time_step, state.step, state.step_origin, self.dt
            )));
        }
        self.restore_clock_and_ledgers(&state);
        self.restore_rank_history(&elements, state.history)?;
        for (whole, part) in [
            (&mut self.u, state.u),
            (&mut self.v_half, state.v_half),
            (&mut self.v_full, state.v_full),
            (&mut self.du_prev, state.du_prev),
            (&mut self.reaction, state.reaction),
        ] {
            let mut values = part.into_iter();
            for i in active.iter().flat_map(Clone::clone) {
                whole[i] = values.next().unwrap_or_default();
            }
        }
        Ok(OutputSchedule::from(state.schedule))
    }

    /// Takes `part`, the histories of this rank's `elements`, as the solver's.
    fn restore_rank_history(
        &mut self,
        elements: &Range<usize>,
        part: MaterialHistory,
    ) -> Result<()> {
        let misfit = || SolverError::InvalidScene {
            entity: "checkpoint".into(),
            message: "its material histories do not fit this rank's bodies and elements".into(),
        };
        let model = &self.problem.model;
        if part.bodies.len() != model.bodies.len() {
            return Err(misfit());
        }
        for ((body, whole), part) in model
            .bodies
            .iter()
            .zip(self.history.bodies.iter_mut())
            .zip(part.bodies)
        {
            match (whole, part) {
                (None, None) => {}
                (Some(whole), Some(mut part)) => {
                    let mine = body_part(&body.elements, elements);
                    let len = whole.state_len;
                    if part.state_len != len
                        || part.values.len() != mine.len() * len
                        || part.cauchy.len() != mine.len()
                    {
                        return Err(misfit());
                    }
                    part.first = mine.start;
                    *whole = part;
                }
                _ => return Err(misfit()),
            }
        }
        Ok(())
    }
}
