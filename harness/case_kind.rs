//! The interface every kind of case implements (a scene, a material-point experiment, a
//! comparison of contact solvers on stored problems, a cross-check with independent code), and
//! the registry that names them.
//!
//! A case file is read in two passes (`crate::catalogue::load_case`): the parts every case has
//! (id, tier, metrics, plots, ...) and, under one top-level key, the kind's own block. The
//! registry maps that key to the kind's `parse` function; a file with none of the keys is a
//! case of the registry's default kind. The catalogue, runner, judge and report know no kind by
//! name: they see `dyn CaseKind`. The list itself lives in `crate::registry`, the one module
//! that imports the kinds.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use serde::de::DeserializeOwned;

use crate::catalogue::{CaseSpec, Variant};
use crate::results::CaseResult;

/// Why a kind's block or the common part of a case file does not fit the kind: each kind's
/// parser returns its own error type, boxed here so that the registry knows no kind's error.
pub type KindParseError = Box<dyn std::error::Error + Send + Sync>;

/// Why a cache of independent answers cannot be recomputed (`impact-vv crosscheck-refresh`),
/// boxed as [`KindParseError`] is: the kind's own error type.
pub type RefreshError = Box<dyn std::error::Error + Send + Sync>;

/// What every kind refuses in the same words: a block that does not parse, a part of the common
/// schema the kind does not use, a metric whose measure is not one of the kind's.
#[derive(Debug, thiserror::Error)]
pub enum KindError {
    /// The kind's block does not read as the kind's schema.
    #[error("`{key}`: {source}")]
    Block {
        /// The kind's key.
        key: String,
        /// The YAML reader's error, with the file's line.
        source: serde_norway::Error,
    },
    /// The kind's block is empty.
    #[error("`{key}`: the block is empty")]
    EmptyBlock {
        /// The kind's key.
        key: String,
    },
    /// A part of the common schema that the kind does not use.
    #[error("{why}: remove `{part}`")]
    RefusedPart {
        /// Why the kind does not use it.
        why: String,
        /// The part (`scene`, `sweep`, `variants`, `plots`).
        part: String,
    },
    /// A metric whose measure is not one of the kind's.
    #[error("metric `{metric}`: not a measure of a {kind} case: {source}")]
    Measure {
        /// The metric.
        metric: String,
        /// The kind's name.
        kind: String,
        /// The YAML reader's error.
        source: serde_norway::Error,
    },
}

/// Options of a harness run, as each case sees them.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Where the cases' solver output goes (`crate::results::case_dir`); `None`
    /// keeps it in memory.
    pub output_dir: Option<PathBuf>,
    /// Wall-time limit per solver run unless the case sets its own (s).
    pub time_limit_s: f64,
    /// Run cases in parallel.
    pub parallel: bool,
    /// Set by a signal: running explicit analyses stop at the end of their step and cases not
    /// started are not run; both are recorded as interrupted.
    pub stop: Option<Arc<AtomicBool>>,
    /// Print each case's log lines (`crate::case_log`) to stderr as well as to its log file
    /// (`impact-vv run --verbose`).
    pub verbose: bool,
}

/// A case with the file it came from and its kind.
#[derive(Debug, Clone)]
pub struct LoadedCase {
    /// The case file it was read from.
    pub path: PathBuf,
    /// The common part of the case: name, tier, metrics, bands.
    pub spec: CaseSpec,
    /// What the case runs and how it measures its metrics.
    pub kind: Arc<dyn CaseKind>,
}

/// A kind of case: what it runs and how it measures each of the case's metrics. Judging is
/// the same for every kind (`crate::judge::judge_metrics`).
pub trait CaseKind: std::fmt::Debug + Send + Sync {
    /// The kind's name: its key in a case file, or the default kind's name.
    fn name(&self) -> &'static str;

    /// Runs `case` under `variant` (`None`: as the file says), measures and judges its
    /// metrics. A kind without variants is only called with `None`.
    fn run(&self, case: &LoadedCase, variant: Option<&Variant>, options: &RunOptions)
        -> CaseResult;

    /// The kind itself, for tools and tests that read its block (`downcast_ref`).
    fn as_any(&self) -> &dyn std::any::Any;

