//! Explicit dynamics: lumped mass, central differences, energies and instability detection
//! (thesis chapter 4, FORMULATION sections 2 and 3).

mod energy;
mod explicit;
mod report;

pub use energy::EnergyLedger;
pub use explicit::{ExplicitSettings, ExplicitSolver, OutputSettings, RunSummary, Snapshot};
pub use report::InstabilityReport;
