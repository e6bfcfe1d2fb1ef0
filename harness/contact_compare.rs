//! Comparison of contact solvers on stored contact problems FC(W, q, mu) (issue 5), after the
//! protocol of Acary, Bremond & Huber (2018), "On solving contact problems with Coulomb
//! friction: formulations and numerical comparisons" (ABH below):
//!
//! - every problem gets its descriptors ([`descriptors`]): contacts, `mu`, asymmetry, rank and
//!   condition number of the symmetric part of `W`;
//! - every solver runs on every problem at every tolerance from zero multipliers, under a time
//!   limit ([`run`]); the harness, never the solver, measures the error of the returned `r`
//!   with the natural map of ABH eq. (error-1),
//!   `error = ||r - P_K(r - (u + g(u)))||_2 / ||q||_2`, `u = W r + q`
//!   (`impact_solver::contact::problem::natural_map_error`, normalised by `||q||_2` as in the
//!   paper and Siconos 2016-2020);
//! - the wall time of a solve is the median over a few repeats (machines are noisy);
//! - [`profile`] turns the rows into Dolan & More (2002) performance profiles and a
//!   work-precision diagram, and [`tables`] into the tables of the outputs;
//! - [`output`] writes `results.json`, `results.csv`, `README.md` and SVG plots, [`command`]
//!   is the `impact-vv contact-compare` command, and [`crate::contact_problems`] runs a catalogue case of this kind.
//!
//! On a frictionless problem (every `mu = 0`) `conic/relaxed` and `conic/coulomb` solve the same
//! QP; both still run, and their rows say so in a note. Timings are wall times on whatever else
//! the machine runs: inside `impact-vv run` other cases may run beside the comparison.

pub mod command;
pub mod descriptors;
pub mod error;
pub mod output;
pub mod profile;
pub mod report;
pub mod run;
pub mod tables;

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::results::lenient;
pub use descriptors::{describe, ProblemDescriptors};
pub use profile::{performance_profile, work_precision_plot, PerformanceProfile};
pub use run::{
    collect_problem_files, compare, load_problems, solver_entries, CompareSettings, LoadedProblem,
    SolverEntry,
};

/// The normalisation of every error in a comparison, stated with it.
pub const NORMALISATION: &str = "natural map ||r - P_K(r - (u + g(u)))||_2 / ||q||_2 \
                                 (Acary, Bremond & Huber 2018, eq. error-1), computed by the harness";

/// Default tolerances: the two of ABH's campaign and one between.
pub const DEFAULT_TOLERANCES: [f64; 3] = [1e-4, 1e-6, 1e-8];
/// Default time limit of one solve (s); ABH's local-problem set used 10 s.
pub const DEFAULT_TIME_LIMIT_S: f64 = 10.0;

/// The `contact_problems` entry of a catalogue case: compare the contact solvers on the problem
/// files of `folder` instead of running a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactProblemsSpec {
    /// Folder of `contact-problem/1` JSON files, relative to the case file.
    pub folder: PathBuf,
    /// Tolerances each solver is run at (what its stopping test bounds); default
    /// [`DEFAULT_TOLERANCES`].
    #[serde(default = "default_tolerances")]
    pub tolerances: Vec<f64>,
    /// Time limit of one solve (s).
    #[serde(default = "default_time_limit")]
    pub time_limit_s: f64,
    /// Solver names (see `impact_solver::contact::registry`); empty: all.
    #[serde(default)]
    pub solvers: Vec<String>,
}

fn default_tolerances() -> Vec<f64> {
    DEFAULT_TOLERANCES.to_vec()
}

fn default_time_limit() -> f64 {
    DEFAULT_TIME_LIMIT_S
}

