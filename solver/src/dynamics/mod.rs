//! Explicit dynamics: lumped mass, central differences, energies and instability detection
//! (thesis chapter 4, FORMULATION sections 2 and 3).

mod energy;
mod explicit;
mod settings;
mod stop_when;

pub use crate::error::InstabilityReport;
pub use crate::output::Snapshot;
pub use energy::EnergyLedger;
pub use explicit::{ExplicitSolver, OutputSchedule, RunState, SegmentEnd};
pub use settings::{ContactTotals, ExplicitSettings, OutputSettings, PhaseTimes, RunSummary};
pub use stop_when::{StopProgress, StopWhen};
