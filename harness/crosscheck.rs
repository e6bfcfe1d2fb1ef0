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
pub mod python;

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::catalogue::{CaseSpec, LoadedCase};
use crate::judge::judge;
use crate::material_point::{MaterialPlot, RecordTable};
use crate::measure::Measure;
use crate::results::{CaseResult, Status};
use crate::runner::RunOptions;
pub use cache::Provenance;

/// The `crosscheck:` entry of a case: which independent comparison it runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CrosscheckSpec {
    ElasticBeam(elastic_beam::ElasticBeamSpec),
    Ccd(ccd::CcdSpec),
}

impl CrosscheckSpec {
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
    pub kind: String,
    /// Fresh or cached, with the date and versions of the independent answer.
    pub provenance: Option<Provenance>,
    #[serde(default)]
    pub setup: Vec<String>,
    /// Every quantity measured, judged or not.
    #[serde(default)]
    pub quantities: std::collections::BTreeMap<String, f64>,
    #[serde(default)]
    pub tables: Vec<RecordTable>,
    #[serde(default)]
    pub plots: Vec<MaterialPlot>,
    #[serde(default)]
    pub notes: Vec<String>,
}

/// Checks a `crosscheck` case: the scene it needs (elastic_beam) or none (ccd), no sweep,
/// variants or plots, and metrics that measure its quantities. The message says what to change.
pub fn validate(spec: &CaseSpec) -> Result<(), String> {
    let Some(c) = &spec.crosscheck else {
        if let Some(m) = spec
            .metrics
            .iter()
            .find(|m| matches!(m.measure, Measure::Crosscheck(_)))
        {
            return Err(format!(
                "metric `{}` measures a cross-check: it needs a case with `crosscheck`",
                m.name
            ));
        }
        return Ok(());
    };
    let needs_scene = matches!(c, CrosscheckSpec::ElasticBeam(_));
    if needs_scene != spec.scene.is_some() {
        return Err(if needs_scene {
            "crosscheck elastic_beam compares solutions of the case's `scene`: add one".into()
        } else {
            "crosscheck ccd runs no scene of its own: remove `scene` (the runs it records are \
             named under `record`)"
                .into()
        });
    }
    let others = [
        ("contact_problems", spec.contact_problems.is_some()),
        ("material_point", spec.material_point.is_some()),
        ("sweep", spec.sweep.is_some()),
        ("variants", !spec.variants.is_empty()),
        ("plots", !spec.plots.is_empty()),
    ];
    if let Some((key, _)) = others.iter().find(|(_, given)| *given) {
        return Err(format!(
            "a `crosscheck` case runs its own comparison: remove `{key}` (its tables and plots \
             come with the comparison)"
        ));
    }
    for m in &spec.metrics {
        let Measure::Crosscheck(q) = &m.measure else {
            return Err(format!(
                "metric `{}`: a `crosscheck` case takes `crosscheck: <quantity>` measures only",
                m.name
            ));
        };
        if !c.quantities().contains(&q.as_str()) {
            return Err(format!(
                "metric `{}` measures `{q}`, which crosscheck {} does not give; it gives {}",
                m.name,
                c.name(),
                c.quantities().join(", ")
            ));
        }
    }
    Ok(())
}

/// Runs a `crosscheck` case and judges its metrics.
pub fn run_case(case: &LoadedCase, options: &RunOptions) -> CaseResult {
    let spec = &case.spec;
    let started = Instant::now();
    let mut result = crate::runner::unfinished_result(spec, "default");
    let Some(c) = &spec.crosscheck else {
        result.message = Some("the case has no crosscheck".into());
        return result;
    };
    let case_dir = case.path.parent().unwrap_or(Path::new("."));
    let time_limit = spec.time_limit_s.unwrap_or(options.time_limit_s);
    let outcome = match c {
        CrosscheckSpec::ElasticBeam(b) => spec
            .scene
            .as_ref()
            .ok_or_else(|| "elastic_beam needs a scene".to_string())
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
            let scratch = options
                .output_dir
                .clone()
                .unwrap_or_else(std::env::temp_dir)
                .join("cases")
                .join(spec.id.replace('/', "__"));
            ccd::run(ccd, case_dir, &scratch).map(|o| {
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
    let source = match provenance.mode.as_str() {
        "cached" => format!("{} (cached {})", provenance.script, provenance.date),
        _ => format!("{} (fresh)", provenance.script),
    };
    let mut failures = Vec::new();
    for m in &spec.metrics {
        let Measure::Crosscheck(q) = &m.measure else {
            continue;
        };
        let Some(reference) = &m.reference else {
            failures.push(format!(
                "metric `{}` has no reference: every metric needs one",
                m.name
            ));
            continue;
        };
        let judged = reference
            .evaluate_for(spec.scene.as_ref())
            .map_err(|e| format!("metric `{}`: reference: {e}", m.name))
            .and_then(|(r, s)| {
                quantities
                    .get(q)
                    .map(|v| (*v, r, s))
                    .ok_or_else(|| format!("metric `{}`: `{q}` was not measured", m.name))
            });
        match judged {
            Ok((value, r, s)) => {
                let s = format!("{s}; against {source}");
                result.metrics.push(judge(m, value, r, &s, &|_| None));
            }
            Err(e) => failures.push(e),
        }
    }
    failures.extend(result.metrics.iter().filter(|m| !m.pass).map(|m| {
        format!(
            "failed: `{}` = {:.6e} against {:.6e} (tolerance {:.3e})",
            m.name, m.value, m.reference, m.tolerance
        )
    }));
    result.status = if failures.is_empty() {
        Status::Pass
    } else {
        Status::Fail
    };
    let mut message = failures;
    message.push(provenance.line());
    message.extend(notes.iter().cloned());
    result.message = Some(message.join("; "));
    result.crosscheck = Some(CrosscheckRecord {
        kind: c.name().into(),
        provenance: Some(provenance),
        setup,
        quantities,
        tables,
        plots,
        notes,
    });
    result
}

/// Recomputes the independent answers of the cases and writes them to the cache
/// (`impact-vv crosscheck-refresh`; needs the `python` feature).
pub fn refresh(case: &LoadedCase) -> Result<Provenance, String> {
    let case_dir = case.path.parent().unwrap_or(Path::new("."));
    match &case.spec.crosscheck {
        Some(CrosscheckSpec::ElasticBeam(b)) => {
            let scene = case
                .spec
                .scene
                .as_ref()
                .ok_or("elastic_beam needs a scene")?;
            let request = elastic_beam::request(b, scene)?;
            cache::refresh("skfem_beam.py", &request, &cache::cache_path(&b.cache))
        }
        Some(CrosscheckSpec::Ccd(c)) => ccd::refresh(c, case_dir),
        None => Err(format!("case `{}` has no crosscheck", case.spec.id)),
    }
}
