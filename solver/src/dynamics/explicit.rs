//! The central-difference (leapfrog) integrator with lumped mass (thesis 4.3.2.2).

use std::path::PathBuf;
use std::time::Instant;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::{EnergyLedger, InstabilityReport};
use crate::error::{Result, SolverError};
use crate::kinematics::{displacement_gradient, green_lagrange_from_h};
use crate::model::{field_frame_with_history, MaterialHistory, Motion, Problem};
use crate::output::history::{HistoryStream, HistoryTable};
use crate::output::vtu::PvdWriter;

/// Settings of an explicit run. Defaults follow FORMULATION section 2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitSettings {
    /// Simulated time (s).
    pub end_time: f64,
    /// Fixed time step (s); `None` takes `safety * dt_cr`.
    #[serde(default)]
    pub time_step: Option<f64>,
    /// Fraction of the critical step used when `time_step` is not given.
    #[serde(default = "default_safety")]
    pub safety: f64,
    /// Run even if `time_step` exceeds the stable estimate (stability sweeps do).
    #[serde(default)]
    pub allow_unstable_time_step: bool,
    /// Mass-proportional damping coefficient `a` of `C = a M` (1/s).
    #[serde(default)]
    pub damping: f64,
    /// Stop after this many steps even if `end_time` is not reached.
    #[serde(default)]
    pub max_steps: Option<usize>,
    /// Time between history records (s); `None` records about 500 instants.
    #[serde(default)]
    pub history_interval: Option<f64>,
    /// Time between field frames (s); `None` writes the first and the last state only.
    #[serde(default)]
    pub field_interval: Option<f64>,
    /// Time between displacement snapshots kept in memory for the caller (crack growth, failure
    /// modes); `None` keeps none. Cheaper than field frames: nothing is written or derived.
    #[serde(default)]
    pub snapshot_interval: Option<f64>,
    /// The run is declared unstable when the energy balance error exceeds this fraction of the
    /// largest energy scale seen so far.
    #[serde(default = "default_energy_tolerance")]
    pub instability_energy_tolerance: f64,
    /// Mesh stability check (4.35): steps where a node moves more than `eta` times the smallest
    /// altitude of its elements are counted.
    #[serde(default = "default_eta")]
    pub mesh_stability_eta: f64,
}

fn default_safety() -> f64 {
    0.9
}
fn default_energy_tolerance() -> f64 {
    0.05
}
fn default_eta() -> f64 {
    0.1
}

impl ExplicitSettings {
    pub fn new(end_time: f64) -> Self {
        Self {
            end_time,
            time_step: None,
            safety: default_safety(),
            allow_unstable_time_step: false,
            damping: 0.0,
            max_steps: None,
            history_interval: None,
            field_interval: None,
            snapshot_interval: None,
            instability_energy_tolerance: default_energy_tolerance(),
            mesh_stability_eta: default_eta(),
        }
    }
}

/// Where a run writes its output; `dir: None` keeps everything in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutputSettings {
    pub dir: Option<PathBuf>,
    /// File stem: `<stem>_history.csv`, `<stem>.pvd`, `<stem>_00000.vtu`, ...
    pub stem: String,
    /// Write VTU field frames (histories are always kept).
    pub fields: bool,
}

/// The contact solver's record over a run, all pairs and passes together.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactTotals {
    /// Steps in which at least one contact problem was solved.
    pub steps_with_contact: usize,
    pub solves: usize,
    pub not_converged: usize,
    pub unresolved: usize,
    /// Gauss-Seidel sweeps or interior-point iterations.
    pub iterations: usize,
}

/// What a completed run reports.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub steps: usize,
    pub time: f64,
    pub time_step: f64,
    pub critical_time_step: f64,
    pub critical_element: usize,
    pub wall_seconds: f64,
    /// Wall time spent in the contact phase (detection and resolution), within `wall_seconds`.
    pub contact_seconds: f64,
    /// How the contact solver fared, summed over the run.
    pub contact_totals: ContactTotals,
    pub energies: EnergyLedger,
    /// Largest |balance error| over the run divided by the largest energy scale of the run.
    pub max_relative_energy_error: f64,
    /// Steps in which some node moved more than `eta` times its smallest element altitude.
    pub mesh_stability_flags: usize,
    pub history: HistoryTable,
    /// Displacements at every `snapshot_interval` (and at the end), when one is set.
    pub snapshots: Vec<Snapshot>,
    pub written: Vec<PathBuf>,
}

