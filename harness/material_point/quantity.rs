//! The quantities the experiments measure, their names and units, and one measured value.

use serde::{Deserialize, Serialize};

use super::Selector;

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
    /// Apparent Poisson ratio at the peak stress.
    PoissonAtPeak,
    /// Largest apparent Poisson ratio after the peak (above 0.5 once the material dilates).
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
    /// Largest secant bulk modulus over the initial one on loading.
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
    /// Uniaxial tensile peak at a rate over the peak at `relative_to`.
    TensionPeakRatio,
    /// Uniaxial compressive peak at a rate (MPa) and its ratio to the peak at `relative_to`.
    CompressionPeakStress,
    /// Uniaxial compressive peak at a rate over the peak at `relative_to`.
    CompressionPeakRatio,
    /// `(max - min) / mean` of the initial slopes (`initial_slope`) over the rates.
    InitialSlopeSpread,
    /// Peak of `sigma_11` in tension under a held lateral stress `sigma_22` (MPa).
    LateralTensionPeak,
    /// That peak over the same point's uniaxial tensile peak (lateral stress 0).
    LateralTensionRatio,
}

impl Quantity {
    /// The quantity's name as a case file writes it (`peak_stress`, ...).
    pub fn name(self) -> String {
        serde_json::to_value(self)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default()
    }

    /// The unit the quantity is reported in (`MPa`, `N/mm`, `mm`, `J/m^3`, `-`).
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
            | CompressionPeakStress
            | LateralTensionPeak => "MPa",
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
    /// What was measured.
    pub quantity: Quantity,
    /// Which run of the experiment gave it.
    pub at: Selector,
    /// The value, in [`Quantity::unit`].
    pub value: f64,
}
