//! What a `material_point` block says: the parameter file, the experiment and its options, as
//! read from the case file.

use std::path::PathBuf;

use impact_solver::material::microplane::experiments::FracturePath;
use impact_solver::material::microplane::{MicroplaneParameters, SphereRule};
use serde::{Deserialize, Serialize};

use super::Quantity;

/// The `material_point` entry of a case: a parameter file, an experiment and its options. Each
/// experiment accepts the options listed in [`Experiment::options`]; any other is an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialPointSpec {
    /// The parameter file, relative to the case file.
    pub material: PathBuf,
    /// The virtual experiment to run on the material point.
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
    /// `tension_compression`: the held lateral stresses `sigma_22` (Pa, compression negative),
    /// one run each; 0 runs the uniaxial test the others are compared with.
    #[serde(default)]
    pub lateral_stresses: Vec<f64>,
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
    /// Tension under held lateral compressions beside uniaxial tension (Kupfer, Hilsdorf &
    /// Rüsch 1969).
    TensionCompression,
}

impl Experiment {
    /// The experiment's name as a case file writes it (`isotropy`, ...).
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
            Experiment::TensionCompression => "tension_compression",
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
            Experiment::TensionCompression => &["element_size", "lateral_stresses", "end", "steps"],
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
            Experiment::TensionCompression => &[LateralTensionPeak, LateralTensionRatio],
        }
    }
}

/// Closed strain cycles: a path from the first corner through the others and back, `repeat`
/// times, each leg cut into `steps` increments.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CycleSpec {
    /// Name of the cycle; a measure selects its k-th repetition as `name#k`.
    pub name: String,
    /// Strain corners `[11, 22, 33, 23, 13, 12]` (tensor shears).
    pub corners: Vec<[f64; 6]>,
    /// Number of times the closed path is run (default 1).
    #[serde(default = "one")]
    pub repeat: usize,
    /// Increments per leg between two corners (default 50).
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
    Mc2010Compression {
        /// Mean compressive strength `f_cm` (MPa).
        f_cm: f64,
        /// Tangent modulus at the origin `E_ci` (MPa).
        e_ci: f64,
        /// Strain at the peak `eps_c1` (magnitude).
        eps_c1: f64,
    },
    /// fib MC2010 bilinear softening in tension (`f_t` in MPa, `g_f` in N/mm).
    Mc2010Softening {
        /// Tensile strength (MPa).
        f_t: f64,
        /// Fracture energy (N/mm).
        g_f: f64,
    },
    /// Hordijk's (1991) softening curve, `w_c = 5.14 GF / ft` (`f_t` in MPa, `g_f` in N/mm).
    Hordijk1991Softening {
        /// Tensile strength (MPa).
        f_t: f64,
        /// Fracture energy (N/mm).
        g_f: f64,
    },
    /// CEB-FIP MC1990 dynamic increase factors for `f_cm` (MPa).
    CebFip1990Dif {
        /// Mean compressive strength `f_cm` (MPa).
        f_cm: f64,
    },
}
