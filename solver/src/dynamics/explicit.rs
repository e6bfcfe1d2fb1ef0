//! The central-difference (leapfrog) integrator with lumped mass (thesis 4.3.2.2). A step is
//! `ExplicitSolver::advance`: named phases (internal forces, predictor, prescribed motion,
//! contact, energy ledger), each timed ([`PhaseTimes`]). What a run records is in `records`,
//! how it stops early in `stopping`, the contact phase's buffers in `contact_phase`.

mod contact_phase;
mod ledger;
mod rank_restart;
mod ranks;
mod reactions;
mod records;
mod restart;
mod resume;
mod run_loop;
mod stopping;
mod symmetry_wall;

use std::time::Instant;

use nalgebra::Vector3;

use super::settings::{ContactTotals, PhaseTimes, RunSummary};
use super::{EnergyLedger, ExplicitSettings, OutputSettings};
use crate::distributed::{Communicator, NodePlan};
use crate::error::{Result, SolverError};
use crate::model::{MaterialHistory, Motion};
use crate::nodal::{NodeField, NodeSlots};
use crate::output::{FieldFrames, HistoryFile, ObserverSet, PieceFrames, Progress, RunObserver};
use crate::problem::Problem;
use contact_phase::ContactScratch;
use ranks::Lent;
pub use ranks::{
    keep_rank_element_data, keeps_own_elements, rank_ranges_of, restore_whole_problem,
};
pub use restart::{RestartState, ScheduleRecord};
pub use resume::RunState;
pub use run_loop::{OutputSchedule, SegmentEnd};

/// A stopwatch read lap by lap.
struct Lap(Instant);

impl Lap {
    fn start() -> Self {
        Lap(Instant::now())
    }

    /// Seconds since the start or the last lap.
    fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

/// Central differences in velocity form with mass-proportional damping (FORMULATION 2):
/// `v_{n+1/2} = ((1 - a dt/2) v_{n-1/2} + dt M^-1 (f_ext - f_int)) / (1 + a dt/2)`,
/// `u_{n+1} = u_n + dt v_{n+1/2}`. The first half step is `v_{1/2} = v_0 + dt/2 (a_0 - a v_0)`.
pub struct ExplicitSolver<'p> {
    problem: &'p Problem,
    settings: ExplicitSettings,
    output: OutputSettings,
    dt: f64,
    dt_critical: f64,
    critical_element: usize,
    constraint_of: NodeField<[Option<u16>; 3]>,
    /// The constrained nodes this process stores, ascending.
    constrained_nodes: Vec<u32>,
    /// On a rank of a distributed run, the gather of the conditions' reactions for the history
    /// rows (their nodes lie on several ranks).
    condition_reactions: Option<reactions::ConditionReactions>,
    /// Symmetry planes that hold every node of their body reaching them.
    walls: symmetry_wall::SymmetryWalls,
    node_length: NodeField<f64>,
    // The nodal values are stored for this rank's nodes only in a distributed run
    // ([`NodeField`]); [`Self::whole`] gives every node's.
    /// Displacement `u_n`.
    pub u: NodeField<Vector3<f64>>,
    /// Velocity at the last half step, `v_{n-1/2}` (before the first step: `v_0`).
    pub v_half: NodeField<Vector3<f64>>,
    /// Velocity at the last full step, `v_n`.
    pub v_full: NodeField<Vector3<f64>>,
    f_int: NodeField<Vector3<f64>>,
    f_ext: NodeField<Vector3<f64>>,
    du_prev: NodeField<Vector3<f64>>,
    /// Scratch for `v_{n+1/2}` while `v_{n-1/2}` is still needed.
    v_next: NodeField<Vector3<f64>>,
    /// Reaction forces at prescribed components, `M a + a M v - f_ext + f_int` (N).
    pub reaction: NodeField<Vector3<f64>>,
    contact: Option<ContactScratch>,
    /// History of the bodies whose material has one (microplane concrete), advanced once per
    /// step by the force computation of [`Self::advance`].
    history: MaterialHistory,
    /// Whether each node belongs to a body with history, whose internal work is also counted
    /// apart (empty when there is none).
    history_node: Vec<bool>,
    /// What the contact phase did in the last step, per pair.
    pub contact_steps: Vec<crate::contact::ContactStep>,
    /// Wall time of each phase so far.
    phases: PhaseTimes,
    contact_totals: ContactTotals,
    /// The energy ledger at the last completed step (J, FORMULATION section 2).
    pub energies: EnergyLedger,
    pending: EnergyLedger,
    /// Number of time steps completed.
    pub step: usize,
    /// Simulated time reached (s): `time_origin + (step - step_origin) dt`.
    pub time: f64,
    /// Time and step at which this solver took the run over (0 unless resumed after a
    /// remeshing, [`Self::resume`]).
    time_origin: f64,
    step_origin: usize,
    /// The time step of the run before a resume, when it differs: the first step after it
    /// spans `(dt_before + dt) / 2` between its half-step velocities ([`Self::advance`]).
    dt_before_resume: Option<f64>,
    /// This rank's share of a distributed run ([`Self::new_rank`]); `None` on one process.
    ranks: Option<ranks::RankShare<'p>>,
    /// The nodes this rank integrates and the leaves of the sums over nodes it computes (all of
    /// them on one process).
    nodes: NodePlan,
}

