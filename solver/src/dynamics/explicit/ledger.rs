//! The energy ledger of a step: full-step velocities, reactions, the mesh stability check and
//! the work of each force over the interval (FORMULATION 2), summed leaf by leaf
//! ([`crate::distributed::NodePlan`]) so that every rank count gives the same bits.

use nalgebra::Vector3;

use super::ExplicitSolver;
use crate::dynamics::EnergyLedger;

/// A node's (and a leaf's) terms: the kinetic energy, the work closing the last interval and
/// the work opened for the coming one (internal, external, damping, contact, friction, history),
/// and whether the node moved too far.
const KINETIC: usize = 0;
const CLOSING: usize = 1;
const PENDING: usize = 7;
const MOVED: usize = 13;
const WIDTH: usize = 14;

/// The six works of `terms[at..at + 6]`.
fn works(terms: &[f64], at: usize) -> EnergyLedger {
    EnergyLedger {
        internal_work: terms[at],
        external_work: terms[at + 1],
        damping_work: terms[at + 2],
        contact_work: terms[at + 3],
        friction_work: terms[at + 4],
        history_work: terms[at + 5],
        ..EnergyLedger::default()
    }
}

impl<'p> ExplicitSolver<'p> {
    /// Full-step velocity, reactions, the mesh stability check and the energy pieces of this
    /// step (FORMULATION 2: the work of each force over the interval, trapezoidal), for this
    /// rank's nodes; the sums over nodes are folded leaf by leaf across the ranks (collective).
    pub(super) fn energy_ledger(
        &mut self,
        h: f64,
    ) -> std::result::Result<bool, (String, Option<usize>)> {
        let model = &self.problem.model;
        let (dt, alpha) = (self.dt, self.settings.damping);
        let first = self.step == 0;
        // At the first step after a resume with a new time step, v_n lies dt_before / 2 after
        // v_{n-1/2}, not midway to v_{n+1/2}.
        let resume_weight = match self.dt_before_resume {
            Some(before) if self.step == self.step_origin && !first => Some(0.5 * before / h),
            _ => None,
        };
        let eta = self.settings.mesh_stability_eta;
        let mut node = |i: usize, terms: &mut [f64; WIDTH]| {
            let m = model.mass[i];
            let v_new = self.v_next[i];
            let v_full = if first {
                self.v_half[i]
            } else if let Some(w) = resume_weight {
                self.v_half[i] + w * (v_new - self.v_half[i])
            } else {
                0.5 * (self.v_half[i] + v_new)
            };
            let mut r = Vector3::zeros();
            let cs = self.constraint_of[i];
            let walled = |d: usize| self.walls.holds(i, d);
            if cs.iter().any(Option::is_some) || (0..3).any(walled) {
                let a = (v_new - self.v_half[i]) / h;
                let total = m * a + alpha * m * v_full - self.f_ext[i] + self.f_int[i];
                for d in 0..3 {
                    if cs[d].is_some() || walled(d) {
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
            if du.norm() > eta * self.node_length[i] {
                terms[MOVED] += 1.0;
            }
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
            terms[KINETIC] += 0.5 * m * v_full.norm_squared();
            let history = self.history_node.get(i) == Some(&true);
            for (at, d) in [(CLOSING, du_old), (PENDING, du)] {
                terms[at] += 0.5 * f_int.dot(&d);
                terms[at + 1] += 0.5 * f_out.dot(&d);
                terms[at + 2] += 0.5 * damping.dot(&d);
                terms[at + 3] -= 0.5 * f_normal.dot(&d);
                terms[at + 4] -= 0.5 * f_friction.dot(&d);
                if history {
                    terms[at + 5] += 0.5 * f_int.dot(&d);
                }
            }
            self.du_prev[i] = dt * v_new + dx_extra;
            self.v_full[i] = v_full;
            self.reaction[i] = r;
        };
        let plan = &self.nodes;
        let mut shares = Vec::with_capacity(WIDTH * plan.my_leaves().len());
        for &k in plan.my_leaves() {
            let mut leaf = [0.0; WIDTH];
            for i in plan.leaf_nodes(k) {
                node(i, &mut leaf);
            }
            shares.extend(leaf);
        }
        let mut ignored = [0.0; WIDTH];
        for i in plan.extra().iter().flat_map(Clone::clone) {
            node(i, &mut ignored);
        }
        let comm = self.ranks.as_ref().map(|r| r.comm());
        let totals = plan.fold(comm, WIDTH, &shares);
        let (kinetic, closing, pending) = (
            totals[KINETIC],
            works(&totals, CLOSING),
            works(&totals, PENDING),
        );
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
        Ok(totals[MOVED] > 0.0)
    }
}
