//! Explicit dynamics: lumped mass, central differences, energies and instability detection
//! (thesis chapter 4, FORMULATION sections 2 and 3).

mod checkpoint_every;
mod energy;
mod explicit;
mod settings;
mod stop_when;

pub use crate::error::InstabilityReport;
pub use crate::output::Snapshot;
pub use checkpoint_every::CheckpointEvery;
pub use energy::EnergyLedger;
pub use explicit::{
    keep_rank_element_data, keeps_own_elements, rank_ranges_of, restore_whole_problem,
};
pub use explicit::{
    ExplicitSolver, OutputSchedule, RestartState, RunState, ScheduleRecord, SegmentEnd,
};
pub use settings::{ContactTotals, ExplicitSettings, OutputSettings, PhaseTimes, RunSummary};
pub use stop_when::{StopProgress, StopWhen};
