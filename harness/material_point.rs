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

pub mod experiments;
pub mod plots;
pub mod report;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use impact_solver::material::microplane::experiments::FracturePath;
use impact_solver::material::microplane::{MicroplaneParameters, SphereRule};
use serde::{Deserialize, Serialize};

use crate::case_kind::{
    parse_measures, unfinished_result, Block, CaseKind, LoadedCase, RunOptions,
};
use crate::catalogue::{CaseSpec, Tolerance, Variant};
use crate::judge::judge_metrics;
use crate::results::{lenient, CaseResult};

/// The `material_point` entry of a case: a parameter file, an experiment and its options. Each
/// experiment accepts the options listed in [`Experiment::options`]; any other is an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialPointSpec {
    /// The parameter file, relative to the case file.
    pub material: PathBuf,
    pub experiment: Experiment,
    /// Element size `h` of the crack band (m); default the file's `h_ref`.
    #[serde(default)]
    pub element_size: Option<f64>,
    /// Element sizes of a crack-band study (m).
    #[serde(default)]
    pub element_sizes: Vec<f64>,
    /// Strain rate (1/s); default the quasi-static rate of the experiments (1e-8 /s).
    #[serde(default)]
    pub rate: Option<f64>,
    /// Strain rates of a rate study (1/s).
    #[serde(default)]
    pub rates: Vec<f64>,
    /// Rate the peak ratios of a rate study are taken against (1/s); one of `rates`.
    #[serde(default)]
    pub relative_to: Option<f64>,
    /// Rates of the unit check of the rate law (uniaxial strain, against the quasi-static path).
    #[serde(default)]
    pub unit_check_rates: Vec<f64>,
    /// Strain magnitude at the end of a compressive path.
    #[serde(default)]
    pub end: Option<f64>,
    /// Increments of a compressive path (per leg for cycles).
    #[serde(default)]
    pub steps: Option<usize>,
    /// Random strain directions of the isotropy check.
    #[serde(default)]
    pub samples: Option<usize>,
    /// Sphere rules of the isotropy check; default both.
    #[serde(default)]
    pub rules: Vec<SphereRule>,
    /// Closed strain cycles.
    #[serde(default)]
    pub cycles: Vec<CycleSpec>,
    /// Axial strain after the tensile peak where the unloading stiffness is measured.
    #[serde(default)]
    pub unload_at: Option<f64>,
    /// Published curves drawn beside the model's (not judged unless a metric says so).
    #[serde(default)]
    pub reference_curves: Vec<ReferenceCurve>,
    /// `uniaxial_tension`, `crack_band`: the path of the tension tests, uniaxial stress or
    /// `bonded` (lateral strains held after the peak). Default: the path on which the
    /// calibration defines GF for the material's tension driver (`FracturePath::of_driver`).
    #[serde(default)]
    pub fracture_path: Option<FracturePath>,
}

impl MaterialPointSpec {
    /// The tension tests' path for a material with these parameters.
    pub fn fracture_path_for(&self, params: &MicroplaneParameters) -> FracturePath {
        self.fracture_path
            .unwrap_or_else(|| FracturePath::of_driver(params.tension_driver))
    }
}

/// The virtual experiments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Experiment {
    /// Elastic response in random strain directions against Hooke's law, per sphere rule.
    Isotropy,
    /// Strain-driven uniaxial tension, lateral stresses zero, to 1e-3 of the peak.
    UniaxialTension,
    /// Strain-driven uniaxial compression, lateral stresses zero.
    UniaxialCompression,
    /// Equal biaxial compression beside uniaxial compression on the same strain grid.
    EqualBiaxial,
    /// Hydrostatic compression and unloading.
    Hydrostatic,
    /// Closed strain cycles, with and without the deviatoric trace term, and the unloading
    /// stiffness after the tensile peak.
    Cyclic,
    /// Uniaxial tension at several element sizes.
    CrackBand,
    /// The rate law's unit check, and tension and compression peaks over strain rates.
    RateEffect,
}

