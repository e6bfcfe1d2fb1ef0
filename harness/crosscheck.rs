//! Independent cross-checks (issue 8): the solver against code written by others, reached
//! through Python (cargo feature `python`, [`python`]) and cached in
//! `references/crosscheck/cache/` so that default runs and CI need no Python ([`cache`]).
//!
//! A catalogue case with `crosscheck:` runs one of them; its metrics measure named quantities of
//! the comparison (`measure: { crosscheck: <quantity> }`) and the report's "Independent
//! cross-checks" section states whether the independent answer was computed in the run or read
//! from the cache, with its date and package versions.
//!
//! - [`elastic_beam`]: the thesis beam in elastic three-point bending against scikit-fem
//!   (quadratic tetrahedra, converged).
//! - [`ccd`]: our vertex-face continuous collision detection against ipctk's Tight-Inclusion.

pub mod cache;
pub mod ccd;
pub mod ccd_queries;
pub mod elastic_beam;
pub mod error;
pub mod python;
pub mod report;

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::case_kind::{
    parse_measures, refuse_parts, unfinished_result, Block, CaseKind, KindParseError, LoadedCase,
    RefreshError, RunOptions,
};
use crate::catalogue::{CaseSpec, Variant};
use crate::judge::judge_metrics;
use crate::results::{case_dir, CaseResult};
use crate::results::{MaterialPlot, RecordTable};
use error::CrosscheckError;

/// Why a `crosscheck` case is refused: each message names the part or metric and what to change.
#[derive(Debug, thiserror::Error)]
pub enum CrosscheckKindError {
    /// The kind's block is missing.
    #[error("a crosscheck case needs its `crosscheck` block")]
    NoBlock,
    /// An elastic-beam cross-check without a scene.
    #[error("crosscheck elastic_beam compares solutions of the case's `scene`: add one")]
    ElasticBeamNeedsScene,
    /// A CCD cross-check with a scene.
    #[error(
        "crosscheck ccd runs no scene of its own: remove `scene` (the runs it records are named \
         under `record`)"
    )]
    CcdRunsNoScene,
    /// A metric whose quantity the cross-check does not give.
    #[error("metric `{metric}` measures `{quantity}`, which crosscheck {crosscheck} does not give; it gives {gives}")]
    NotGiven {
        /// The metric.
        metric: String,
        /// The quantity it measures.
        quantity: String,
        /// The cross-check's name.
        crosscheck: String,
        /// The quantities it gives, comma separated.
        gives: String,
    },
}
pub use cache::{AnswerMode, Provenance};

/// The `crosscheck:` entry of a case: which independent comparison it runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CrosscheckSpec {
    /// The elastic beam of the case's scene against scikit-fem (`references/crosscheck/`).
    ElasticBeam(elastic_beam::ElasticBeamSpec),
    /// Our vertex-face CCD against ipctk on seeded random and recorded queries.
    Ccd(ccd::CcdSpec),
}

impl CrosscheckSpec {
    /// The comparison's name with the independent code, as the report shows it.
    pub fn name(&self) -> &'static str {
        match self {
            CrosscheckSpec::ElasticBeam(_) => "elastic_beam (scikit-fem)",
            CrosscheckSpec::Ccd(_) => "ccd (ipctk)",
        }
    }

    /// The quantities its metrics may measure.
    pub fn quantities(&self) -> &'static [&'static str] {
        match self {
            CrosscheckSpec::ElasticBeam(_) => &elastic_beam::QUANTITIES,
            CrosscheckSpec::Ccd(_) => &ccd::QUANTITIES,
        }
    }
}

/// What a cross-check case recorded, for the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrosscheckRecord {
    /// The comparison's name ([`CrosscheckSpec::name`]).
    pub kind: String,
    /// Fresh or cached, with the date and versions of the independent answer.
    pub provenance: Option<Provenance>,
    /// Lines describing the setup (sizes, settings) of both sides.
    #[serde(default)]
    pub setup: Vec<String>,
    /// Every quantity measured, judged or not.
    #[serde(default)]
    pub quantities: std::collections::BTreeMap<String, f64>,
    /// Tables of the report (per-query disagreements, per-point differences).
    #[serde(default)]
    pub tables: Vec<RecordTable>,
    /// Plots of the report.
    #[serde(default)]
    pub plots: Vec<MaterialPlot>,
    /// What a reader should know (fallbacks, skipped parts).
    #[serde(default)]
    pub notes: Vec<String>,
}

impl CrosscheckRecord {
    /// Its key among a case result's records.
    pub const KEY: &'static str = "crosscheck";
}

/// What a `crosscheck` case measures: `{ crosscheck: <quantity> }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CrosscheckMeasure {
    /// The name of a quantity the comparison gives ([`CrosscheckSpec::quantities`]).
    Crosscheck(String),
}

/// A case that compares the solver with independent code.
#[derive(Debug)]
pub struct CrosscheckCase {
    /// The case's `crosscheck:` block.
    pub spec: CrosscheckSpec,
    /// The quantity each metric measures.
    quantities: Vec<String>,
}

impl CaseKind for CrosscheckCase {
    fn name(&self) -> &'static str {
        "crosscheck"
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn run(&self, case: &LoadedCase, _: Option<&Variant>, options: &RunOptions) -> CaseResult {
        run_case(self, case, options)
    }