impl<'p> ExplicitSolver<'p> {
    /// Checks the time step against the stable limit and prepares the state at `t = 0`.
    pub fn new(
        problem: &'p Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
    ) -> Result<Self> {
        let history = problem.model.initial_history();
        Self::with_history(Lent::Shared(problem), settings, output, history, None)
    }

    /// [`Self::new`] with the material histories `history` (a resumed run's, which the model's
    /// initial ones would only be built to be replaced by), as rank `comm.rank()` of
    /// `comm.size()` when `comm` is given ([`Self::new_rank`]).
    fn with_history(
        lent: Lent<'p>,
        settings: ExplicitSettings,
        output: OutputSettings,
        history: MaterialHistory,
        comm: Option<&'p dyn Communicator>,
    ) -> Result<Self> {
        let problem = lent.problem();
        let model = &problem.model;
        settings.validate("analysis.explicit")?;
        let (dt_critical, critical_element) = model.critical_time_step();
        let dt = match settings.time_step {
            Some(dt) => {
                if dt > dt_critical && !settings.allow_unstable_time_step {
                    return Err(SolverError::TimeStepAboveStable {
                        requested: dt,
                        stable: dt_critical,
                        element: critical_element,
                    });
                }
                dt
            }
            None => settings.safety * dt_critical,
        };
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.time_step".into(),
                message: format!(
                    "time step must be positive and finite, got {dt} (the stable estimate is \
                     {dt_critical:e} s, set by element {critical_element}: check the material's \
                     density and modulus)"
                ),
            });
        }
        // A stable step longer than the whole run is cut to the run's length: the run ends at
        // `end_time`, not a step past it (a smaller step is as stable).
        let dt = if settings.max_steps.is_none() {
            dt.min(settings.end_time)
        } else {
            dt
        };
        let steps = settings.end_time / dt;
        if settings.max_steps.is_none() && steps > super::settings::MAX_STEPS {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.end_time".into(),
                message: format!(
                    "{:e} s takes {steps:.3e} steps of {dt:.4e} s, more than the {:e} a run may \
                     take; shorten end_time, or set max_steps",
                    settings.end_time,
                    super::settings::MAX_STEPS
                ),
            });
        }
        let n = model.node_count();
        let contact = (!problem.contact.is_empty()).then(|| ContactScratch::new(problem));
        // A rank's nodes are known before any nodal array is allocated: it allocates its own.
        let (nodes, ranks, history) = match comm.filter(|c| c.size() > 1) {
            Some(comm) => {
                let (nodes, share, history) =
                    ranks::rank_share(problem, contact.as_ref(), history, comm)?;
                (nodes, Some(share), history)
            }
            None => (NodePlan::single(n), None, history),
        };
        let slots = nodes.slots();
        let constraint_map = problem.constraint_map();
        let constrained_nodes = (0..n as u32)
            .filter(|&i| constraint_map[i as usize].iter().any(Option::is_some))
            .filter(|&i| slots.slot(i as usize).is_some())
            .collect();
        let condition_reactions = ranks.as_ref().map(|r| {
            let comm = r.comm();
            reactions::ConditionReactions::new(
                problem,
                &constraint_map,
                &nodes,
                comm.rank(),
                comm.size(),
            )
        });
        let constraint_of = NodeField::from_whole(&slots, &constraint_map);
        drop(constraint_map);
        let node_length = node_lengths(model, &slots);
        let history_node = history_nodes(model);
        let walls = symmetry_wall::SymmetryWalls::new(problem);
        let v0 = NodeField::from_whole(&slots, &problem.initial_velocity);
        let k0 = {
            let (m, v) = (&model.mass, &problem.initial_velocity);
            fixed_order_sum(n, |i| 0.5 * m[i] * v[i].norm_squared())
        };
        // What reads other ranks' elements and nodes is done: a rank that may keep its own
        // part only frees the rest (contact reads its surfaces' layers every step).
        let own = ranks.as_ref().map(|r| r.own_elements());
        let keeps = ranks
            .as_ref()
            .is_some_and(|r| keeps_own_elements(problem, r.comm()));
        let problem = lent.keep_own_part(own, keeps.then_some(&slots));
        let zeros = NodeField::filled(&slots, Vector3::zeros());
        let mut solver = Self {
            problem,
            settings,
            output,
            dt,
            dt_critical,
            critical_element,
            constraint_of,
            constrained_nodes,
            condition_reactions,
            walls,
            node_length,
            u: zeros.clone(),
            v_half: v0.clone(),
            v_full: v0,
            f_int: zeros.clone(),
            f_ext: zeros.clone(),
            du_prev: zeros.clone(),
            v_next: zeros.clone(),
            contact,
            history,
            history_node,
            contact_steps: Vec::new(),
            phases: PhaseTimes::default(),
            contact_totals: ContactTotals::default(),
            reaction: zeros,
            energies: EnergyLedger::default(),
            pending: EnergyLedger::default(),
            step: 0,
            time: 0.0,
            time_origin: 0.0,
            step_origin: 0,
            dt_before_resume: None,
            ranks,
            nodes,
        };
        solver.energies.initial_kinetic = k0;
        solver.energies.kinetic = k0;
        Ok(solver)
    }

    /// The problem this solver runs (on a rank that keeps its own elements only, with that
    /// part of the connectivity).
    pub fn problem(&self) -> &'p Problem {
        self.problem
    }

    /// Starts the run from displacement `u0` (for example a static solution) instead of the
    /// reference configuration. Work is counted from this state on. Histories stay virgin: the
    /// first step of a microplane body loads it from zero to the strain of `u0` at once.
    pub fn set_initial_displacement(&mut self, u0: &[Vector3<f64>]) {
        self.u = NodeField::from_whole(self.u.slots(), u0);
    }

    /// The history of the bodies whose material has one, as of the last step's force
    /// computation (at the current displacement `u`).
    pub fn history(&self) -> &MaterialHistory {
        &self.history
    }

    /// The element histories, taken out of a solver whose run is over (a clone would hold a
    /// second copy of every history at the run's end: 1.2 KB per microplane element).
    pub fn take_history(&mut self) -> MaterialHistory {
        std::mem::take(&mut self.history)
    }

    /// The contact problems recorded so far (pairs with `record_every`), taken out of the solver.
    pub fn take_recorded_problems(&mut self) -> Vec<crate::contact::RecordedProblem> {
        self.contact
            .as_mut()
            .map(|c| std::mem::take(&mut c.phase.recorded))
            .unwrap_or_default()
    }

    /// The CCD queries recorded so far (pairs with `record_ccd_every`), taken out of the solver.
    pub fn take_recorded_ccd_queries(&mut self) -> Vec<crate::contact::RecordedCcdQuery> {
        self.contact
            .as_mut()
            .map(|c| std::mem::take(&mut c.phase.recorded_ccd))
            .unwrap_or_default()
    }

    /// The time step of the run (s): the scene's, or `safety` times the critical one.
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// The stable limit of the central-difference scheme (s) and the index of the element that
    /// sets it (smallest altitude over dilatational wave speed).
    pub fn critical_time_step(&self) -> (f64, usize) {
        (self.dt_critical, self.critical_element)
    }

    /// Number of steps the run will take.
    pub fn planned_steps(&self) -> usize {
        // From the time this solver took the run over (0 unless resumed, then exactly as
        // before for a run from the start).
        let span = if self.step_origin == 0 {
            self.settings.end_time
        } else {
            self.settings.end_time - self.time_origin
        };
        let by_time = (span / self.dt - 1e-9).ceil().max(0.0) as usize;
        self.settings
            .max_steps
            .map_or(by_time, |m| m.min(by_time.max(m)))
    }

    /// One time step without observers: the forces, contact and energies at `t_n`, then the
    /// move to `u_{n+1}`; whether the mesh stability check flagged a node. For benchmarks and
    /// callers that drive the integrator themselves ([`Self::run_with`] is the run with output,
    /// the energy-balance stop and progress). An instability is returned as the error it is in
    /// a run, with nothing written. In a distributed run ([`Self::new_rank`]) it moves this
    /// rank's nodes only ([`Self::whole`] gathers every node's values).
    pub fn step(&mut self) -> Result<bool> {
        match self.advance() {
            Ok(moved_too_far) => {
                self.finish_step();
                Ok(moved_too_far)
            }
            Err(reason_element) => {
                let mut none = ObserverSet::new(Vec::new());
                Err(self.stop(reason_element, &mut none))
            }
        }
    }

    /// Runs to the end time with the observers that write the output settings' files
    /// ([`Self::output_observers`]), calling `progress(fraction)` about a hundred times. On
    /// instability the output computed so far is written before the error is returned.
    pub fn run(&mut self, progress: &mut dyn FnMut(f64)) -> Result<RunSummary> {
        let mut files = self.output_observers()?;
        let mut progress = Progress(progress);
        let mut observers: Vec<&mut dyn RunObserver> = files
            .iter_mut()
            .map(|o| &mut **o as &mut dyn RunObserver)
            .collect();
        observers.push(&mut progress);
        self.run_with(&mut observers)
    }

    /// The observers that write what the output settings ask for: the history CSV
    /// (`<stem>_history.csv`) and, with `fields`, the VTU frames and their `<stem>.pvd`.
    /// In a distributed run ([`Self::new_rank`]) rank 0 writes the history, and every rank its
    /// piece of each frame (`PieceFrames`: `<stem>_<i>_<rank>.vtu`, joined by rank 0's
    /// `<stem>_<i>.pvtu`).
    pub fn output_observers(&self) -> Result<Vec<Box<dyn RunObserver>>> {
        let mut observers: Vec<Box<dyn RunObserver>> = Vec::new();
        if let Some(dir) = &self.output.dir {
            let (rank, size) = self.rank();
            if rank == 0 {
                let path = dir.join(format!("{}_history.csv", self.output.stem));
                observers.push(Box::new(HistoryFile::new(path)));
            }
            if self.output.fields {
                let stem = &self.output.stem;
                observers.push(match self.rank_elements() {
                    Some(cells) => Box::new(PieceFrames::new(dir, stem, rank, size, cells)?),
                    None => Box::new(FieldFrames::new(dir, stem)?),
                });
            }
        }
        Ok(observers)
    }

    /// Computes forces at `t_n`, the new half-step velocity, the full-step velocity, reactions and
    /// the energies at `t_n`. Leaves `u` at `u_n`; [`Self::finish_step`] moves it to `u_{n+1}`.
    /// Returns whether the mesh stability check flagged a node, or the reason to stop. Each
    /// phase is timed ([`PhaseTimes`]).
    fn advance(&mut self) -> std::result::Result<bool, (String, Option<usize>)> {
        // Effective step between v_{n-1/2} and v_{n+1/2}: half a step at the start, and the
        // mean of the two steps on either side of t_n at the first step after a resume with a
        // new time step (central differences with a variable step, Belytschko et al. 2014,
        // 6.2.1: v_{n+1/2} = v_{n-1/2} + (dt_{n-1/2} + dt_{n+1/2}) / 2 a_n).
        let h = if self.step == 0 {
            0.5 * self.dt
        } else {
            match self.dt_before_resume {
                Some(before) if self.step == self.step_origin => 0.5 * (before + self.dt),
                _ => self.dt,
            }
        };
        let mut clock = Lap::start();
        self.internal_forces()?;
        self.phases.internal_forces += clock.lap();
        self.predictor(h);
        self.phases.predictor += clock.lap();
        self.prescribed_motion();
        self.phases.prescribed_motion += clock.lap();
        self.contact_correction(h);
        self.symmetry_walls();
        self.phases.contact += clock.lap();
        let moved_too_far = self.energy_ledger(h)?;
        self.phases.energy_ledger += clock.lap();
        std::mem::swap(&mut self.v_half, &mut self.v_next);
        Ok(moved_too_far)
    }

    /// The internal forces at `t_n`, the only force computation of the step: it advances the
    /// material histories, with the strain rate from `v_{n-1/2}` (`v_0` at the first step).
    fn internal_forces(&mut self) -> std::result::Result<(), (String, Option<usize>)> {
        let problem = self.problem;
        let model = &problem.model;
        let inverted = model.advance_internal_forces(
            &self.u,
            &self.v_half,
            self.dt,
            &mut self.history,
            &mut self.f_int,
        );
        if let Some(e) = self.complete_forces(inverted) {
            let det = self.element_jacobian(e);
            return Err((format!("element inverted (det F = {det:.3e})"), Some(e)));
        }
        Ok(())
    }

    /// The loads at `t_n` and the damped central-difference update of every node,
    /// `v_{n+1/2} = ((1 - a h/2) v_{n-1/2} + h M^-1 (f_ext - f_int)) / (1 + a h/2)`.
    fn predictor(&mut self, h: f64) {
        let problem = self.problem;
        let model = &problem.model;
        if !problem.external_forces(self.time, &mut self.f_ext) && self.step == 0 {
            self.f_ext.fill(Vector3::zeros());
        }
        let alpha = self.settings.damping;
        let (c_old, c_new) = (1.0 - 0.5 * alpha * h, 1.0 / (1.0 + 0.5 * alpha * h));
        // Run by run over slices: a rank's fields store each run contiguously.
        for run in self.nodes.active() {
            let v_next = self.v_next.run_mut(run.clone());
            let old = self.v_half.run(run.clone());
            let (f_ext, f_int) = (self.f_ext.run(run.clone()), self.f_int.run(run.clone()));
            let mass = &model.mass[run.clone()];
            for ((((v, v_old), fe), fi), m) in
                v_next.iter_mut().zip(old).zip(f_ext).zip(f_int).zip(mass)
            {
                let a = (fe - fi) / *m;
                *v = (c_old * v_old + h * a) * c_new;
            }
        }
    }

    /// Prescribed components: the velocity that the condition gives over the step.
    fn prescribed_motion(&mut self) {
        let problem = self.problem;
        let (dt, t) = (self.dt, self.time);
        // After a remeshing the motions, functions of the original coordinates, read those
        // and the displacement since then ([`crate::model::CarriedState`]).
        let carried = problem.model.carried.as_ref().map(|c| &c.displacement);
        for &i in &self.constrained_nodes {
            let i = i as usize;
            let (x, u_now) = match carried {
                Some(d) => (problem.model.reference[i] - d[i], d[i] + self.u[i]),
                None => (problem.model.reference[i], self.u[i]),
            };
            for d in 0..3 {
                if let Some(c) = self.constraint_of[i][d] {
                    let motion = &problem.constraints[c as usize].motion;
                    self.v_next[i][d] = match motion {
                        Motion::Velocity(_, f) => f.eval(t + 0.5 * dt),
                        Motion::AffineVelocity { .. } => motion
                            .velocity(&x, t)
                            .expect("an affine velocity gives a velocity at every point")[d],
                        _ => {
                            let u = motion
                                .displacement(&x, t + dt)
                                .expect("every motion but a velocity gives a displacement");
                            (u[d] - u_now[d]) / dt
                        }
                    };
                }
            }
        }
    }

    /// Contact: detection and the correction of `v_{n+1/2}` by the contact solvers, with the
    /// run's totals.
    fn contact_correction(&mut self, h: f64) {
        let Some(scratch) = self.contact.as_mut() else {
            return;
        };
        // The force that makes a velocity change dv in the damped update
        // m (v+ - v-) / h + alpha m (v+ + v-) / 2 = f is m dv (1/h + alpha/2).
        let force_per_dv = 1.0 / h + 0.5 * self.settings.damping;
        self.contact_steps = scratch.correct(
            self.step,
            &self.problem.model,
            self.dt,
            force_per_dv,
            &self.u,
            &mut self.v_next,
        );
        let totals = &mut self.contact_totals;
        for s in &self.contact_steps {
            totals.solves += s.solves;
            totals.not_converged += s.not_converged;
            totals.unresolved += s.unresolved;
            totals.iterations += s.iterations;
        }
        totals.steps_with_contact += usize::from(self.contact_steps.iter().any(|s| s.solves > 0));
    }

    /// Nodes that would cross a symmetry plane of their body in the step are held on it
    /// (`symmetry_wall.rs`), after contact: the plane is the last word on where a node goes.
    fn symmetry_walls(&mut self) {
        let model = &self.problem.model;
        let (u, constraint_of) = (&self.u, &self.constraint_of);
        let surplus = self.contact.as_ref().map(|c| &c.position_surplus);
        self.walls.hold(
            |i| model.reference[i] + u[i],
            |i| surplus.map_or_else(Vector3::zeros, |s| s[i]),
            self.dt,
            |i, d| constraint_of[i][d].is_some(),
            &mut self.v_next,
        );
    }

    fn finish_step(&mut self) {
        for run in self.nodes.active() {
            let du = self.du_prev.run(run.clone());
            for (u, du) in self.u.run_mut(run.clone()).iter_mut().zip(du) {
                *u += du;
            }
        }
        self.step += 1;
        self.time = self.time_origin + (self.step - self.step_origin) as f64 * self.dt;
    }
}