impl Experiment {
    pub fn name(self) -> &'static str {
        match self {
            Experiment::Isotropy => "isotropy",
            Experiment::UniaxialTension => "uniaxial_tension",
            Experiment::UniaxialCompression => "uniaxial_compression",
            Experiment::EqualBiaxial => "equal_biaxial",
            Experiment::Hydrostatic => "hydrostatic",
            Experiment::Cyclic => "cyclic",
            Experiment::CrackBand => "crack_band",
            Experiment::RateEffect => "rate_effect",
        }
    }

    /// The options this experiment reads.
    pub fn options(self) -> &'static [&'static str] {
        match self {
            Experiment::Isotropy => &["samples", "rules"],
            Experiment::UniaxialTension => &["element_size", "rate"],
            Experiment::UniaxialCompression => {
                &["element_size", "rate", "end", "steps", "reference_curves"]
            }
            Experiment::EqualBiaxial | Experiment::Hydrostatic => &["element_size", "end", "steps"],
            Experiment::Cyclic => &["element_size", "cycles", "unload_at"],
            Experiment::CrackBand => &["element_sizes", "rate", "reference_curves"],
            Experiment::RateEffect => &[
                "element_size",
                "rates",
                "relative_to",
                "unit_check_rates",
                "end",
                "steps",
                "reference_curves",
            ],
        }
    }

    /// The quantities this experiment measures.
    pub fn quantities(self) -> &'static [Quantity] {
        use Quantity::*;
        match self {
            Experiment::Isotropy => &[IsotropyError, StiffnessIsotropyError, SolverIsotropyError],
            Experiment::UniaxialTension => &[
                PeakStress,
                PeakStrain,
                InitialSlope,
                FractureEnergy,
                FinalStressRatio,
                PostPeakRise,
            ],
            Experiment::UniaxialCompression => &[
                PeakStress,
                PeakStrain,
                InitialSlope,
                InitialPoisson,
                PoissonAtPeak,
                LargestPoissonAfterPeak,
                DilatancyOnset,
                Mc2010CurveMisfit,
            ],
            Experiment::EqualBiaxial => &[BiaxialPeakStress, PeakStress, BiaxialRatio],
            Experiment::Hydrostatic => &[
                Damaged,
                CompactionThenStiffening,
                SmallestSecantRatio,
                LargestSecantRatio,
                InitialBulkModulus,
                ResidualVolumetricStrain,
                CycleDissipation,
                ReturnedWorkFraction,
                ReturnedWorkFractionClosedForm,
                ReturnedWorkFractionError,
            ],
            Experiment::Cyclic => &[
                SmallestDissipation,
                SmallestRelativeDissipation,
                ReturnedEnergyFraction,
                CycleDissipation,
                Healed,
                UnloadingSlope,
                UnloadingSecant,
                UnloadingPosition,
            ],
            Experiment::CrackBand => &[
                FractureEnergy,
                PeakStress,
                PeakStrain,
                FinalStressRatio,
                PostPeakRise,
                SofteningStressRatioAtW1,
                SofteningEndOpening,
            ],
            Experiment::RateEffect => &[
                RateScalingError,
                RateScalingMisfit,
                InitialSlope,
                TensionPeakStress,
                TensionPeakRatio,
                CompressionPeakStress,
                CompressionPeakRatio,
                InitialSlopeSpread,
            ],
        }
    }
}

/// Closed strain cycles: a path from the first corner through the others and back, `repeat`
/// times, each leg cut into `steps` increments.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CycleSpec {
    pub name: String,
    /// Strain corners `[11, 22, 33, 23, 13, 12]` (tensor shears).
    pub corners: Vec<[f64; 6]>,
    #[serde(default = "one")]
    pub repeat: usize,
    #[serde(default = "default_cycle_steps")]
    pub steps: usize,
}

fn one() -> usize {
    1
}

fn default_cycle_steps() -> usize {
    50
}

/// A published curve drawn beside the model's (stresses in MPa).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ReferenceCurve {
    /// fib MC2010 compressive stress-strain curve (Sargin form), `reference::concrete`.
    Mc2010Compression { f_cm: f64, e_ci: f64, eps_c1: f64 },
    /// fib MC2010 bilinear softening in tension (`f_t` in MPa, `g_f` in N/mm).
    Mc2010Softening { f_t: f64, g_f: f64 },
    /// Hordijk's (1991) softening curve, `w_c = 5.14 GF / ft` (`f_t` in MPa, `g_f` in N/mm).
    Hordijk1991Softening { f_t: f64, g_f: f64 },
    /// CEB-FIP MC1990 dynamic increase factors for `f_cm` (MPa).
    CebFip1990Dif { f_cm: f64 },
}

