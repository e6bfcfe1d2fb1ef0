//! The energy balance of a run (FORMULATION section 3).

/// Energies accumulated by the time stepper, all in joules.
///
/// Works are integrated with the trapezoidal rule over each displacement increment:
/// `W += 1/2 (f_n + f_{n+1}) . (x_{n+1} - x_n)`. The stepper adds `1/2 f_n . du_{n-1/2}` to close
/// the interval ending at `t_n` and keeps `1/2 f_n . du_{n+1/2}` pending for the next one, so the
/// values read at `t_n` are complete up to `t_n`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyLedger {
    /// Kinetic energy at the current full step, `1/2 sum m v^2`.
    pub kinetic: f64,
    /// Kinetic energy at the start of the run.
    pub initial_kinetic: f64,
    /// Work of the internal forces: stored plus dissipated energy.
    pub internal_work: f64,
    /// Work of loads, gravity and reaction forces at prescribed nodes.
    pub external_work: f64,
    /// Work dissipated by mass-proportional damping.
    pub damping_work: f64,
    /// Energy taken out of the bodies by the normal components of the contact forces (minus
    /// their work on the nodes): near zero for exactly enforced contact, positive with the
    /// high-frequency damping of `beta_0 > 0`.
    pub contact_work: f64,
    /// Energy taken out by the tangential (friction) components: never negative for Coulomb
    /// friction, which opposes slip (FORMULATION section 3).
    pub friction_work: f64,
    /// The part of `internal_work` done on the nodes of bodies with history (microplane
    /// concrete): what they store plus what they dissipate. Their material defines no stored
    /// energy, so once their stress has dropped to zero (an open crack) all of it was
    /// dissipated. Not a separate term of the balance.
    pub history_work: f64,
    /// Energy the remeshings put in (J): the sum of their jumps in total (kinetic plus stored)
    /// energy, [`crate::remesh::RemeshRecord::total_energy_jump`]; 0 in a run without
    /// remeshing. A term of the balance, so that a remeshing's jump is reported, not flagged.
    pub remesh_work: f64,
}

impl EnergyLedger {
    /// `K + W_int + W_damp + W_contact + W_friction - W_ext - K_0 - W_remesh`: zero for an exact
    /// balance.
    pub fn balance_error(&self) -> f64 {
        self.kinetic
            + self.internal_work
            + self.damping_work
            + self.contact_work
            + self.friction_work
            - self.external_work
            - self.initial_kinetic
            - self.remesh_work
    }

    /// The energy scale the error is measured against: the largest of the energy put in
    /// (`K_0 + |W_ext|`), the kinetic energy and the internal work.
    pub fn scale(&self) -> f64 {
        (self.initial_kinetic + self.external_work.abs())
            .max(self.kinetic)
            .max(self.internal_work.abs())
    }

    /// Balance error relative to [`Self::scale`] (zero when nothing has happened yet).
    pub fn relative_error(&self) -> f64 {
        let s = self.scale();
        if s > 0.0 {
            self.balance_error() / s
        } else {
            0.0
        }
    }
}