/// The displacement of every node at one instant of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    pub time: f64,
    pub u: Vec<Vector3<f64>>,
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
    constraint_of: Vec<[Option<u16>; 3]>,
    constrained_nodes: Vec<u32>,
    node_length: Vec<f64>,
    /// Displacement `u_n`.
    pub u: Vec<Vector3<f64>>,
    /// Velocity at the last half step, `v_{n-1/2}` (before the first step: `v_0`).
    pub v_half: Vec<Vector3<f64>>,
    /// Velocity at the last full step, `v_n`.
    pub v_full: Vec<Vector3<f64>>,
    f_int: Vec<Vector3<f64>>,
    f_ext: Vec<Vector3<f64>>,
    du_prev: Vec<Vector3<f64>>,
    /// Scratch for `v_{n+1/2}` while `v_{n-1/2}` is still needed.
    v_next: Vec<Vector3<f64>>,
    /// Reaction forces at prescribed components, `M a + a M v - f_ext + f_int` (N).
    pub reaction: Vec<Vector3<f64>>,
    contact: Option<ContactScratch>,
    /// History of the bodies whose material has one (microplane concrete), advanced once per
    /// step by the force computation of [`Self::advance`].
    history: MaterialHistory,
    /// Whether each node belongs to a body with history, whose internal work is also counted
    /// apart (empty when there is none).
    history_node: Vec<bool>,
    /// What the contact phase did in the last step, per pair.
    pub contact_steps: Vec<crate::contact::ContactStep>,
    contact_seconds: f64,
    contact_totals: ContactTotals,
    pub energies: EnergyLedger,
    pending: EnergyLedger,
    pub step: usize,
    pub time: f64,
    deadline: Option<(Instant, f64)>,
    /// Set from outside (a signal handler) to stop the run at the end of the current step.
    stop: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

