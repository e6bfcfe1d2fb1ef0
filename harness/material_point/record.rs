//! What a `material_point` case keeps for the report: its values, tables and plots, and what an
//! experiment hands back to build them.

use serde::{Deserialize, Serialize};

use super::Value;
use crate::results::lenient;

/// Everything a `material_point` case measured and drew, for the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialRecord {
    /// The parameter file as the case names it.
    pub material: String,
    /// The experiment's name (`uniaxial_tension`, `uniaxial_compression`, ...).
    pub experiment: String,
    /// How it ran: element size and where it came from, rates, paths.
    #[serde(default)]
    pub setup: Vec<String>,
    /// Every value measured, judged or not.
    #[serde(default)]
    pub values: Vec<RecordedValue>,
    /// Tables of measured against target (plain text cells).
    #[serde(default)]
    pub tables: Vec<RecordTable>,
    /// Plots of the report.
    #[serde(default)]
    pub plots: Vec<MaterialPlot>,
    /// Paths that stopped early, and other things a reader should know.
    #[serde(default)]
    pub notes: Vec<String>,
}

impl MaterialRecord {
    /// Its key among a case result's records.
    pub const KEY: &'static str = "material";
}

/// A measured value in the record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordedValue {
    /// The quantity's name (`Quantity::name`).
    pub quantity: String,
    /// Which run (`h = 25 mm`, `rate 1e-3 /s`, ...); empty for an experiment's only run.
    #[serde(default)]
    pub at: String,
    /// The value, in `unit`.
    #[serde(deserialize_with = "lenient::f64")]
    pub value: f64,
    /// Its unit (`Quantity::unit`).
    pub unit: String,
    /// The metrics that judged it.
    #[serde(default)]
    pub judged_by: Vec<String>,
}

pub use crate::results::{MaterialPlot, RecordTable, TargetBox};

/// What an experiment produced.
#[derive(Debug, Default)]
pub struct Outcome {
    /// Every value measured, with the run that gave it.
    pub values: Vec<Value>,
    /// How it ran: element size, rates, paths.
    pub setup: Vec<String>,
    /// Tables of measured against target.
    pub tables: Vec<RecordTable>,
    /// Plots of the report.
    pub plots: Vec<MaterialPlot>,
    /// Paths that stopped early, and other things a reader should know.
    pub notes: Vec<String>,
}
