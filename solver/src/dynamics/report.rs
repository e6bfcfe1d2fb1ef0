//! What a run that stopped early tells its user.

use std::fmt;
use std::path::PathBuf;

/// Why and where an explicit run stopped, with the energies at that moment.
#[derive(Debug, Clone, PartialEq)]
pub struct InstabilityReport {
    pub reason: String,
    pub step: usize,
    pub time: f64,
    /// The element at fault: the inverted one, or the most strained one.
    pub element: Option<usize>,
    pub kinetic: f64,
    pub internal_work: f64,
    pub external_work: f64,
    pub energy_error: f64,
    pub time_step: f64,
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