impl<'p> ExplicitSolver<'p> {
    /// Checks the time step against the stable limit and prepares the state at `t = 0`.
    pub fn new(
        problem: &'p Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
    ) -> Result<Self> {
        let model = &problem.model;
        if !(settings.end_time > 0.0) && settings.max_steps.is_none() {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.end_time".into(),
                message: format!("must be positive, got {}", settings.end_time),
            });
        }
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
                message: format!("time step must be positive and finite, got {dt}"),
            });
        }
        let n = model.node_count();
        let constraint_of = problem.constraint_map();
        let constrained_nodes = (0..n as u32)
            .filter(|&i| constraint_of[i as usize].iter().any(Option::is_some))
            .collect();
        let mut node_length = vec![f64::INFINITY; n];
        for (e, tet) in model.tets.iter().enumerate() {
            for &a in tet {
                node_length[a as usize] = node_length[a as usize].min(model.min_altitude[e]);
            }
        }
        let v0 = problem.initial_velocity.clone();
        let mut solver = Self {
            problem,
            settings,
            output,
            dt,
            dt_critical,
            critical_element,
            constraint_of,
            constrained_nodes,
            node_length,
            u: vec![Vector3::zeros(); n],
            v_full: v0.clone(),
            v_half: v0,
            f_int: vec![Vector3::zeros(); n],
            f_ext: vec![Vector3::zeros(); n],
            du_prev: vec![Vector3::zeros(); n],
            v_next: vec![Vector3::zeros(); n],
            contact: (!problem.contact.is_empty()).then(|| ContactScratch::new(problem)),
            history: model.initial_history(),
            history_node: if model.has_history() {
                let mut flags = vec![false; n];
                // The nodes of the history bodies' elements (a material region owns no nodes
                // of its own but uses its parent's).
                for body in model.bodies.iter().filter(|b| b.material.has_history()) {
                    for e in body.elements.clone() {
                        for &node in &model.tets[e] {
                            flags[node as usize] = true;
                        }
                    }
                }
                flags
            } else {
                Vec::new()
            },
            contact_steps: Vec::new(),
            contact_seconds: 0.0,
            contact_totals: ContactTotals::default(),
            reaction: vec![Vector3::zeros(); n],
            energies: EnergyLedger::default(),
            pending: EnergyLedger::default(),
            step: 0,
            time: 0.0,
            deadline: None,
            stop: None,
        };
        let k0 = solver.kinetic_energy(&solver.v_full);
        solver.energies.initial_kinetic = k0;
        solver.energies.kinetic = k0;
        Ok(solver)
    }

    /// Starts the run from displacement `u0` (for example a static solution) instead of the
    /// reference configuration. Work is counted from this state on. Histories stay virgin: the
    /// first step of a microplane body loads it from zero to the strain of `u0` at once.
    pub fn set_initial_displacement(&mut self, u0: &[Vector3<f64>]) {
        self.u.copy_from_slice(u0);
    }

    /// The history of the bodies whose material has one, as of the last step's force
    /// computation (at the current displacement `u`).
    pub fn history(&self) -> &MaterialHistory {
        &self.history
    }

    /// Stops the run with [`SolverError::TimeLimit`] once `seconds` of wall time have passed,
    /// after writing the output computed so far.
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

    /// Stops the run at the end of the step during which `flag` becomes true: the history up to
    /// that step is written (with the frames and snapshots already written) and the run returns
    /// [`SolverError::Interrupted`].
    pub fn set_stop_flag(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        self.stop = Some(flag);
    }

    pub fn set_time_limit(&mut self, seconds: f64) {
        self.deadline = Some((
            Instant::now() + std::time::Duration::from_secs_f64(seconds),
            seconds,
        ));
    }

    pub fn time_step(&self) -> f64 {
        self.dt
    }

    pub fn critical_time_step(&self) -> (f64, usize) {
        (self.dt_critical, self.critical_element)
    }

    /// Number of steps the run will take.
    pub fn planned_steps(&self) -> usize {
        let by_time = (self.settings.end_time / self.dt - 1e-9).ceil().max(0.0) as usize;
        self.settings
            .max_steps
            .map_or(by_time, |m| m.min(by_time.max(m)))
    }

    /// One line per decision the run takes, printed before it starts.
    pub fn plan(&self) -> String {
        let model = &self.problem.model;
        format!(
            "explicit dynamics: {} bodies, {} nodes, {} elements; dt = {:.4e} s ({:.3} of the \
             stable estimate {:.4e} s set by element {}); {} steps to t = {:.4e} s; {} constraints, \
             {} loads, gravity {}; damping a = {}; contact: {}",
            model.bodies.len(),
            model.node_count(),
            model.element_count(),
            self.dt,
            self.dt / self.dt_critical,
            self.dt_critical,
            self.critical_element,
            self.planned_steps(),
            self.settings.end_time,
            self.problem.constraints.len(),
            self.problem.loads.len(),
            if self.problem.gravity.is_some() { "on" } else { "off" },
            self.settings.damping,
            if self.problem.contact.is_empty() {
                "none".to_string()
            } else {
                self.problem
                    .contact
                    .iter()
                    .map(|p| format!("{} (mu {}, beta_0 {}, {} pass)", p.name, p.friction, p.beta_0, if p.two_pass { "two-" } else { "one-" }))
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        ) + &self.history_plan()
    }

    /// The bodies with history, their element sizes and the memory the history takes (empty
    /// without such bodies).
    fn history_plan(&self) -> String {
        let model = &self.problem.model;
        let mut parts = Vec::new();
        for (body, history) in model.bodies.iter().zip(&self.history.bodies) {
            if let (Some(m), Some(h)) = (&body.microplane, history) {
                let (lo, hi) = m.bands.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
                    (lo.min(b.size), hi.max(b.size))
                });
                parts.push(format!(
                    "`{}` microplane ({} directions, element sizes {:.1}-{:.1} mm, limit {:.1} \
                     mm; history {} B per element, {:.1} MB)",
                    body.name,
                    m.model.planes().len(),
                    lo * 1e3,
                    hi * 1e3,
                    m.model.largest_element() * 1e3,
                    h.bytes_per_element(),
                    (h.bytes_per_element() * body.elements.len()) as f64 / 1e6
                ));
            }
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!("; materials with history: {}", parts.join(", "))
        }
    }

    fn kinetic_energy(&self, v: &[Vector3<f64>]) -> f64 {
        fixed_order_sum(v.len(), |i| {
            0.5 * self.problem.model.mass[i] * v[i].norm_squared()
        })
    }

    /// Runs to the end time, calling `progress(fraction)` about a hundred times. On instability
    /// the output computed so far is written before the error is returned.
    pub fn run(&mut self, progress: &mut dyn FnMut(f64)) -> Result<RunSummary> {
        let started = Instant::now();
        let steps = self.planned_steps();
        let history_interval = self
            .settings
            .history_interval
            .unwrap_or(self.settings.end_time / 500.0)
            .max(0.0);
        let mut history = HistoryTable::new(self.history_columns());
        // The CSV grows as the run goes (a killed run leaves it up to the last flush); the whole
        // table is written again at the end, the same text.
        let mut stream = match self.history_path() {
            Some(path) => Some(HistoryStream::create(&path, history.columns())?),
            None => None,
        };
        let mut next_history = 0.0;
        let mut pvd = match (&self.output.dir, self.output.fields) {
            (Some(dir), true) => Some(PvdWriter::new(dir, &self.output.stem)?),
            _ => None,
        };
        let mut next_field = 0.0;
        let mut next_snapshot = 0.0;
        let mut snapshots = Vec::new();
        let mut written = Vec::new();
        let mut max_scale: f64 = 0.0;
        let mut max_abs_error: f64 = 0.0;
        let mut flags = 0;
        let progress_every = (steps / 100).max(1);

        for n in 0..=steps {
            let last = n == steps;
            match self.advance() {
                Ok(moved_too_far) => flags += moved_too_far as usize,
                Err(reason_element) => {
                    drop(stream.take());
                    return Err(self.stop(
                        reason_element,
                        &mut history,
                        pvd.as_mut(),
                        &mut written,
                    ));
                }
            }
            // Energies now describe t_n; check the balance before recording.
            let e = self.energies;
            max_scale = max_scale.max(e.scale());
            let error = e.balance_error();
            max_abs_error = max_abs_error.max(error.abs());
            if n > 10 && error.abs() > self.settings.instability_energy_tolerance * max_scale {
                let reason = format!(
                    "energy balance error {:.3e} J exceeds {} of the energy scale {:.3e} J",
                    error, self.settings.instability_energy_tolerance, max_scale
                );
                let element = self.most_strained_element();
                drop(stream.take());
                return Err(self.stop((reason, element), &mut history, pvd.as_mut(), &mut written));
            }
            if n == 0 || last || self.time >= next_history - 1e-9 * self.dt {
                let row = self.history_row(&e);
                if let Some(stream) = stream.as_mut() {
                    stream.append(&row)?;
                }
                history.push(row);
                next_history += history_interval;
            }
            if let Some(writer) = pvd.as_mut() {
                let due = match self.settings.field_interval {
                    Some(_) => self.time >= next_field - 1e-9 * self.dt,
                    None => n == 0,
                };
                if due || last {
                    written.push(self.write_frame(writer)?);
                    if let Some(interval) = self.settings.field_interval {
                        next_field += interval;
                    }
                }
            }
            if let Some(interval) = self.settings.snapshot_interval {
                if last || self.time >= next_snapshot - 1e-9 * self.dt {
                    snapshots.push(Snapshot {
                        time: self.time,
                        u: self.u.clone(),
                    });
                    next_snapshot += interval;
                }
            }
            if n % progress_every == 0 {
                progress(n as f64 / steps.max(1) as f64);
                if let Some((deadline, limit_s)) = self.deadline {
                    if Instant::now() > deadline {
                        drop(stream.take());
                        if let Some(path) = self.history_path() {
                            if history.write_csv(&path).is_ok() {
                                written.push(path);
                            }
                        }
                        return Err(SolverError::TimeLimit {
                            limit_s,
                            step: self.step,
                            time: self.time,
                        });
                    }
                }
            }
            if last {
                break;
            }
            if self
                .stop
                .as_ref()
                .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
            {
                drop(stream.take());
                if let Some(path) = self.history_path() {
                    history.write_csv(&path)?;
                    written.push(path);
                }
                return Err(SolverError::Interrupted {
                    step: self.step,
                    time: self.time,
                });
            }
            self.finish_step();
        }
        progress(1.0);
        // Closed before the table is written whole, so that nothing buffered lands after it.
        if let Some(mut stream) = stream.take() {
            stream.flush()?;
        }
        if let Some(path) = self.history_path() {
            history.write_csv(&path)?;
            written.push(path);
        }
        Ok(RunSummary {
            steps,
            time: self.time,
            time_step: self.dt,
            critical_time_step: self.dt_critical,
            critical_element: self.critical_element,
            wall_seconds: started.elapsed().as_secs_f64(),
            contact_seconds: self.contact_seconds,
            contact_totals: self.contact_totals,
            energies: self.energies,
            max_relative_energy_error: if max_scale > 0.0 {
                max_abs_error / max_scale
            } else {
                0.0
            },
            mesh_stability_flags: flags,
            history,
            snapshots,
            written,
        })
    }

    /// Computes forces at `t_n`, the new half-step velocity, the full-step velocity, reactions and
    /// the energies at `t_n`. Leaves `u` at `u_n`; [`Self::finish_step`] moves it to `u_{n+1}`.
    /// Returns whether the mesh stability check flagged a node, or the reason to stop.
    fn advance(&mut self) -> std::result::Result<bool, (String, Option<usize>)> {
        let problem = self.problem;
        let model = &problem.model;
        let (dt, t, alpha) = (self.dt, self.time, self.settings.damping);
        // The only force computation of the step: it advances the material histories, with the
        // strain rate from v_{n-1/2} (v_0 at the first step).
        if let Some(e) = model.advance_internal_forces(
            &self.u,
            &self.v_half,
            dt,
            &mut self.history,
            &mut self.f_int,
        ) {
            let det = model.deformation_gradient(e, &self.u).determinant();
            return Err((format!("element inverted (det F = {det:.3e})"), Some(e)));
        }
        if !problem.external_forces(t, &mut self.f_ext) && self.step == 0 {
            self.f_ext.iter_mut().for_each(|f| *f = Vector3::zeros());
        }
        let first = self.step == 0;
        // Effective step between v_{n-1/2} and v_{n+1/2} (half a step at the start).
        let h = if first { 0.5 * dt } else { dt };
        let (c_old, c_new) = (1.0 - 0.5 * alpha * h, 1.0 / (1.0 + 0.5 * alpha * h));
        for i in 0..model.node_count() {
            let a = (self.f_ext[i] - self.f_int[i]) / model.mass[i];
            self.v_next[i] = (c_old * self.v_half[i] + h * a) * c_new;
        }
        for &i in &self.constrained_nodes {
            let i = i as usize;
            let x = model.reference[i];
            for d in 0..3 {
                if let Some(c) = self.constraint_of[i][d] {
                    let motion = &problem.constraints[c as usize].motion;
                    self.v_next[i][d] = match motion {
                        Motion::Velocity(_, f) => f.eval(t + 0.5 * dt),
                        Motion::AffineVelocity { .. } => motion.velocity(&x, t).unwrap()[d],
                        _ => (motion.displacement(&x, t + dt).unwrap()[d] - self.u[i][d]) / dt,
                    };
                }
            }
        }
        if let Some(scratch) = self.contact.as_mut() {
            // The force that makes a velocity change dv in the damped update
            // m (v+ - v-) / h + alpha m (v+ + v-) / 2 = f is m dv (1/h + alpha/2).
            let force_per_dv = 1.0 / h + 0.5 * alpha;
            let started = std::time::Instant::now();
            self.contact_steps = scratch.correct(
                self.step,
                model,
                dt,
                force_per_dv,
                &self.u,
                &mut self.v_next,
            );
            self.contact_seconds += started.elapsed().as_secs_f64();
            let totals = &mut self.contact_totals;
            for s in &self.contact_steps {
                totals.solves += s.solves;
                totals.not_converged += s.not_converged;
                totals.unresolved += s.unresolved;
                totals.iterations += s.iterations;
            }
            totals.steps_with_contact +=
                usize::from(self.contact_steps.iter().any(|s| s.solves > 0));
        }
        // Full-step velocity, reactions, and the energy pieces of this step.
        let mut moved_too_far = false;
        let mut kinetic = 0.0;
        let mut closing = EnergyLedger::default();
        let mut pending = EnergyLedger::default();
        let eta = self.settings.mesh_stability_eta;
        for i in 0..model.node_count() {
            let m = model.mass[i];
            let v_new = self.v_next[i];
            let v_full = if first {
                self.v_half[i]
            } else {
                0.5 * (self.v_half[i] + v_new)
            };
            let mut r = Vector3::zeros();
            let cs = self.constraint_of[i];
            if cs.iter().any(Option::is_some) {
                let a = (v_new - self.v_half[i]) / h;
                let total = m * a + alpha * m * v_full - self.f_ext[i] + self.f_int[i];
                for d in 0..3 {
                    if cs[d].is_some() {
                        r[d] = total[d];
                    }
                }
            }
            // Contact moves a node by dx = beta dt^2 r / m but changes its velocity by
            // gamma dt r / m (beta-2 scheme): with beta_0 > 0 the position keeps the surplus.
            let (f_contact, f_friction, dx_extra) = match &self.contact {
                Some(c) => (c.force[i], c.friction_force[i], c.position_surplus[i]),
                None => (Vector3::zeros(), Vector3::zeros(), Vector3::zeros()),
            };
            let f_normal = f_contact - f_friction;
            let du = dt * v_new + dx_extra;
            moved_too_far |= du.norm() > eta * self.node_length[i];
            let du_old = self.du_prev[i];
            let (f_int, f_out) = (self.f_int[i], self.f_ext[i] + r);
            let damping = alpha * m * v_full;
            // Work over the coming interval. At the start the first half step spans dt/2 with
            // mean velocity (v_0 + v_1/2)/2, which keeps an impulsive start (a velocity jump at
            // t = 0) exact: the leapfrog identity m (v_1/2 - v_0) = dt/2 F_0 dotted with it.
            let du = if first {
                0.5 * (dt * self.v_half[i] + du)
            } else {
                du
            };
            kinetic += 0.5 * m * v_full.norm_squared();
            closing.internal_work += 0.5 * f_int.dot(&du_old);
            closing.external_work += 0.5 * f_out.dot(&du_old);
            closing.damping_work += 0.5 * damping.dot(&du_old);
            closing.contact_work -= 0.5 * f_normal.dot(&du_old);
            pending.contact_work -= 0.5 * f_normal.dot(&du);
            closing.friction_work -= 0.5 * f_friction.dot(&du_old);
            pending.friction_work -= 0.5 * f_friction.dot(&du);
            pending.internal_work += 0.5 * f_int.dot(&du);
            pending.external_work += 0.5 * f_out.dot(&du);
            pending.damping_work += 0.5 * damping.dot(&du);
            if self.history_node.get(i) == Some(&true) {
                closing.history_work += 0.5 * f_int.dot(&du_old);
                pending.history_work += 0.5 * f_int.dot(&du);
            }
            self.du_prev[i] = dt * v_new + dx_extra;
            self.v_full[i] = v_full;
            self.reaction[i] = r;
        }
        if !kinetic.is_finite() || !closing.internal_work.is_finite() {
            let element = self.most_strained_element();
            return Err((
                "non-finite kinetic energy or work (NaN or overflow)".into(),
                element,
            ));
        }
        self.energies.kinetic = kinetic;
        self.energies.internal_work += self.pending.internal_work + closing.internal_work;
        self.energies.external_work += self.pending.external_work + closing.external_work;
        self.energies.damping_work += self.pending.damping_work + closing.damping_work;
        self.energies.contact_work += self.pending.contact_work + closing.contact_work;
        self.energies.friction_work += self.pending.friction_work + closing.friction_work;
        self.energies.history_work += self.pending.history_work + closing.history_work;
        self.pending = pending;
        std::mem::swap(&mut self.v_half, &mut self.v_next);
        Ok(moved_too_far)
    }

    fn history_path(&self) -> Option<PathBuf> {
        self.output
            .dir
            .as_ref()
            .map(|d| d.join(format!("{}_history.csv", self.output.stem)))
    }

    /// Columns: time and step, the energies (`stored_energy` counts elastic bodies only; with
    /// microplane bodies, `microplane_internal_work`, their part of `internal_work`), then
    /// `<probe>_x/y/z` and `<constraint>_reaction_x/y/z`.
    fn history_columns(&self) -> Vec<String> {
        let mut c: Vec<String> = [
            "time",
            "step",
            "kinetic",
            "internal_work",
            "stored_energy",
            "external_work",
            "damping_work",
            "contact_work",
            "friction_work",
            "energy_error",
            "energy_error_relative",
            "momentum_x",
            "momentum_y",
            "momentum_z",
            "angular_momentum_x",
            "angular_momentum_y",
            "angular_momentum_z",
        ]
        .map(String::from)
        .to_vec();
        if !self.history_node.is_empty() {
            c.push("microplane_internal_work".into());
        }
        // Per body, when there are several: who holds the kinetic energy and the momentum
        // (the hammer's energy passing to the beam, thesis Figs. 10.11-10.14; (6.48)).
        if self.problem.model.bodies.len() > 1 {
            for b in &self.problem.model.bodies {
                c.push(format!("{}_kinetic", b.name));
                c.extend(["x", "y", "z"].map(|a| format!("{}_momentum_{a}", b.name)));
            }
        }
        c.extend(self.problem.probe_columns());
        for p in &self.problem.contact {
            c.extend(
                [
                    "force_x",
                    "force_y",
                    "force_z",
                    "normal",
                    "tangential",
                    "active",
                    "sliding",
                    "iterations",
                    "unresolved",
                ]
                .map(|q| format!("{}_{q}", p.name)),
            );
        }
        c
    }

    fn history_row(&self, e: &EnergyLedger) -> Vec<f64> {
        let model = &self.problem.model;
        let mut row = vec![
            self.time,
            self.step as f64,
            e.kinetic,
            e.internal_work,
            model.stored_energy(&self.u),
            e.external_work,
            e.damping_work,
            e.contact_work,
            e.friction_work,
            e.balance_error(),
            e.relative_error(),
        ];
        let momentum = fixed_order_sum3(model.node_count(), |i| self.v_full[i] * model.mass[i]);
        row.extend(momentum.iter());
        // About the origin, with the full-step velocity: the average of two values leapfrog
        // keeps exactly for torque-free forces, `sum m x_n x v_(n+1/2) = sum m x_(n+1) x v_(n+1/2)`.
        let angular = fixed_order_sum3(model.node_count(), |i| {
            (model.reference[i] + self.u[i]).cross(&self.v_full[i]) * model.mass[i]
        });
        row.extend(angular.iter());
        if !self.history_node.is_empty() {
            row.push(e.history_work);
        }
        if model.bodies.len() > 1 {
            for b in &model.bodies {
                let (mut kinetic, mut momentum) = (0.0, Vector3::zeros());
                for n in b.nodes.clone() {
                    kinetic += 0.5 * model.mass[n] * self.v_full[n].norm_squared();
                    momentum += self.v_full[n] * model.mass[n];
                }
                row.push(kinetic);
                row.extend(momentum.iter());
            }
        }
        self.problem.push_probe_values(
            &mut row,
            &self.u,
            Some(&self.v_full),
            &self.reaction,
            &self.constraint_of,
        );
        for (i, pair) in self.problem.contact.iter().enumerate() {
            let s = self.contact_steps.get(i).copied().unwrap_or_default();
            // The force the first body exerts on the second: the rate of the momentum that
            // contact gave the second body's nodes (both passes together, counted once).
            let force = match &self.contact {
                Some(c) => model.bodies[pair.bodies[1]]
                    .nodes
                    .clone()
                    .fold(Vector3::zeros(), |acc, n| acc + c.force[n]),
                None => Vector3::zeros(),
            };
            row.extend(force.iter());
            row.extend([
                s.normal_force,
                s.tangential_force,
                s.active as f64,
                s.sliding as f64,
                s.iterations as f64,
                s.unresolved as f64,
            ]);
        }
        row
    }

    fn write_frame(&self, writer: &mut PvdWriter) -> Result<PathBuf> {
        let model = &self.problem.model;
        let points: Vec<Vector3<f64>> = model
            .reference
            .iter()
            .zip(&self.u)
            .map(|(x, u)| x + u)
            .collect();
        writer.write_frame(&field_frame_with_history(
            model,
            Some(&self.history),
            &points,
            &self.u,
            Some(&self.v_full),
            self.time,
        ))
    }

    /// The element with the largest Green-Lagrange strain norm (or a non-finite one).
    fn most_strained_element(&self) -> Option<usize> {
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

    /// Writes what was computed, then builds the error that stops the run.
    fn stop(
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

    fn finish_step(&mut self) {
        for (u, du) in self.u.iter_mut().zip(&self.du_prev) {
            *u += du;
        }
        self.step += 1;
        self.time = self.step as f64 * self.dt;
    }
}

/// Buffers of the contact phase, allocated once per run.
struct ContactScratch {
    phase: crate::contact::ContactPhase,
    /// Inverse lumped mass per component; zero for prescribed components, which contact cannot
    /// move.
    inverse_mass: Vec<Vector3<f64>>,
    beta_0: f64,
    x0: Vec<Vector3<f64>>,
    x1: Vec<Vector3<f64>>,
    predicted: Vec<Vector3<f64>>,
    /// Contact force on each node over the step, `m dv (1/h + alpha/2)` with `h` the velocity
    /// update's step and `alpha` the mass-proportional damping (N).
    force: Vec<Vector3<f64>>,
    /// Position corrections made by the tangential parts of the contact forces.
    tangential_dx: Vec<Vector3<f64>>,
    /// The friction part of `force` (N).
    friction_force: Vec<Vector3<f64>>,
    /// `dx - dt dv` of the beta-2 corrections (zero for `beta_0 = 0`).
    position_surplus: Vec<Vector3<f64>>,
}

impl ContactScratch {
    fn new(problem: &Problem) -> Self {
        let model = &problem.model;
        let n = model.node_count();
        let prescribed = problem.constraint_map();
        let inverse_mass = (0..n)
            .map(|i| {
                Vector3::from_fn(|d, _| match prescribed[i][d] {
                    Some(_) => 0.0,
                    None => 1.0 / model.mass[i],
                })
            })
            .collect();
        Self {
            phase: crate::contact::ContactPhase::new(model, problem.contact.clone()),
            inverse_mass,
            beta_0: problem.contact.iter().map(|p| p.beta_0).fold(0.0, f64::max),
            x0: vec![Vector3::zeros(); n],
            x1: vec![Vector3::zeros(); n],
            predicted: vec![Vector3::zeros(); n],
            force: vec![Vector3::zeros(); n],
            tangential_dx: vec![Vector3::zeros(); n],
            friction_force: vec![Vector3::zeros(); n],
            position_surplus: vec![Vector3::zeros(); n],
        }
    }

    /// Corrects the predicted velocities `v_next` (and records forces) so that the positions
    /// `x + dt v` at the end of the step violate no contact (thesis 6.4.2.3, (6.58)-(6.61)).
    fn correct(
        &mut self,
        step: usize,
        model: &crate::model::Model,
        dt: f64,
        force_per_dv: f64,
        u: &[Vector3<f64>],
        v_next: &mut [Vector3<f64>],
    ) -> Vec<crate::contact::ContactStep> {
        for i in 0..u.len() {
            self.x0[i] = model.reference[i] + u[i];
            self.x1[i] = self.x0[i] + v_next[i] * dt;
        }
        self.predicted.copy_from_slice(&self.x1);
        self.tangential_dx.fill(Vector3::zeros());
        let mut steps = self.phase.resolve(
            step,
            model,
            &self.inverse_mass,
            dt,
            &self.x0,
            &mut self.x1,
            &mut self.tangential_dx,
        );
        // A multiplier r moves a node by beta dt^2 r / m and changes its velocity by
        // gamma dt r / m, gamma = 1/2 (FORMULATION 4): the velocity takes gamma / beta of the
        // correction (all of it for beta_0 = 0) and the force is gamma dt r times force_per_dv.
        const GAMMA: f64 = 0.5;
        let velocity_share = GAMMA / (self.beta_0 + 0.5);
        let force_per_dx = velocity_share / dt * force_per_dv;
        for i in 0..u.len() {
            let dx = self.x1[i] - self.predicted[i];
            let dv = dx * (velocity_share / dt);
            v_next[i] += dv;
            self.force[i] = dx * (model.mass[i] * force_per_dx);
            self.friction_force[i] = self.tangential_dx[i] * (model.mass[i] * force_per_dx);
            self.position_surplus[i] = dx - dv * dt;
        }
        for step in &mut steps {
            step.normal_force *= GAMMA * dt * force_per_dv;
            step.tangential_force *= GAMMA * dt * force_per_dv;
        }
        steps
    }
}

/// Sum of `term(i)` for `i < n` in index order, so the result does not depend on threads.
pub(crate) fn fixed_order_sum(n: usize, term: impl Fn(usize) -> f64) -> f64 {
    (0..n).map(term).sum()
}

/// [`fixed_order_sum`] of vectors.
fn fixed_order_sum3(n: usize, term: impl Fn(usize) -> Vector3<f64>) -> Vector3<f64> {
    (0..n).map(term).fold(Vector3::zeros(), |a, b| a + b)
}
