//! The whole state of a run between two steps, for a checkpoint from which a later process goes
//! on bit for bit ([`crate::restart`]). Unlike [`super::RunState`] (a remeshing's hand-over, which
//! starts a new segment with its own time origin), it keeps the segment's origin, so the resumed
//! solver forms `time = time_origin + (step - step_origin) dt` with the same numbers, and the
//! output schedule, so history rows and frames fall due at the same steps.
//!
//! The wall time per phase is not kept: a resumed run reports the time of its own process.
//! What is not here is rebuilt identically from the problem: the time step and its stable limit,
//! the constraint map, the contact buffers. Those buffers carry nothing from one step to the
//! next that the next step reads: the contact solvers start from zero multipliers (no warm
//! start), the detector's boxes give answers bitwise those of a fresh detection, and the forces
//! and position surpluses of the nodes the last step touched are zeroed before they are read.

use nalgebra::Vector3;

use super::{ExplicitSolver, Lent, OutputSchedule};
use crate::dynamics::settings::ContactTotals;
use crate::dynamics::{EnergyLedger, ExplicitSettings, OutputSettings, StopProgress};
use crate::error::{Result, SolverError};
use crate::model::MaterialHistory;
use crate::nodal::NodeField;
use crate::problem::Problem;

/// The output schedule's numbers ([`OutputSchedule`]), as plain fields.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ScheduleRecord {
    /// Time at which the next history row falls due (s).
    pub next_history: f64,
    /// Time at which the next field frame falls due (s).
    pub next_field: f64,
    /// Time at which the next snapshot falls due (s).
    pub next_snapshot: f64,
    /// Largest energy scale so far (J).
    pub max_scale: f64,
    /// Largest absolute energy balance error so far (J).
    pub max_abs_error: f64,
    /// Steps flagged by the mesh stability check.
    pub flags: usize,
    /// Steps taken over every segment.
    pub steps: usize,
    /// Where the run stands with its `stop_when`.
    pub stop: StopProgress,
}

impl From<&OutputSchedule> for ScheduleRecord {
    fn from(s: &OutputSchedule) -> Self {
        Self {
            next_history: s.next_history,
            next_field: s.next_field,
            next_snapshot: s.next_snapshot,
            max_scale: s.max_scale,
            max_abs_error: s.max_abs_error,
            flags: s.flags,
            steps: s.steps,
            stop: s.stop,
        }
    }
}

impl From<ScheduleRecord> for OutputSchedule {
    fn from(s: ScheduleRecord) -> Self {
        Self {
            next_history: s.next_history,
            next_field: s.next_field,
            next_snapshot: s.next_snapshot,
            max_scale: s.max_scale,
            max_abs_error: s.max_abs_error,
            flags: s.flags,
            steps: s.steps,
            stop: s.stop,
        }
    }
}

/// Everything a step reads that a previous step wrote, between two steps.
#[derive(Debug, Clone, PartialEq)]
pub struct RestartState {
    /// Displacement `u_n` (m).
    pub u: Vec<Vector3<f64>>,
    /// Velocity of the last half step `v_{n-1/2}` (m/s).
    pub v_half: Vec<Vector3<f64>>,
    /// Velocity of the last full step (m/s).
    pub v_full: Vec<Vector3<f64>>,
    /// The last displacement increment `u_n - u_{n-1}` (m).
    pub du_prev: Vec<Vector3<f64>>,
    /// Reaction forces of the last step at prescribed components (N); the next step recomputes
    /// them, kept so that the restored solver reads as the one that wrote the state.
    pub reaction: Vec<Vector3<f64>>,
    /// Steps completed.
    pub step: usize,
    /// Time reached (s).
    pub time: f64,
    /// The time step (s), checked against the one the resumed solver computes.
    pub time_step: f64,
    /// Step and time at which this segment's solver took the run over.
    pub step_origin: usize,
    /// See [`Self::step_origin`] (s).
    pub time_origin: f64,
    /// The time step before the segment's start, when it differed (s).
    pub dt_before_resume: Option<f64>,
    /// The energy ledger at the last step.
    pub energies: EnergyLedger,
    /// The half-interval works the next step completes.
    pub pending: EnergyLedger,
    /// The material histories.
    pub history: MaterialHistory,
    /// What contact did so far.
    pub contact_totals: ContactTotals,
    /// The output schedule.
    pub schedule: ScheduleRecord,
}

