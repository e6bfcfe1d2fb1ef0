//! Why a material-point case is refused, cannot run, or a metric of it has no value.

use impact_solver::material::microplane::driver::DriverError;
use impact_solver::material::microplane::ParameterError;

/// Why a `material_point` case is refused (each message names the key or metric and what to
/// change), why its experiment cannot run, or why a metric selects no single value.
#[derive(Debug, thiserror::Error)]
pub enum MaterialPointError {
    /// The kind's block is missing.
    #[error("a material_point case needs its `material_point` block")]
    NoBlock,
    /// The parameter file cannot be read or checked.
    #[error(transparent)]
    ParameterFile(#[from] impact_solver::SolverError),
    /// The parameters are refused by the model.
    #[error(transparent)]
    Parameters(#[from] ParameterError),
    /// The material point cannot be driven along the experiment's path.
    #[error(transparent)]
    Driver(#[from] DriverError),
    /// An element size the crack band refuses.
    #[error(transparent)]
    CrackBand(#[from] impact_solver::material::microplane::CrackBandError),
    /// A number that must be positive and finite.
    #[error("material_point: {name} must be positive, got {value}")]
    NotPositive {
        /// The key.
        name: String,
        /// The value given.
        value: f64,
    },
    /// An option the experiment does not read.
    #[error(
        "material_point: experiment `{experiment}` does not read `{option}`; it reads {accepted}"
    )]
    UnreadOption {
        /// The experiment.
        experiment: String,
        /// The option given.
        option: String,
        /// The options it reads, comma separated.
        accepted: String,
    },
    /// Zero steps or samples.
    #[error("material_point: steps and samples must be at least 1")]
    ZeroSteps,
    /// An option the experiment needs.
    #[error("material_point: {experiment} needs `{option}`")]
    Needs {
        /// The experiment.
        experiment: String,
        /// The option it needs.
        option: String,
    },
    /// Lateral stresses that are not compressions.
    #[error(
        "material_point: lateral_stresses {stresses:?}: give lateral compressions in Pa (0 or \
         negative)"
    )]
    LateralStresses {
        /// The stresses given (Pa).
        stresses: Vec<f64>,
    },
    /// `relative_to` not among the rates.
    #[error("material_point: relative_to = {relative_to:e} must be one of `rates` {rates:?}")]
    RelativeTo {
        /// The rate given (1/s).
        relative_to: f64,
        /// The rates (1/s).
        rates: Vec<f64>,
    },
    /// A cycle too short.
    #[error(
        "material_point: cycle `{cycle}` needs two corners or more, repeat >= 1 and steps >= 1"
    )]
    ShortCycle {
        /// The cycle.
        cycle: String,
    },
    /// A cycle named twice.
    #[error("material_point: cycle `{cycle}` appears twice")]
    CycleTwice {
        /// The cycle.
        cycle: String,
    },
    /// A metric whose quantity the experiment does not measure.
    #[error(
        "metric `{metric}`: experiment `{experiment}` does not measure `{quantity}`; it measures \
         {measured}"
    )]
    NotMeasured {
        /// The metric.
        metric: String,
        /// The experiment.
        experiment: String,
        /// The quantity asked for.
        quantity: String,
        /// The quantities it measures, comma separated.
        measured: String,
    },
    /// The experiment measured none of the quantity.
    #[error("the experiment measured no `{quantity}` (its path may have stopped early)")]
    NothingMeasured {
        /// The quantity.
        quantity: String,
    },
    /// The quantity was not measured where the metric asks.
    #[error("no `{quantity}` at {at}; measured at {available}")]
    NotAt {
        /// The quantity.
        quantity: String,
        /// Where the metric asks.
        at: String,
        /// Where it was measured.
        available: String,
    },
    /// The quantity was measured at several places and the metric does not say which.
    #[error(
        "`{quantity}` was measured at {available}: say which (element_size, rate, rule, cycle, \
         deviatoric_trace_term or lateral_stress)"
    )]
    Ambiguous {
        /// The quantity.
        quantity: String,
        /// Where it was measured.
        available: String,
    },
}