/// One solve: a solver on a problem at a tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ComparisonRow {
    /// Name of the problem (its file stem).
    pub problem: String,
    /// The solver's name (`contact::registry` spelling).
    pub solver: String,
    /// The tolerance the solver was given.
    #[serde(deserialize_with = "lenient::f64")]
    pub tolerance: f64,
    /// Natural-map error of the returned multipliers over `||q||_2` ([`NORMALISATION`]); NaN
    /// when the solver returned nothing (setup error, panic).
    #[serde(deserialize_with = "lenient::f64")]
    pub error: f64,
    /// The same error before normalisation.
    #[serde(deserialize_with = "lenient::f64")]
    pub absolute_error: f64,
    /// Sweeps or interior-point iterations, as the solver reports them.
    pub iterations: usize,
    /// Outer fixed-point iterations (`conic/coulomb`); 1 otherwise.
    pub outer_iterations: usize,
    /// Median wall time of the repeats, measured by the harness around `solve` (s).
    #[serde(deserialize_with = "lenient::f64")]
    pub seconds: f64,
    /// How many times the solve was timed.
    pub repeats: usize,
    /// `converged`, `max-iterations`, `time-limit`, `failed` (the solver's), or `error` (the
    /// problem could not be posed) and `panicked` (the harness caught a panic).
    pub status: String,
    /// Whether this counts as solved in the profiles: `error <= tolerance` within the time
    /// limit, whatever the solver's own status says.
    pub solved: bool,
    /// What the solver wanted a reader to know (fallbacks taken, removed asymmetry).
    #[serde(default)]
    pub notes: Vec<String>,
}

impl ComparisonRow {
    /// ABH's criterion: the error reached is at most the tolerance, within the time limit (a
    /// solver's "converged" does not count, and a non-converged status does not exclude).
    pub fn meets(&self, time_limit_s: f64) -> bool {
        self.error <= self.tolerance && self.seconds <= time_limit_s
    }
}

/// A problem file that could not be read, with the reason (naming the file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Unreadable {
    /// The problem file.
    pub file: String,
    /// Why it could not be read or checked.
    pub message: String,
}

/// A whole comparison: settings, problems, and one row per problem x solver x tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// How the error is normalised, in words ([`NORMALISATION`]).
    pub normalisation: String,
    /// The tolerances every solver ran at.
    pub tolerances: Vec<f64>,
    /// Time limit of one solve (s of wall time).
    #[serde(deserialize_with = "lenient::f64")]
    pub time_limit_s: f64,
    /// Solver names in the order they ran.
    pub solvers: Vec<String>,
    /// The problems read, with their size and structure descriptors.
    pub problems: Vec<ProblemDescriptors>,
    /// The problem files that could not be read.
    #[serde(default)]
    pub unreadable: Vec<Unreadable>,
    /// One row per problem, solver and tolerance.
    pub rows: Vec<ComparisonRow>,
}

impl Comparison {
    /// Its key among a case result's records.
    pub const KEY: &'static str = "contact_comparison";

    /// The row of `problem`, `solver` at `tolerance`, if it ran.
    pub fn row(&self, problem: &str, solver: &str, tolerance: f64) -> Option<&ComparisonRow> {
        self.rows.iter().find(|r| {
            r.problem == problem && r.solver == solver && same_tolerance(r.tolerance, tolerance)
        })
    }

    /// Problem names in order.
    pub fn problem_names(&self) -> Vec<String> {
        self.problems.iter().map(|p| p.name.clone()).collect()
    }
}

/// Tolerances are compared with a relative slack so that a value read back from JSON or YAML
/// still finds its rows.
pub fn same_tolerance(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// A problem for unit tests, built through the `contact-problem/1` reader so that tests do not
/// depend on the fields of `ContactProblem`.
#[cfg(test)]
pub(crate) fn test_problem(
    triplets: &[(usize, usize, f64)],
    q: &[f64],
    mu: &[f64],
) -> impact_solver::contact::problem::ContactProblem {
    let json = serde_json::json!({
        "format": "contact-problem/1",
        "dimension": 3,
        "contacts": mu.len(),
        "mu": mu.iter().map(|m| m.is_finite().then_some(*m)).collect::<Vec<_>>(),
        "q": q,
        "W": { "rows": q.len(), "cols": q.len(), "triplets": triplets },
    });
    serde_json::from_value::<impact_solver::contact::problem_file::ProblemFile>(json)
        .expect("a test problem file")
        .to_problem("test")
        .expect("a valid test problem")
}