    fn refresh(&self, case: &LoadedCase) -> Option<Result<String, RefreshError>> {
        Some(refresh(self, case).map(|p| p.line()).map_err(Into::into))
    }
}

/// Reads a `crosscheck` case: the scene it needs (elastic_beam) or none (ccd), no sweep,
/// variants or plots, and metrics that measure its quantities. The message says what to
/// change.
pub fn parse(
    block: Option<&Block>,
    spec: &CaseSpec,
    _base: &Path,
) -> Result<Arc<dyn CaseKind>, KindParseError> {
    let c: CrosscheckSpec = block.ok_or(CrosscheckKindError::NoBlock)?.parse()?;
    let needs_scene = matches!(c, CrosscheckSpec::ElasticBeam(_));
    if needs_scene != spec.scene.is_some() {
        return Err(if needs_scene {
            CrosscheckKindError::ElasticBeamNeedsScene
        } else {
            CrosscheckKindError::CcdRunsNoScene
        }
        .into());
    }
    refuse_parts(
        spec,
        &["sweep", "variants", "plots"],
        "a `crosscheck` case runs its own comparison, with its own tables and plots",
    )?;
    let measures: Vec<CrosscheckMeasure> = parse_measures(spec, "crosscheck")?;
    let mut quantities = Vec::new();
    for (m, CrosscheckMeasure::Crosscheck(q)) in spec.metrics.iter().zip(measures) {
        if !c.quantities().contains(&q.as_str()) {
            return Err(CrosscheckKindError::NotGiven {
                metric: m.name.clone(),
                quantity: q.clone(),
                crosscheck: c.name().to_string(),
                gives: c.quantities().join(", "),
            }
            .into());
        }
        quantities.push(q);
    }
    Ok(Arc::new(CrosscheckCase {
        spec: c,
        quantities,
    }))
}

/// Runs a `crosscheck` case and judges its metrics.
fn run_case(kind: &CrosscheckCase, case: &LoadedCase, options: &RunOptions) -> CaseResult {
    let spec = &case.spec;
    let started = Instant::now();
    let mut result = unfinished_result(spec, "default");
    let c = &kind.spec;
    let case_folder = case.path.parent().unwrap_or(Path::new("."));
    let time_limit = spec.time_limit_s.unwrap_or(options.time_limit_s);
    let outcome = match c {
        CrosscheckSpec::ElasticBeam(b) => spec
            .scene
            .as_ref()
            .ok_or(CrosscheckError::NeedsScene)
            .and_then(|scene| elastic_beam::run(b, scene, time_limit))
            .map(|o| {
                (
                    o.quantities,
                    o.provenance,
                    o.setup,
                    o.tables,
                    vec![],
                    o.notes,
                )
            }),
        CrosscheckSpec::Ccd(ccd) => {
            let scratch = case_dir(
                &options
                    .output_dir
                    .clone()
                    .unwrap_or_else(std::env::temp_dir),
                &spec.id,
            );
            ccd::run(ccd, case_folder, &scratch).map(|o| {
                (
                    o.quantities,
                    o.provenance,
                    o.setup,
                    o.tables,
                    o.plots,
                    o.notes,
                )
            })
        }
    };
    result.wall_s = started.elapsed().as_secs_f64();
    let (quantities, provenance, setup, tables, plots, notes) = match outcome {
        Ok(o) => o,
        Err(e) => {
            result.message = Some(format!("the cross-check could not run: {e}"));
            return result;
        }
    };
    let source = match provenance.mode {
        AnswerMode::Cached => format!("{} (cached {})", provenance.script, provenance.date),
        AnswerMode::Fresh => format!("{} (fresh)", provenance.script),
    };
    let mut judgement = judge_metrics(
        &spec.metrics,
        spec.scene.as_ref(),
        &mut |i, _, _| {
            let q = &kind.quantities[i];
            quantities
                .get(q)
                .copied()
                .ok_or_else(|| CrosscheckError::NotMeasured {
                    quantity: q.clone(),
                })
        },
        &|_| None,
    );
    for m in &mut judgement.metrics {
        m.reference_source = format!("{}; against {source}", m.reference_source);
    }
    let notes: Vec<String> = std::iter::once(provenance.line())
        .chain(notes.iter().cloned())
        .collect();
    let (status, message) = judgement.verdict(&notes);
    result.status = status;
    result.message = Some(message);
    result.metrics = judgement.metrics;
    let record = CrosscheckRecord {
        kind: c.name().into(),
        provenance: Some(provenance),
        setup,
        quantities,
        tables,
        plots,
        notes,
    };
    result.set_record(CrosscheckRecord::KEY, &record);
    result
}

/// Recomputes the independent answers of the cases and writes them to the cache
/// (`impact-vv crosscheck-refresh`; needs the `python` feature).
fn refresh(kind: &CrosscheckCase, case: &LoadedCase) -> Result<Provenance, CrosscheckError> {
    let case_folder = case.path.parent().unwrap_or(Path::new("."));
    match &kind.spec {
        CrosscheckSpec::ElasticBeam(b) => {
            let scene = case
                .spec
                .scene
                .as_ref()
                .ok_or(CrosscheckError::NeedsScene)?;
            let request = elastic_beam::request(b, scene)?;
            cache::refresh("skfem_beam.py", &request, &cache::cache_path(&b.cache))
        }
        CrosscheckSpec::Ccd(c) => ccd::refresh(c, case_folder),
    }
}