/// What a `material_point` metric measures: a quantity of the experiment, and which of its runs
/// when it has several (element size, strain rate, sphere rule, cycle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialMeasure {
    pub quantity: Quantity,
    /// Element size (m) of a crack-band run.
    #[serde(default)]
    pub element_size: Option<f64>,
    /// Strain rate (1/s) of a rate-study run.
    #[serde(default)]
    pub rate: Option<f64>,
    /// Sphere rule of an isotropy run.
    #[serde(default)]
    pub rule: Option<SphereRule>,
    /// A cycle's name (`name#k` for its k-th repetition).
    #[serde(default)]
    pub cycle: Option<String>,
    /// Cycles run with the deviatoric trace term (true, the default) or without (false).
    #[serde(default)]
    pub deviatoric_trace_term: Option<bool>,
}

impl MaterialMeasure {
    /// The runs this measure selects.
    pub fn at(&self) -> Selector {
        Selector {
            element_size: self.element_size,
            rate: self.rate,
            rule: self.rule,
            cycle: self.cycle.clone(),
            deviatoric_trace_term: self.deviatoric_trace_term,
        }
    }
}

/// Which run of an experiment a value belongs to; in a measure, a field left out matches any.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Selector {
    /// Element size (m).
    pub element_size: Option<f64>,
    /// Strain rate (1/s).
    pub rate: Option<f64>,
    pub rule: Option<SphereRule>,
    /// A cycle's name (`name#k` for its k-th repetition).
    pub cycle: Option<String>,
    /// With the deviatoric trace term of the homogenisation (cycles).
    pub deviatoric_trace_term: Option<bool>,
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

impl Selector {
    /// Whether a value measured at `value` is selected: every field given here matches.
    pub fn selects(&self, value: &Selector) -> bool {
        let num = |want: Option<f64>, have: Option<f64>| match (want, have) {
            (None, _) => true,
            (Some(w), Some(h)) => close(w, h),
            (Some(_), None) => false,
        };
        num(self.element_size, value.element_size)
            && num(self.rate, value.rate)
            && self.rule.is_none_or(|r| value.rule == Some(r))
            && self
                .cycle
                .as_ref()
                .is_none_or(|c| value.cycle.as_ref() == Some(c))
            && self
                .deviatoric_trace_term
                .is_none_or(|t| value.deviatoric_trace_term.unwrap_or(true) == t)
    }

    /// A short label, e.g. `h = 25 mm`, `rate 1e-3 /s`; empty when nothing is set.
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        if let Some(h) = self.element_size {
            parts.push(format!("h = {} mm", crate::report::format::num(h * 1e3)));
        }
        if let Some(r) = self.rate {
            parts.push(format!("rate {r:e} /s"));
        }
        if let Some(r) = self.rule {
            parts.push(rule_name(r).to_string());
        }
        if let Some(c) = &self.cycle {
            parts.push(format!("cycle {c}"));
        }
        match self.deviatoric_trace_term {
            // (The model's default is on since issue 16; off is the thesis' homogenisation.)
            Some(true) => parts.push("with trace term".into()),
            Some(false) => parts.push("thesis default (no trace term)".into()),
            None => {}
        }
        parts.join(", ")
    }
}

/// The name of a sphere rule as the parameter files spell it.
pub fn rule_name(r: SphereRule) -> &'static str {
    match r {
        SphereRule::BazantOh21 => "bazant_oh21",
        SphereRule::Bazant37 => "bazant37",
    }
}

