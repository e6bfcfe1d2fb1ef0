//! The V&V harness of the concrete-impact solver: runs scenes and benchmark cases against their
//! references and reports the verdicts.

pub mod execute;
pub mod progress;
pub mod report;
pub mod results;
pub mod scene_run;
