//! (in progress)
#[derive(Debug)]
pub struct InstabilityReport;
impl std::fmt::Display for InstabilityReport { fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result { write!(f, "unstable") } }