/// The quantities the experiments measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Largest relative deviation from Hooke's law (file's E and nu, computed here) of the
    /// model's update at a strain of magnitude 1e-20 over random directions.
    IsotropyError,
    /// The same for the model's homogenised elastic stiffness matrix.
    StiffnessIsotropyError,
    /// The solver's own isotropy check (`experiments::isotropy_error`), as a cross-check.
    SolverIsotropyError,
    /// Largest |axial stress| (MPa; compression as a magnitude).
    PeakStress,
    /// Axial strain at the peak (magnitude).
    PeakStrain,
    /// Axial stress over axial strain at the first increment (MPa); in a rate study, at a strain
    /// of 1e-12 in elastic uniaxial stress (Young's modulus at that rate).
    InitialSlope,
    /// `h int sigma d eps` over the whole path (N/mm).
    FractureEnergy,
    /// Stress at the end of the path over the peak.
    FinalStressRatio,
    /// Largest rise of the stress above its running minimum after the peak, over the peak:
    /// zero for a monotonically softening branch.
    PostPeakRise,
    /// Apparent Poisson ratio `-eps_22 / eps_11` at the first increment.
    InitialPoisson,
    PoissonAtPeak,
    LargestPoissonAfterPeak,
    /// Axial strain where the volumetric strain is most compressive (NaN if it never turns).
    DilatancyOnset,
    /// RMS of model minus the MC2010 curve over the reference's pre-peak branch `[0, eps_c1]`
    /// (MPa).
    Mc2010CurveMisfit,
    /// Peak of `-sigma_11` under equal biaxial compression (MPa).
    BiaxialPeakStress,
    /// Biaxial over uniaxial compressive peak.
    BiaxialRatio,
    /// 1 if any microplane branch lost stiffness along the path, else 0.
    Damaged,
    /// 1 if the secant bulk modulus on loading first falls below, then rises above, the initial
    /// one (by 1e-3 of it), else 0.
    CompactionThenStiffening,
    /// Smallest and largest secant bulk modulus over the initial one on loading.
    SmallestSecantRatio,
    LargestSecantRatio,
    /// Bulk modulus of the first increment (MPa).
    InitialBulkModulus,
    /// Volumetric strain where the pressure first returns to zero on unloading (magnitude;
    /// zero if it does only at zero strain).
    ResidualVolumetricStrain,
    /// Hydrostatic load-unload cycle: work given back on unloading over the work of loading
    /// (trapezoidal rule along the model's path).
    ReturnedWorkFraction,
    /// The same computed here in closed form from the volumetric law (5.21) and its unloading
    /// rule (slope max(E_V0, tangent) at the turning point), independently of the solver.
    ReturnedWorkFractionClosedForm,
    /// `|model / closed form - 1|`.
    ReturnedWorkFractionError,
    /// Softening against the crack opening `w = h (eps - sigma/E)`: stress over the peak where
    /// the opening reaches `w1 = GF / ft` of the case's softening reference curve.
    SofteningStressRatioAtW1,
    /// Opening where the stress has fallen to 1 % of the peak (mm): the end `w_c` of the law.
    SofteningEndOpening,
    /// Smallest work `oint sigma : d eps` over the repetitions of a closed cycle (J/m^3).
    SmallestDissipation,
    /// The same over `oint |sigma : d eps|` of the cycle.
    SmallestRelativeDissipation,
    /// Its negative: the largest fraction of a repetition's work `oint |sigma : d eps|` that the
    /// cycle gives back (negative when every repetition dissipates).
    ReturnedEnergyFraction,
    /// Work over one repetition of a closed cycle (`cycle: name#k`), or over the hydrostatic
    /// load-unload cycle (J/m^3).
    CycleDissipation,
    /// 1 if any branch's secant rose along the path (damage healed), else 0.
    Healed,
    /// Slope of the first unloading increment after the tensile peak (MPa).
    UnloadingSlope,
    /// Secant `sigma / eps` where unloading starts (MPa).
    UnloadingSecant,
    /// `(slope - secant) / (E - secant)`: in [0, 1] when the unloading slope lies between the
    /// secant and E.
    UnloadingPosition,
    /// `|peak ratio / F ratio - 1|` of the rate law's unit check, with `F` computed here.
    RateScalingError,
    /// The solver's largest relative misfit along the scaled path of the unit check.
    RateScalingMisfit,
    /// Uniaxial tensile peak at a rate (MPa) and its ratio to the peak at `relative_to`.
    TensionPeakStress,
    TensionPeakRatio,
    /// Uniaxial compressive peak at a rate (MPa) and its ratio to the peak at `relative_to`.
    CompressionPeakStress,
    CompressionPeakRatio,
    /// `(max - min) / mean` of the initial slopes (`initial_slope`) over the rates.
    InitialSlopeSpread,
}

