//! Catalogue cases that run no scene but a virtual experiment on one material point of the
//! microplane concrete model (`material_point:` instead of `scene:`; CATALOGUE "Concrete
//! material"), judged with `material_point` metrics.
//!
//! A case names a parameter file (`cases/materials/*.yaml`: `parameters:` and an optional
//! `calibration:` record, which is accepted and ignored), an experiment and its options:
//!
//! ```yaml
//! material_point:
//!   material: ../materials/thesis-concrete.yaml   # relative to the case file
//!   experiment: uniaxial_tension                  # see `Experiment`
//!   element_size: 0.05                            # options of that experiment
//! metrics:
//!   - name: peak_stress
//!     unit: MPa
//!     measure: { material_point: { quantity: peak_stress } }
//!     reference: { value: { value: 2.7, source: "CATALOGUE: ft = 2.7 MPa" } }
//!     tolerance: { relative: 0.03 }
//! ```
//!
//! The experiments drive `impact_solver::material::microplane::experiments`; everything they
//! measure (judged or not) is recorded with the case ([`MaterialRecord`]): its values, tables
//! and plots with the targets drawn, for the report's "Concrete material" section. Stresses are
//! in MPa, moduli in MPa, fracture energies in N/mm, dissipation in J/m^3, strains plain.

mod error;
pub mod experiments;
pub mod plots;
mod quantity;
mod record;
pub mod report;
mod select;
mod spec;

pub use error::MaterialPointError;
pub use quantity::{Quantity, Value};
pub use record::{MaterialPlot, MaterialRecord, Outcome, RecordTable, RecordedValue, TargetBox};
use select::close;
pub use select::{rule_name, select, MaterialMeasure, PointMeasure, Selector, Targets};
pub use spec::{CycleSpec, Experiment, MaterialPointSpec, ReferenceCurve};

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use impact_solver::material::microplane::MicroplaneParameters;

use crate::case_kind::{
    parse_measures, refuse_parts, unfinished_result, Block, CaseKind, KindParseError, LoadedCase,
    RunOptions,
};
use crate::catalogue::{CaseSpec, Variant};
use crate::judge::judge_metrics;
use crate::results::CaseResult;

/// Reads the parameters of a parameter file with the solver's loader
/// ([`impact_solver::material::read_microplane_file`]: `parameters:` checked, an optional
/// `calibration:` record ignored, any other top-level key an error naming it).
pub fn read_parameters(path: &Path) -> Result<MicroplaneParameters, MaterialPointError> {
    Ok(impact_solver::material::read_microplane_file(path)?)
}

/// The options of `spec` that are given (non-default), by name.
fn given_options(spec: &MaterialPointSpec) -> Vec<&'static str> {
    [
        ("element_size", spec.element_size.is_some()),
        ("element_sizes", !spec.element_sizes.is_empty()),
        ("rate", spec.rate.is_some()),
        ("rates", !spec.rates.is_empty()),
        ("relative_to", spec.relative_to.is_some()),
        ("unit_check_rates", !spec.unit_check_rates.is_empty()),
        ("end", spec.end.is_some()),
        ("steps", spec.steps.is_some()),
        ("samples", spec.samples.is_some()),
        ("rules", !spec.rules.is_empty()),
        ("cycles", !spec.cycles.is_empty()),
        ("unload_at", spec.unload_at.is_some()),
        ("lateral_stresses", !spec.lateral_stresses.is_empty()),
        ("reference_curves", !spec.reference_curves.is_empty()),
    ]
    .into_iter()
    .filter(|(_, given)| *given)
    .map(|(name, _)| name)
    .collect()
}

fn positive(name: &str, v: f64) -> Result<(), MaterialPointError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(MaterialPointError::NotPositive {
            name: name.into(),
            value: v,
        })
    }
}

/// A case that runs a virtual experiment on one material point.
#[derive(Debug)]
pub struct MaterialPointCase {
    /// The case's `material_point:` block: material, experiment, its settings.
    pub spec: MaterialPointSpec,
    measures: Vec<MaterialMeasure>,
}

impl CaseKind for MaterialPointCase {
    fn name(&self) -> &'static str {
        "material_point"
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn run(&self, case: &LoadedCase, _: Option<&Variant>, _: &RunOptions) -> CaseResult {
        run_case(self, case)
    }
}

/// Reads a `material_point` case: its block, no scene, sweep, variants or plots beside it,
/// options that belong to the experiment, and metrics that measure a quantity of it. The
/// message says what to change.
pub fn parse(
    block: Option<&Block>,
    spec: &CaseSpec,
    base: &Path,
) -> Result<Arc<dyn CaseKind>, KindParseError> {
    let mut mp: MaterialPointSpec = block.ok_or(MaterialPointError::NoBlock)?.parse()?;
    if mp.material.is_relative() {
        mp.material = base.join(&mp.material);
    }
    let measures = validate(&mp, spec)?;
    Ok(Arc::new(MaterialPointCase { spec: mp, measures }))
}