impl RestartState {
    /// The lengths of its nodal vectors: `u`, `v_half`, `v_full`, `du_prev`, `reaction`.
    pub(super) fn nodal_lengths(&self) -> [usize; 5] {
        [
            self.u.len(),
            self.v_half.len(),
            self.v_full.len(),
            self.du_prev.len(),
            self.reaction.len(),
        ]
    }
}

impl<'p> ExplicitSolver<'p> {
    /// The state between two steps with the run's output schedule (see [`RestartState`]).
    pub fn restart_state(&self, schedule: &OutputSchedule) -> RestartState {
        RestartState {
            u: self.whole(&self.u).into_owned(),
            v_half: self.whole(&self.v_half).into_owned(),
            v_full: self.whole(&self.v_full).into_owned(),
            du_prev: self.whole(&self.du_prev).into_owned(),
            reaction: self.whole(&self.reaction).into_owned(),
            step: self.step,
            time: self.time,
            time_step: self.dt,
            step_origin: self.step_origin,
            time_origin: self.time_origin,
            dt_before_resume: self.dt_before_resume,
            energies: self.energies,
            pending: self.pending,
            history: self.history.clone(),
            contact_totals: self.contact_totals,
            schedule: ScheduleRecord::from(schedule),
        }
    }

    /// A solver over `problem` that goes on from `state` as the solver that wrote it would
    /// have, and the run's output schedule. Errors when the state does not fit the problem (node
    /// count, histories) or the time step computed from the settings differs from the state's.
    pub fn restored(
        problem: &'p Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
        mut state: RestartState,
    ) -> Result<(Self, OutputSchedule)> {
        let misfit = |message: String| SolverError::InvalidScene {
            entity: "checkpoint".into(),
            message,
        };
        let n = problem.model.node_count();
        let lengths = state.nodal_lengths();
        if lengths.iter().any(|&l| l != n) {
            return Err(misfit(format!(
                "{lengths:?} nodal values for a model of {n} nodes: the checkpoint is of another \
                 mesh"
            )));
        }
        let fits = state.history.bodies.len() == problem.model.bodies.len()
            && problem
                .model
                .bodies
                .iter()
                .zip(&state.history.bodies)
                .all(|(b, h)| {
                    let len = b.material.history_len();
                    match h {
                        None => len == 0,
                        Some(h) => {
                            h.state_len == len
                                && h.values.len() == len * b.elements.len()
                                && h.cauchy.len() == b.elements.len()
                        }
                    }
                });
        if !fits {
            return Err(misfit(
                "its material histories do not fit the model's bodies and elements".into(),
            ));
        }
        if state.step < state.step_origin {
            return Err(misfit(format!(
                "step {} lies before its segment's first step {}",
                state.step, state.step_origin
            )));
        }
        let history = std::mem::take(&mut state.history);
        let mut solver =
            Self::with_history(Lent::Shared(problem), settings, output, history, None)?;
        if solver.dt.to_bits() != state.time_step.to_bits() {
            return Err(misfit(format!(
                "written with a time step of {:e} s, but this scene gives {:e} s",
                state.time_step, solver.dt
            )));
        }
        solver.restore_clock_and_ledgers(&state);
        solver.u = NodeField::dense(state.u);
        solver.v_half = NodeField::dense(state.v_half);
        solver.v_full = NodeField::dense(state.v_full);
        solver.du_prev = NodeField::dense(state.du_prev);
        solver.reaction = NodeField::dense(state.reaction);
        Ok((solver, OutputSchedule::from(state.schedule)))
    }

    /// The step, the time and the segment's origin, the time step forced before the resume,
    /// the energy ledgers and the contact totals of `state`: what a restored run reads besides
    /// its nodal values and histories, the same on one process and on every rank.
    pub(super) fn restore_clock_and_ledgers(&mut self, state: &RestartState) {
        self.step = state.step;
        self.time = state.time;
        self.step_origin = state.step_origin;
        self.time_origin = state.time_origin;
        self.dt_before_resume = state.dt_before_resume;
        self.energies = state.energies;
        self.pending = state.pending;
        self.contact_totals = state.contact_totals;
    }
}