impl Quantity {
    pub fn name(self) -> String {
        serde_json::to_value(self)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default()
    }

    pub fn unit(self) -> &'static str {
        use Quantity::*;
        match self {
            PeakStress
            | InitialSlope
            | Mc2010CurveMisfit
            | BiaxialPeakStress
            | InitialBulkModulus
            | UnloadingSlope
            | UnloadingSecant
            | TensionPeakStress
            | CompressionPeakStress => "MPa",
            FractureEnergy => "N/mm",
            SofteningEndOpening => "mm",
            SmallestDissipation | CycleDissipation => "J/m^3",
            _ => "-",
        }
    }
}

/// One measured value of an experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    pub quantity: Quantity,
    pub at: Selector,
    pub value: f64,
}

/// Everything a `material_point` case measured and drew, for the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialRecord {
    /// The parameter file as the case names it.
    pub material: String,
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
    pub quantity: String,
    /// Which run (`h = 25 mm`, `rate 1e-3 /s`, ...); empty for an experiment's only run.
    #[serde(default)]
    pub at: String,
    #[serde(deserialize_with = "lenient::f64")]
    pub value: f64,
    pub unit: String,
    /// The metrics that judged it.
    #[serde(default)]
    pub judged_by: Vec<String>,
}

pub use crate::results::{MaterialPlot, RecordTable, TargetBox};

/// Reads the parameters of a parameter file with the solver's loader
/// ([`impact_solver::material::read_microplane_file`]: `parameters:` checked, an optional
/// `calibration:` record ignored, any other top-level key an error naming it).
pub fn read_parameters(path: &Path) -> Result<MicroplaneParameters, String> {
    impact_solver::material::read_microplane_file(path).map_err(|e| e.to_string())
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
        ("reference_curves", !spec.reference_curves.is_empty()),
    ]
    .into_iter()
    .filter(|(_, given)| *given)
    .map(|(name, _)| name)
    .collect()
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(format!("material_point: {name} must be positive, got {v}"))
    }
}

/// What a `material_point` case measures: `{ material_point: { quantity, at } }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PointMeasure {
    MaterialPoint(MaterialMeasure),
}

/// A case that runs a virtual experiment on one material point.
#[derive(Debug)]
pub struct MaterialPointCase {
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
) -> Result<Arc<dyn CaseKind>, String> {
    let mut mp: MaterialPointSpec = block
        .ok_or("a material_point case needs its `material_point` block")?
        .parse()?;
    if mp.material.is_relative() {
        mp.material = base.join(&mp.material);
    }
    let measures = validate(&mp, spec)?;
    Ok(Arc::new(MaterialPointCase { spec: mp, measures }))
}