fn validate(
    mp: &MaterialPointSpec,
    spec: &CaseSpec,
) -> Result<Vec<MaterialMeasure>, KindParseError> {
    refuse_parts(
        spec,
        &["scene", "sweep", "variants", "plots"],
        "a `material_point` case runs a virtual experiment, not a scene, with its own plots",
    )?;
    let accepted = mp.experiment.options();
    if let Some(o) = given_options(mp).iter().find(|o| !accepted.contains(o)) {
        return Err(MaterialPointError::UnreadOption {
            experiment: mp.experiment.name().into(),
            option: o.to_string(),
            accepted: accepted.join(", "),
        }
        .into());
    }
    for (name, v) in [
        ("element_size", mp.element_size),
        ("rate", mp.rate),
        ("relative_to", mp.relative_to),
        ("end", mp.end),
        ("unload_at", mp.unload_at),
    ] {
        if let Some(v) = v {
            positive(name, v)?;
        }
    }
    for (name, list) in [
        ("element_sizes", &mp.element_sizes),
        ("rates", &mp.rates),
        ("unit_check_rates", &mp.unit_check_rates),
    ] {
        for &v in list.iter() {
            positive(name, v)?;
        }
    }
    if mp.steps == Some(0) || mp.samples == Some(0) {
        return Err(MaterialPointError::ZeroSteps.into());
    }
    match mp.experiment {
        Experiment::CrackBand if mp.element_sizes.is_empty() => {
            return Err(needs("crack_band", "element_sizes"))
        }
        Experiment::Cyclic if mp.cycles.is_empty() => return Err(needs("cyclic", "cycles")),
        Experiment::TensionCompression
            if mp
                .lateral_stresses
                .iter()
                .any(|s| !s.is_finite() || *s > 0.0) =>
        {
            return Err(MaterialPointError::LateralStresses {
                stresses: mp.lateral_stresses.clone(),
            }
            .into())
        }
        Experiment::RateEffect => {
            let Some(r) = mp.relative_to else {
                return Err(needs("rate_effect", "relative_to"));
            };
            if !mp.rates.iter().any(|&x| close(x, r)) {
                return Err(MaterialPointError::RelativeTo {
                    relative_to: r,
                    rates: mp.rates.clone(),
                }
                .into());
            }
        }
        _ => {}
    }
    for c in &mp.cycles {
        if c.corners.len() < 2 || c.repeat == 0 || c.steps == 0 {
            return Err(MaterialPointError::ShortCycle {
                cycle: c.name.clone(),
            }
            .into());
        }
        if mp.cycles.iter().filter(|d| d.name == c.name).count() > 1 {
            return Err(MaterialPointError::CycleTwice {
                cycle: c.name.clone(),
            }
            .into());
        }
    }
    let quantities = mp.experiment.quantities();
    let measures: Vec<PointMeasure> = parse_measures(spec, "material_point")?;
    let measures: Vec<MaterialMeasure> = measures
        .into_iter()
        .map(|PointMeasure::MaterialPoint(m)| m)
        .collect();
    for (m, measure) in spec.metrics.iter().zip(&measures) {
        if !quantities.contains(&measure.quantity) {
            return Err(MaterialPointError::NotMeasured {
                metric: m.name.clone(),
                experiment: mp.experiment.name().into(),
                quantity: measure.quantity.name(),
                measured: quantities
                    .iter()
                    .map(|q| q.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }
            .into());
        }
    }
    Ok(measures)
}

/// The error of an experiment that lacks an option it needs.
fn needs(experiment: &str, option: &str) -> KindParseError {
    MaterialPointError::Needs {
        experiment: experiment.into(),
        option: option.into(),
    }
    .into()
}

/// `path` with `a/../` pairs removed (for display: `cases/material/../materials/x.yaml` reads
/// `cases/materials/x.yaml`).
fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in path.components() {
        match c {
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out.iter().collect()
}

/// Runs a `material_point` case: the experiment, its metrics, and the record for the report. A
/// panic inside the model is caught and reported as an error of this case alone.
fn run_case(kind: &MaterialPointCase, case: &LoadedCase) -> CaseResult {
    let spec = &case.spec;
    let started = Instant::now();
    let mut result = unfinished_result(spec, "default");
    let mp = &kind.spec;
    let parameters = match read_parameters(&mp.material) {
        Ok(p) => p,
        Err(e) => {
            result.message = Some(e.to_string());
            return result;
        }
    };
    let targets = Targets::new(spec, &kind.measures);
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        experiments::run(mp, &parameters, &targets)
    }));
    result.wall_s = started.elapsed().as_secs_f64();
    let outcome = match outcome {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => {
            result.message = Some(format!("the experiment could not run: {e}"));
            return result;
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            result.message = Some(format!("the experiment panicked: {what}"));
            return result;
        }
    };
    let mut judged_by: Vec<Vec<String>> = vec![Vec::new(); outcome.values.len()];
    let judgement = judge_metrics(
        &spec.metrics,
        None,
        &mut |i, m, _| {
            let measure = &kind.measures[i];
            let value = select(measure, &outcome.values)?;
            for (i, v) in outcome.values.iter().enumerate() {
                if v.quantity == measure.quantity && measure.at().selects(&v.at) {
                    judged_by[i].push(m.name.clone());
                }
            }
            Ok::<_, MaterialPointError>(value)
        },
        &|_| None,
    );
    let notes: Vec<String> = outcome
        .notes
        .iter()
        .chain(&outcome.setup)
        .cloned()
        .collect();
    let (status, message) = judgement.verdict(&notes);
    result.status = status;
    result.message = Some(message);
    result.metrics = judgement.metrics;
    let record = MaterialRecord {
        material: lexically_normal(&mp.material).display().to_string(),
        experiment: mp.experiment.name().to_string(),
        setup: outcome.setup,
        values: outcome
            .values
            .iter()
            .zip(judged_by)
            .map(|(v, judged_by)| RecordedValue {
                quantity: v.quantity.name(),
                at: v.at.label(),
                value: v.value,
                unit: v.quantity.unit().to_string(),
                judged_by,
            })
            .collect(),
        tables: outcome.tables,
        plots: outcome.plots,
        notes: outcome.notes,
    };
    result.set_record(MaterialRecord::KEY, &record);
    result
}
