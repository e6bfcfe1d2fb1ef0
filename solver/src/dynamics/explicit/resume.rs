//! The state of a run taken out of one solver and given to another, for a remeshing between two
//! steps ([`crate::remesh::remesh_problem`]): the integrator borrows its problem, so a run that
//! changes its mesh goes on with a new solver over the new problem.

use nalgebra::Vector3;

use super::{ExplicitSolver, Lent};
use crate::dynamics::settings::{ContactTotals, PhaseTimes};
use crate::dynamics::{EnergyLedger, ExplicitSettings, OutputSettings};
use crate::error::{Result, SolverError};
use crate::model::MaterialHistory;
use crate::nodal::NodeField;
use crate::problem::Problem;

/// The state of the central-difference scheme between two steps (after a step's move to
/// `u_{n+1}`, before the next step's forces).
#[derive(Debug, Clone, PartialEq)]
pub struct RunState {
    /// Displacement `u_n` from the model's reference (m).
    pub u: Vec<Vector3<f64>>,
    /// Velocity of the last half step `v_{n-1/2}` (m/s).
    pub v_half: Vec<Vector3<f64>>,
    /// Velocity of the last full step `v_{n-1}` (m/s), as recorded.
    pub v_full: Vec<Vector3<f64>>,
    /// The last displacement increment `u_n - u_{n-1}` (m), which the next step's work closes.
    pub du_prev: Vec<Vector3<f64>>,
    /// Steps completed.
    pub step: usize,
    /// The time step of the last step (s), which with the resumed run's step sets the span of
    /// the first step after the resume.
    pub time_step: f64,
    /// Time reached (s).
    pub time: f64,
    /// The energy ledger at the last step.
    pub energies: EnergyLedger,
    /// The half-interval works the next step completes.
    pub pending: EnergyLedger,
    /// The material histories (bodies of microplane concrete), as the last step left them.
    pub history: MaterialHistory,
    /// Wall time of each phase so far, carried so that a run over several meshes reports its
    /// whole time.
    pub phases: PhaseTimes,
    /// What contact did so far.
    pub contact_totals: ContactTotals,
}

impl<'p> ExplicitSolver<'p> {
    /// The run's state between two steps (see [`RunState`]).
    pub fn state(&self) -> RunState {
        RunState {
            u: self.whole(&self.u).into_owned(),
            v_half: self.whole(&self.v_half).into_owned(),
            v_full: self.whole(&self.v_full).into_owned(),
            du_prev: self.whole(&self.du_prev).into_owned(),
            step: self.step,
            time_step: self.dt,
            time: self.time,
            energies: self.energies,
            pending: self.pending,
            history: self.history.clone(),
            phases: self.phases,
            contact_totals: self.contact_totals,
        }
    }

    /// [`Self::state`], moving the fields out instead of copying them (a remeshing run ends a
    /// segment so at each remeshing, and a microplane body's history is large).
    pub fn into_state(self) -> RunState {
        // A remeshing run is never distributed: its fields are dense.
        let dense = "a run on one process stores every node";
        RunState {
            u: self.u.into_dense().expect(dense),
            v_half: self.v_half.into_dense().expect(dense),
            v_full: self.v_full.into_dense().expect(dense),
            du_prev: self.du_prev.into_dense().expect(dense),
            step: self.step,
            time_step: self.dt,
            time: self.time,
            energies: self.energies,
            pending: self.pending,
            history: self.history,
            phases: self.phases,
            contact_totals: self.contact_totals,
        }
    }

    /// A solver that goes on from `state` over `problem` (the problem a remeshing built): the
    /// time step from `settings` and the new mesh's stable limit, as [`Self::new`] checks it,
    /// and the next step a full one (`state.step > 0`). Drive it with [`Self::step`]; its
    /// `run` methods plan their steps from time 0 and are for runs from the start. Contact is
    /// not carried over (no scratch state is rebuilt).
    pub fn resume(
        problem: &'p Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
        state: RunState,
    ) -> Result<Self> {
        let n = problem.model.node_count();
        let lengths = [
            state.u.len(),
            state.v_half.len(),
            state.v_full.len(),
            state.du_prev.len(),
        ];
        let history_fits = state.history.bodies.len() == problem.model.bodies.len()
            && problem
                .model
                .bodies
                .iter()
                .zip(&state.history.bodies)
                .all(|(b, h)| {
                    let len = b.material.history_len();
                    match h {
                        None => len == 0,
                        Some(h) => h.state_len == len && h.values.len() == len * b.elements.len(),
                    }
                });
        if !history_fits {
            return Err(SolverError::Remesh {
                entity: "run state".to_string(),
                message: "its material histories do not fit the model's bodies and elements"
                    .to_string(),
            });
        }
        if lengths.iter().any(|&l| l != n) || state.step == 0 {
            return Err(SolverError::Remesh {
                entity: "run state".to_string(),
                message: format!(
                    "{lengths:?} nodal values for {n} nodes at step {}: a run resumes after its \
                     first step, with one value per node",
                    state.step
                ),
            });
        }
        let mut solver =
            Self::with_history(Lent::Shared(problem), settings, output, state.history, None)?;
        solver.u = NodeField::dense(state.u);
        solver.v_half = NodeField::dense(state.v_half);
        solver.v_full = NodeField::dense(state.v_full);
        solver.du_prev = NodeField::dense(state.du_prev);
        solver.step = state.step;
        solver.step_origin = state.step;
        solver.time = state.time;
        solver.time_origin = state.time;
        solver.energies = state.energies;
        solver.pending = state.pending;
        solver.phases = state.phases;
        solver.contact_totals = state.contact_totals;
        // Bitwise the same run when the step does not change.
        solver.dt_before_resume = (state.time_step != solver.dt).then_some(state.time_step);
        Ok(solver)
    }
}