    /// Recomputes the independent answers a case keeps in a cache (`impact-vv
    /// crosscheck-refresh`): a line saying what was written, or why not. `None`: this kind keeps
    /// no cache.
    fn refresh(&self, _case: &LoadedCase) -> Option<Result<String, RefreshError>> {
        None
    }
}

/// A kind's block of a case file: its key, and the file's text with every line outside the
/// block blanked, so that errors inside it give the file's own line numbers.
#[derive(Debug, Clone)]
pub struct Block {
    /// The kind's key in the case file (e.g. `material_point`, `crosscheck`).
    pub key: String,
    /// The whole file's text with the lines outside the block blanked.
    pub text: String,
}

impl Block {
    /// The block's value, read strictly (the kind's types deny unknown fields).
    pub fn parse<T: DeserializeOwned>(&self) -> Result<T, KindError> {
        let de = serde_norway::Deserializer::from_str(&self.text);
        let mut map: std::collections::BTreeMap<String, T> =
            serde_norway::with::singleton_map_recursive::deserialize(de).map_err(|source| {
                KindError::Block {
                    key: self.key.clone(),
                    source,
                }
            })?;
        map.remove(&self.key).ok_or_else(|| KindError::EmptyBlock {
            key: self.key.clone(),
        })
    }
}

/// The result of a case before it has run: an error until something better is known.
pub fn unfinished_result(spec: &CaseSpec, variant: &str) -> CaseResult {
    CaseResult {
        id: spec.id.clone(),
        variant: variant.into(),
        status: crate::results::Status::Error,
        wall_s: 0.0,
        metrics: Vec::new(),
        description: spec.description.clone(),
        tier: spec.tier.name().into(),
        tags: spec.tags.clone(),
        message: None,
        plots: Vec::new(),
        sweep: None,
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        peak_memory_mib: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

/// Reads a kind from its block (`None` for the default kind, which has no key) and the common
/// part of the case, already read with its paths resolved against the case file's folder
/// (`base`). It checks everything the kind needs of the case (a scene or none, the metrics'
/// measures, sweeps, variants) and says what to change.
pub type ParseKind = fn(
    block: Option<&Block>,
    case: &CaseSpec,
    base: &std::path::Path,
) -> Result<Arc<dyn CaseKind>, KindParseError>;

/// A kind registered under its key in a case file.
#[derive(Debug, Clone, Copy)]
pub struct KindEntry {
    /// The top-level key of a case file that selects the kind.
    pub key: &'static str,
    /// Builds the kind from its block of the case file.
    pub parse: ParseKind,
}

/// The kinds a catalogue is read with: those named by a key, and the kind of a case that names
/// none.
#[derive(Debug, Clone, Copy)]
pub struct Registry {
    /// The kinds selected by a key of the case file.
    pub keyed: &'static [KindEntry],
    /// The kind of a case file that holds none of the keys.
    pub default: ParseKind,
}

/// Refuses the parts of the common schema that a kind does not use: the first of `parts`
/// (`scene`, `sweep`, `variants`, `plots`) that `case` gives is an error, `why` followed by
/// the part to remove.
pub fn refuse_parts(case: &CaseSpec, parts: &[&str], why: &str) -> Result<(), KindError> {
    let given = |part: &&&str| match **part {
        "scene" => case.scene.is_some(),
        "sweep" => case.sweep.is_some(),
        "variants" => !case.variants.is_empty(),
        "plots" => !case.plots.is_empty(),
        other => unreachable!("`{other}` is not an optional part of a case"),
    };
    match parts.iter().find(given) {
        Some(part) => Err(KindError::RefusedPart {
            why: why.into(),
            part: part.to_string(),
        }),
        None => Ok(()),
    }
}

/// The metrics' measures of `case` read as the kind's measure type `M`, in the metrics' order.
/// The error names the metric.
pub fn parse_measures<M: DeserializeOwned>(
    case: &CaseSpec,
    kind: &str,
) -> Result<Vec<M>, KindError> {
    case.metrics
        .iter()
        .map(|m| {
            serde_norway::with::singleton_map_recursive::deserialize(m.measure.clone()).map_err(
                |source| KindError::Measure {
                    metric: m.name.clone(),
                    kind: kind.into(),
                    source,
                },
            )
        })
        .collect()
}
