//! How often a run writes a checkpoint (`analysis.explicit.checkpoint`), the file from which a
//! later process resumes it bit for bit ([`crate::restart`]).

use serde::{Deserialize, Serialize};

/// `checkpoint: { every_s: 60 }` (wall time) or `{ every_steps: N }`; with both, whichever
/// comes first.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckpointEvery {
    /// Seconds of wall time between two checkpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every_s: Option<f64>,
    /// Steps between two checkpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every_steps: Option<usize>,
}

impl CheckpointEvery {
    /// Whether it asks for any checkpoint at all.
    pub fn is_set(&self) -> bool {
        self.every_s.is_some() || self.every_steps.is_some()
    }

    /// An error message naming the key when a value is out of range: `every_s` positive and
    /// finite, `every_steps` at least 1.
    pub fn check(&self) -> Result<(), String> {
        if let Some(s) = self.every_s.filter(|s| !(*s > 0.0 && s.is_finite())) {
            return Err(format!(
                "checkpoint.every_s must be a positive, finite number of seconds, got {s}"
            ));
        }
        if self.every_steps == Some(0) {
            return Err("checkpoint.every_steps counts steps: at least 1".into());
        }
        Ok(())
    }
}
