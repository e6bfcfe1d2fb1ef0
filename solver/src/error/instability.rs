//! What an explicit run that stopped early tells its user: the report
//! [`super::SolverError::Unstable`] carries.

use std::fmt;
use std::path::PathBuf;

/// Why and where an explicit run stopped, with the energies at that moment.
#[derive(Debug, Clone, PartialEq)]
pub struct InstabilityReport {
    /// What went wrong, e.g. an inverted element or an energy balance error beyond tolerance.
    pub reason: String,
    /// Number of time steps completed when the run stopped.
    pub step: usize,
    /// Simulated time at the stop (s).
    pub time: f64,
    /// The element at fault: the inverted one, or the most strained one.
    pub element: Option<usize>,
    /// Kinetic energy at the stop (J).
    pub kinetic: f64,
    /// Work of the internal forces since the start (J): stored plus dissipated in the material.
    pub internal_work: f64,
    /// Work of loads, gravity and reaction forces at prescribed nodes since the start (J).
    pub external_work: f64,
    /// Energy balance error `K + W_int + ... - W_ext - K_0` at the stop (J,
    /// [`crate::dynamics::EnergyLedger::balance_error`]).
    pub energy_error: f64,
    /// The time step of the run (s).
    pub time_step: f64,
    /// The stable limit of the run's mesh and materials (s).
    pub critical_time_step: f64,
    /// Output files written before the stop (history CSV, field frames).
    pub written: Vec<PathBuf>,
}

impl fmt::Display for InstabilityReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "run stopped at step {} (t = {:.6e} s): {}",
            self.step, self.time, self.reason
        )?;
        if let Some(e) = self.element {
            write!(f, "; element {e}")?;
        }
        write!(
            f,
            ". Energies: kinetic {:.6e} J, internal work {:.6e} J, external work {:.6e} J, \
             balance error {:.6e} J. Time step {:.6e} s (stable estimate {:.6e} s). \
             Fix: lower the time step or the safety factor, or check the loading",
            self.kinetic,
            self.internal_work,
            self.external_work,
            self.energy_error,
            self.time_step,
            self.critical_time_step
        )?;
        if !self.written.is_empty() {
            write!(f, ". Output written up to the stop: ")?;
            for (i, p) in self.written.iter().enumerate() {
                write!(f, "{}{}", if i > 0 { ", " } else { "" }, p.display())?;
            }
        }
        Ok(())
    }
}
