//! Measurements: numbers taken from a run's histories and final fields.

mod columns;
mod energy;
mod error;
mod evaluate;
mod field;
mod motion;
mod signal;
mod stress;
mod structure;
#[cfg(test)]
mod synthetic;

use serde::{Deserialize, Serialize};

pub use error::MeasureError;

/// Nodes a field measure looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NodeScope {
    /// Nodes not on the boundary of the body.
    #[default]
    Interior,
    /// Every node of the body.
    All,
}

/// Field measured against an affine exact field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldQuantity {
    /// Nodal displacement (m).
    Displacement,
    /// Nodal velocity (m/s).
    Velocity,
}

/// A tensor component in Voigt order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TensorComponent {
    /// `xx`, index 0.
    Xx,
    /// `yy`, index 1.
    Yy,
    /// `zz`, index 2.
    Zz,
    /// `xy`, index 3 (tensor shear).
    Xy,
    /// `yz`, index 4 (tensor shear).
    Yz,
    /// `xz`, index 5 (tensor shear).
    Xz,
}

/// What to measure. Sweep measures (`observed_order`, stability) need a sweep in the case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Measure {
    /// Largest value of a history column.
    HistoryMax {
        /// Name of the history column.
        column: String,
    },
    /// Smallest value of a history column.
    HistoryMin {
        /// Name of the history column.
        column: String,
    },
    /// Largest |value| of a history column (a peak load whose sign is a convention).
    HistoryPeakMagnitude {
        /// Name of the history column.
        column: String,
    },
    /// Last recorded value of a history column, times `scale` (for example `-1 / area` to turn
    /// a contact force into a compressive stress).
    HistoryFinal {
        /// Name of the history column.
        column: String,
        /// Factor on the value (default 1).
        #[serde(default = "one")]
        scale: f64,
    },
    /// Time of the largest absolute value of a column.
    PeakTime {
        /// Name of the history column.
        column: String,
    },
    /// `scale` times the value of `column` in the row where `of` has its largest |value|: the
    /// crack mouth opening at the peak load, say.
    ValueAtPeak {
        /// Name of the history column read.
        column: String,
        /// Name of the history column whose peak picks the row.
        of: String,
        /// Factor on the value (default 1).
        #[serde(default = "one")]
        scale: f64,
    },
    /// The largest |value| of a column over the mean |value| of the five rows centred on it (the
    /// peak's row and two on each side, fewer at an end of the history): 1 for a peak that the
    /// records resolve, up to 5 for a spike of one row. A peak force that is a single-step spike
    /// is a numerical event, not a measurement.
    PeakOverNeighbours {
        /// Name of the history column.
        column: String,
    },
    /// Total time during which the column exceeds `threshold`.
    DurationAbove {
        /// Name of the history column.
        column: String,
        /// The level, in the column's unit.
        threshold: f64,
    },
    /// Mean of a column over the time window `[from, to]`.
    PlateauMean {
        /// Name of the history column.
        column: String,
        /// Start of the window (s).
        from: f64,
        /// End of the window (s).
        to: f64,
    },
    /// First time the column reaches `level` (linear interpolation between records).
    ArrivalTime {
        /// Name of the history column.
        column: String,
        /// The level, in the column's unit.
        level: f64,
    },
    /// `distance / (t_to - t_from)` from the arrival of `level` at two probes: the front speed.
    FrontSpeed {
        /// History column of the first probe.
        from: String,
        /// History column of the second probe.
        to: String,
        /// Distance between the probes (m).
        distance: f64,
        /// The level whose arrival is timed, in the columns' unit.
        level: f64,
    },
    /// Largest |energy balance error| over the run, over the largest energy scale.
    EnergyBalanceError,
    /// Largest |K - K_0| / K_0 over the history: the drift of the kinetic energy.
    KineticEnergyDrift,
    /// Largest |column(t) - column(0)| over the history, divided by `scale` (for example the
    /// drift of the total momentum over one body's initial momentum).
    MaxChange {
        /// Name of the history column.
        column: String,
        /// The divisor, in the column's unit.
        scale: f64,
    },
    /// Largest |v(t) - v(0)| / |v(0)| of the vector whose components are `columns` (for
    /// example the total angular momentum).
    RelativeDrift {
        /// The history columns of the `x`, `y`, `z` components.
        columns: [String; 3],
    },
    /// (kinetic + stored energy) at the end over the initial kinetic energy: the energy left in
    /// the bodies after an impact, elastic vibration included.
    FinalEnergyRatio,
    /// |omega| of a body at the end, from its angular momentum about its centre of mass and its
    /// inertia tensor in the current configuration (`omega = I^-1 L`), times `scale` (for
    /// example `R / v` to make it dimensionless).
    BodySpin {
        /// Name of the body.
        body: String,
        /// Factor on `|omega|` (s, default 1).
        #[serde(default = "one")]
        scale: f64,
    },
    /// Largest |field - exact| over the nodes, over the largest |exact|, for the exact field
    /// `scale (translation + gradient (X - center))`, where `scale` is the final time for an
    /// explicit displacement (constant velocity field) and 1 otherwise.
    AffineFieldError {
        /// The field compared: displacement or velocity.
        quantity: FieldQuantity,
        /// Uniform part of the exact field (m or m/s, per unit `scale`).
        #[serde(default)]
        translation: [f64; 3],
        /// Gradient of the exact field, row `i` for component `i`.
        gradient: [[f64; 3]; 3],
        /// Reference point `X` of the gradient (m).
        #[serde(default)]
        center: [f64; 3],
        /// Which nodes are compared (default the interior ones).
        #[serde(default)]
        nodes: NodeScope,
    },
    /// Largest relative deviation of any element's Cauchy stress from the exact stress of the
    /// homogeneous deformation `F = I + scale gradient` (scale as in `affine_field_error`).
    UniformStressError {
        /// Displacement gradient of the deformation per unit `scale`, row `i` for component `i`.
        gradient: [[f64; 3]; 3],
    },
    /// Largest |sigma_ij| over all elements, divided by Young's modulus of its body.
    MaxStressOverModulus,
    /// Mean Cauchy stress component over the elements whose centroid lies in `[min, max]`.
    ElementStressMean {
        /// The stress component.
        component: TensorComponent,
        /// Lower corner of the box (m).
        min: [f64; 3],
        /// Upper corner of the box (m).
        max: [f64; 3],
    },
    /// `(max - min) / |mean|` of a Cauchy stress component over the elements whose centroid
    /// lies in `[min, max]`: the scatter of a stress that should be uniform.
    ElementStressScatter {
        /// The stress component.
        component: TensorComponent,
        /// Lower corner of the box (m).
        min: [f64; 3],
        /// Upper corner of the box (m).
        max: [f64; 3],
    },
    /// Mean Green-Lagrange strain component over all elements.
    ElementStrainMean {
        /// The strain component.
        component: TensorComponent,
    },
    /// Reaction of a constraint (static: at equilibrium; explicit: the last record), divided by
    /// `divide_by` (for example an area, giving a nominal stress).
    Reaction {
        /// Name of the boundary condition.
        constraint: String,
        /// The reaction's component.
        component: TensorAxis,
        /// The divisor (default 1), e.g. an area (m^2).
        #[serde(default = "one")]
        divide_by: f64,
    },
    /// Frequency from the mean spacing of upward zero crossings of a column (Hz).
    ZeroCrossingFrequency {
        /// Name of the history column.
        column: String,
    },
    /// Observed convergence order of another metric's error over the sweep.
    ObservedOrder {
        /// Name of the other metric of the case.
        metric: String,
    },
    /// 1 if every sweep level with time-step factor up to 1 ran stably, else 0.
    StableUpToEstimate,
    /// Smallest time-step factor of the sweep whose run went unstable: the measured stability
    /// limit over the estimate (the largest factor plus one step if none did).
    MeasuredStabilityLimit,
    /// 1 if every unstable level stopped with an instability report (no NaN, no other error).
    UnstableRunsReported,
    /// The contact problems the run recorded, replayed through `solver` at `tolerance` (or
    /// `recorded`: the run's own multipliers); `quantity` is the worst over the problems (see
    /// `crate::replay`).
    ContactReplay {
        /// The solver's name (`contact::registry` spelling), or `recorded`.
        solver: String,
        /// What is measured on each replayed problem.
        quantity: crate::replay::ReplayQuantity,
        /// The tolerance the solver is given (default 1e-10).
        #[serde(default = "replay_tolerance")]
        tolerance: f64,
        /// Only the problems the run's solver converged on.
        #[serde(default)]
        only_converged: bool,
    },
    /// Failure mode of a beam (FORMULATION 5, thesis 10.3.2) in the final state or at the end
    /// of the contact (`at`), as its code: 0 none, 1 bending, 2 mixed, 3 shear, 4 bending with
    /// inclined damage zones (`crate::beam::classify`). Judged against
    /// `{ failure_mode: <mode> }` with `absolute: 0`.
    FailureMode(#[serde(default)] crate::beam::BeamSpec),
    /// A quantity of the bending-crack tips over every snapshot
    /// (`crate::beam::cracks::crack_tip_report`): the cohesive (`w >= w_p`, `sigma(w_p) = 0.9
    /// f_t`) and traction-free (`w >= w_cr / 2`) tips of the face-connected crack grown from
    /// mid-span's bottom, their largest windowed speed over the Rayleigh speed `c_R` judged with
    /// its resolution (a mode-I tip cannot outrun `c_R`, Freund 1990; the thesis finds about
    /// 0.55 `c_R`), the initiation length and the coalescence length.
    CrackTip(crate::beam::CrackTipMeasure),
    /// `max |left - right| / max(|left|, |right|)` over the history records up to the first
    /// snapshot in which an element of the beam outside the crushing under the impactor is
    /// cracked (`eps_1 / eps_r >= 1`, `crate::beam::cracks::first_crack_time`): the two
    /// reactions of a mirror-symmetric beam, load and mesh agree, and 0 is exact (issue 17).
    ReactionAsymmetry {
        /// History column of the left reaction.
        left: String,
        /// History column of the right reaction.
        right: String,
        /// The beam body (default `beam`).
        #[serde(default = "beam_body")]
        body: String,
    },
    /// `max K / W_int` over the records where `W_int` exceeds `above_fraction` (default 5 %)
    /// of its largest value (`crate::beam::history::kinetic_over_internal_work`).
    KineticOverInternalWork {
        /// History column of the kinetic energy `K` (default `kinetic`).
        #[serde(default = "kinetic_column")]
        kinetic: String,
        /// History column of the internal work `W_int` (default `internal_work`).
        #[serde(default = "internal_work_column")]
        internal_work: String,
        /// Fraction of the largest `W_int` above which records count (default 0.05).
        #[serde(default = "five_percent")]
        above_fraction: f64,
        /// Only the records up to the largest |value| of this column (the peak load): past the
        /// peak of a brittle beam the crack releases stored energy as motion whatever the
        /// loading rate, so the quasi-static check belongs to the loading branch.
        #[serde(default)]
        until_peak_of: Option<String>,
        /// With `until_peak_of`: go on past the peak to the first record where that column's
        /// |value| falls below this fraction of its peak (issue 16: quasi-static through the
        /// peak and down to 80 % of it).
        #[serde(default)]
        after_peak_down_to: Option<f64>,
    },
    /// Least-squares slope of `force` against `displacement` up to the first record where
    /// |force| reaches `up_to_fraction` of its peak (`crate::beam::history::secant_stiffness`).
    SecantStiffness {
        /// History column of the force (N).
        force: String,
        /// History column of the displacement (m).
        displacement: String,
        /// Fraction of the peak |force| up to which records are fitted.
        up_to_fraction: f64,
    },
    /// Initial stiffness of a load-opening curve (`crate::curve::rising_branch_slope`): the
    /// least-squares slope of `F = load_scale * load` against `w = opening_scale * (opening -
    /// opening_minus)` over the records up to the peak of `F` with `F` in `[from, to]` (in the
    /// scaled unit), the same rule as the `curve_slope` reference applies to a measured curve.
    RisingBranchSlope {
        /// History column of the load.
        load: String,
        /// Factor on the load (default 1; -1 for a downward reaction).
        #[serde(default = "one")]
        load_scale: f64,
        /// History column of the opening (for a CMOD, the right mouth probe's x).
        opening: String,
        /// History column subtracted from `opening` (the left mouth probe's x).
        #[serde(default)]
        opening_minus: Option<String>,
        /// Factor on the opening (default 1; 1e6 for um from m).
        #[serde(default = "one")]
        opening_scale: f64,
        /// Lower end of the load window, in the scaled unit.
        from: f64,
        /// Upper end of the load window, in the scaled unit.
        to: f64,
    },
    /// Largest |bending moment| about the z axis at the section `x = section_x` over the run,
    /// from the y reactions of `conditions`, all on one side of the section: `M = sum_c
    /// R_c (section_x - x_c)`, each named boundary condition or `quantity: reaction` probe on one
    /// line of nodes `x = x_c` (probe a strip or a plate line by line;
    /// `crate::beam::history::peak_bending_moment`). Unlike a load,
    /// it does not depend on where a rigid plate or support strip carries its force, so it
    /// compares with a sectional (hinge) model of the beam.
    PeakBendingMoment {
        /// `x` of the section (m).
        section_x: f64,
        /// Boundary conditions or reaction probes on one side of the section.
        conditions: Vec<String>,
        /// Only the records up to the largest |value| of this column (the peak load): after a
        /// brittle beam snaps, inertia forces make the reactions' moment differ from the
        /// section's, so the quasi-static branch alone gives a sectional moment.
        #[serde(default)]
        until_peak_of: Option<String>,
    },
    /// `max |numerator| / max |denominator|` over the history.
    PeakRatio {
        /// History column of the numerator.
        numerator: String,
        /// History column of the denominator.
        denominator: String,
    },
    /// Time of the largest |column| minus that of the largest |after| (s).
    PeakTimeLag {
        /// Name of the history column.
        column: String,
        /// History column whose peak time is subtracted.
        after: String,
    },
    /// The force balance (6.48) of `body` along y summed over its nodes: `max |-contact -
    /// sum other_contacts + m g_y + sum reactions - dp/dt| / max |contact|`, with `contact` the
    /// force the body exerts on the other body of the pair, `dp/dt` by central differences of
    /// `momentum`, `m` the body's mass (`crate::beam::history::force_equilibrium_error`).
    ForceEquilibriumError {
        /// Name of the body.
        body: String,
        /// History column of the contact force the body exerts on the other body (N); its
        /// largest magnitude is the scale of the error.
        contact: String,
        /// History columns of the reactions on the body (N).
        reactions: Vec<String>,
        /// History columns of the forces the body exerts through further contact pairs that
        /// list it first (a beam resting on support plates), in the sign of `contact` (N).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        other_contacts: Vec<String>,
        /// History column of the body's momentum along y (kg m/s).
        momentum: String,
    },
    /// The crack band of a prism run against the material point of its size (`crate::band`):
    /// dissipated energy per crack area, traction-opening deviation.
    CrackBand(crate::band::BandMeasure),
    /// A material-point diagnostic of the band's concrete at its size, no run needed
    /// (`crate::band::PointMeasure`): uniaxial strain, tension with shear (stress locking).
    CrackBandPoint(crate::band::PointMeasure),
}

fn kinetic_column() -> String {
    "kinetic".into()
}

fn internal_work_column() -> String {
    "internal_work".into()
}

fn five_percent() -> f64 {
    0.05
}

fn replay_tolerance() -> f64 {
    1e-10
}

/// A displacement axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TensorAxis {
    /// The `x` axis.
    X,
    /// The `y` axis.
    Y,
    /// The `z` axis.
    Z,
}

fn one() -> f64 {
    1.0
}

impl Measure {
    /// Whether the measure is computed over the levels of a sweep rather than from one run.
    pub fn is_sweep_measure(&self) -> bool {
        matches!(
            self,
            Measure::ObservedOrder { .. }
                | Measure::StableUpToEstimate
                | Measure::MeasuredStabilityLimit
                | Measure::UnstableRunsReported
        )
    }
}

fn beam_body() -> String {
    "beam".into()
}