/// Sum of `term(i)` for `i < n` in index order, so the result does not depend on threads.
pub(crate) fn fixed_order_sum(n: usize, term: impl Fn(usize) -> f64) -> f64 {
    (0..n).map(term).sum()
}

/// The smallest altitude of the elements around each node `slots` stores (m; infinite at a
/// node of no element): the length of its stable step.
fn node_lengths(model: &crate::model::Model, slots: &NodeSlots) -> NodeField<f64> {
    let mut node_length = NodeField::filled(slots, f64::INFINITY);
    for (e, tet) in model.tets.iter().enumerate() {
        if tet.iter().all(|&a| node_length.get(a as usize).is_none()) {
            continue;
        }
        let l = model.min_altitude(e);
        for &a in tet {
            if let Some(length) = node_length.get_mut(a as usize) {
                *length = length.min(l);
            }
        }
    }
    node_length
}

/// Whether each node belongs to an element of a body with a material history (empty when no
/// body has one). A material region owns no nodes of its own but uses its parent's.
fn history_nodes(model: &crate::model::Model) -> Vec<bool> {
    if !model.has_history() {
        return Vec::new();
    }
    let mut flags = vec![false; model.node_count()];
    for body in model.bodies.iter().filter(|b| b.material.history_len() > 0) {
        for e in body.elements.clone() {
            for &node in &model.tets[e] {
                flags[node as usize] = true;
            }
        }
    }
    flags
}
