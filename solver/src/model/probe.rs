//! Probes: the node sets whose mean displacement or velocity, or summed reaction, a history
//! records (`crate::problem::Problem::probes`).

use serde::{Deserialize, Serialize};

/// What a probe records, three components: the mean over its nodes of a nodal field, or the
/// sum of the reactions on them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProbeQuantity {
    /// Mean displacement of the probe's nodes (m).
    Displacement,
    /// Mean velocity of the probe's nodes (m/s), at the full step.
    Velocity,
    /// The resultant of the boundary-condition reactions on the probe's nodes (N), a sum, not
    /// a mean: the force one line of nodes of a rigid plate carries, for example.
    Reaction,
}

/// A history of the mean displacement or velocity of a node set.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name of the probe; its history columns are `<name>_x`, `_y`, `_z`.
    pub name: String,
    /// The probed nodes, as indices into the model's node arrays.
    pub nodes: Vec<u32>,
    /// What is recorded over the nodes.
    pub quantity: ProbeQuantity,
}