fn validate(mp: &MaterialPointSpec, spec: &CaseSpec) -> Result<Vec<MaterialMeasure>, String> {
    let others = [
        ("scene", spec.scene.is_some()),
        ("sweep", spec.sweep.is_some()),
        ("variants", !spec.variants.is_empty()),
        ("plots", !spec.plots.is_empty()),
    ];
    if let Some((key, _)) = others.iter().find(|(_, given)| *given) {
        return Err(format!(
            "a `material_point` case runs a virtual experiment, not a scene: remove `{key}` \
             (its plots come with the experiment)"
        ));
    }
    let accepted = mp.experiment.options();
    if let Some(o) = given_options(mp).iter().find(|o| !accepted.contains(o)) {
        return Err(format!(
            "material_point: experiment `{}` does not read `{o}`; it reads {}",
            mp.experiment.name(),
            accepted.join(", ")
        ));
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
        return Err("material_point: steps and samples must be at least 1".into());
    }
    match mp.experiment {
        Experiment::CrackBand if mp.element_sizes.is_empty() => {
            return Err("material_point: crack_band needs `element_sizes`".into())
        }
        Experiment::Cyclic if mp.cycles.is_empty() => {
            return Err("material_point: cyclic needs `cycles`".into())
        }
        Experiment::RateEffect => {
            let Some(r) = mp.relative_to else {
                return Err("material_point: rate_effect needs `relative_to`".into());
            };
            if !mp.rates.iter().any(|&x| close(x, r)) {
                return Err(format!(
                    "material_point: relative_to = {r:e} must be one of `rates` {:?}",
                    mp.rates
                ));
            }
        }
        _ => {}
    }
    for c in &mp.cycles {
        if c.corners.len() < 2 || c.repeat == 0 || c.steps == 0 {
            return Err(format!(
                "material_point: cycle `{}` needs two corners or more, repeat >= 1 and steps >= 1",
                c.name
            ));
        }
        if mp.cycles.iter().filter(|d| d.name == c.name).count() > 1 {
            return Err(format!("material_point: cycle `{}` appears twice", c.name));
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
            return Err(format!(
                "metric `{}`: experiment `{}` does not measure `{}`; it measures {}",
                m.name,
                mp.experiment.name(),
                measure.quantity.name(),
                quantities
                    .iter()
                    .map(|q| q.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    Ok(measures)
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

/// The value a measure selects among an experiment's values: exactly one must match.
pub fn select(measure: &MaterialMeasure, values: &[Value]) -> Result<f64, String> {
    let of_quantity: Vec<&Value> = values
        .iter()
        .filter(|v| v.quantity == measure.quantity)
        .collect();
    let chosen: Vec<&&Value> = of_quantity
        .iter()
        .filter(|v| measure.at().selects(&v.at))
        .collect();
    let available = || {
        of_quantity
            .iter()
            .map(|v| format!("`{}`", v.at.label()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match chosen.as_slice() {
        [one] => Ok(one.value),
        [] if of_quantity.is_empty() => Err(format!(
            "the experiment measured no `{}` (its path may have stopped early)",
            measure.quantity.name()
        )),
        [] => Err(format!(
            "no `{}` at {}; measured at {}",
            measure.quantity.name(),
            measure.at().label(),
            available()
        )),
        _ => Err(format!(
            "`{}` was measured at {}: say which (element_size, rate, rule, cycle or \
             deviatoric_trace_term)",
            measure.quantity.name(),
            available()
        )),
    }
}

/// The acceptance band of each metric, known before the run (reference and tolerance), so that
/// the plots can draw the targets.
#[derive(Debug, Clone, Default)]
pub struct Targets {
    entries: Vec<(MaterialMeasure, f64, [f64; 2])>,
}

impl Targets {
    fn new(spec: &CaseSpec, measures: &[MaterialMeasure]) -> Self {
        let entries = spec
            .metrics
            .iter()
            .zip(measures)
            .filter_map(|(m, measure)| {
                let (r, _) = m.reference.as_ref()?.evaluate_for(None).ok()?;
                let band = match &m.tolerance {
                    Tolerance::Relative(t) => [r - t * r.abs(), r + t * r.abs()],
                    Tolerance::Absolute(t) => [r - t, r + t],
                    Tolerance::AtMost(t) => [f64::NEG_INFINITY, *t],
                    Tolerance::AtLeast(t) => [*t, f64::INFINITY],
                    Tolerance::AtLeastRatio(t) => [t * r, f64::INFINITY],
                    Tolerance::RelativeToPeak { .. } => return None,
                };
                Some((measure.clone(), r, band))
            })
            .collect();
        Targets { entries }
    }

    /// The band of the first metric on `quantity` whose selector selects `at`.
    pub fn band(&self, quantity: Quantity, at: &Selector) -> Option<[f64; 2]> {
        self.find(quantity, at).map(|e| e.2)
    }

    /// The reference value of the first metric on `quantity` whose selector selects `at`.
    pub fn reference(&self, quantity: Quantity, at: &Selector) -> Option<f64> {
        self.find(quantity, at).map(|e| e.1)
    }

    fn find(&self, quantity: Quantity, at: &Selector) -> Option<&(MaterialMeasure, f64, [f64; 2])> {
        self.entries
            .iter()
            .find(|(m, _, _)| m.quantity == quantity && m.at().selects(at))
    }
}

/// What an experiment produced.
#[derive(Debug, Default)]
pub struct Outcome {
    pub values: Vec<Value>,
    pub setup: Vec<String>,
    pub tables: Vec<RecordTable>,
    pub plots: Vec<MaterialPlot>,
    pub notes: Vec<String>,
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
            result.message = Some(e);
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
            Ok(value)
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
