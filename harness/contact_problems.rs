//! Catalogue cases that run no scene but a contact-solver comparison on stored problems
//! (`contact_problems:` instead of `scene:`), judged with `contact_problem_error` metrics.
//!
//! The problems live in the repository (`references/contact-problems/`), so a missing problem
//! folder is a broken checkout or a typo in the case file: the case is an error naming both.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::case_kind::{
    parse_measures, refuse_parts, unfinished_result, Block, CaseKind, KindParseError, LoadedCase,
    RunOptions,
};
use crate::catalogue::{CaseSpec, Variant};
use crate::contact_compare::output::write_outputs;
use crate::contact_compare::{
    collect_problem_files, compare, load_problems, same_tolerance, solver_entries, CompareSettings,
    Comparison, ContactProblemsSpec,
};
use crate::judge::judge_metrics;
use crate::results::{case_dir, CaseResult};

/// Why a `contact_problems` case is refused or a metric of it has no value; each message names
/// the key or metric and what to change.
#[derive(Debug, thiserror::Error)]
pub enum ContactProblemsError {
    /// The kind's block is missing.
    #[error("a contact_problems case needs its `contact_problems` block")]
    NoBlock,
    /// Tolerances empty or not positive.
    #[error("contact_problems: tolerances must be positive and at least one, got {tolerances:?}")]
    Tolerances {
        /// The tolerances given.
        tolerances: Vec<f64>,
    },
    /// A time limit that is not positive and finite.
    #[error("contact_problems: time_limit_s must be positive and finite, got {limit}")]
    TimeLimit {
        /// The limit given (s).
        limit: f64,
    },
    /// A solver list the registry refuses.
    #[error("contact_problems: {0}")]
    Solvers(crate::contact_compare::error::CompareError),
    /// A metric's solver that the comparison does not run.
    #[error(
        "metric `{metric}` names solver `{solver}`, which the comparison does not run ({solvers})"
    )]
    MetricSolver {
        /// The metric.
        metric: String,
        /// The solver it names.
        solver: String,
        /// The solvers run, comma separated.
        solvers: String,
    },
    /// A metric's tolerance that the comparison does not run.
    #[error(
        "metric `{metric}` asks for tolerance {tolerance:e}, which the comparison does not run \
         (tolerances {tolerances:?}): add it to `contact_problems.tolerances`"
    )]
    MetricTolerance {
        /// The metric.
        metric: String,
        /// The tolerance it asks for.
        tolerance: f64,
        /// The tolerances run.
        tolerances: Vec<f64>,
    },
    /// A problem the comparison did not read.
    #[error("problem `{problem}` is not among the problems read ({read})")]
    UnknownProblem {
        /// The problem named.
        problem: String,
        /// The problems read, comma separated.
        read: String,
    },
    /// A solver that did not run on a problem at a tolerance.
    #[error("solver `{solver}` did not run on `{problem}` at {tolerance:e}")]
    NotRun {
        /// The solver.
        solver: String,
        /// The problem.
        problem: String,
        /// The tolerance.
        tolerance: f64,
    },
}

/// What a `contact_problems` case measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ComparisonMeasure {
    /// The natural-map error (Acary, Bremond & Huber 2018, `||F(r)|| / ||q||`, computed by the
    /// harness) that contact solver `solver` reached at `tolerance` on the named problems (all
    /// of them when `problems` is empty), reduced by `statistic`. A failed solve counts as an
    /// infinite error.
    ContactProblemError {
        /// The solver's name (`contact::registry` spelling).
        solver: String,
        /// Names of the problems to solve; all of the case's problems when empty.
        #[serde(default)]
        problems: Vec<String>,
        /// The tolerance the solver is given (what its stopping test bounds).
        tolerance: f64,
        /// How the errors of the problems reduce to one value (default: the largest).
        #[serde(default)]
        statistic: Statistic,
    },
}

/// How several values reduce to one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Statistic {
    /// The largest (the worst error).
    #[default]
    Max,
    /// The smallest (the best error).
    Min,
    /// The arithmetic mean.
    Mean,
}

impl Statistic {
    /// The statistic of `values`; NaN when there are none, and NaN (or infinity) propagates.
    pub fn of(self, values: &[f64]) -> f64 {
        if values.is_empty() {
            return f64::NAN;
        }
        if values.iter().any(|v| v.is_nan()) {
            return f64::NAN;
        }
        match self {
            Statistic::Max => values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Statistic::Min => values.iter().copied().fold(f64::INFINITY, f64::min),
            Statistic::Mean => values.iter().sum::<f64>() / values.len() as f64,
        }
    }
}

/// A case that compares the contact solvers on stored problems.
#[derive(Debug)]
pub struct ContactProblemsCase {
    spec: ContactProblemsSpec,
    measures: Vec<ComparisonMeasure>,
}

/// Reads a `contact_problems` case: its block, no scene, sweep, variants or plots, and metrics
/// that measure what the comparison runs. The message says what to change.
pub fn parse(
    block: Option<&Block>,
    case: &CaseSpec,
    base: &Path,
) -> Result<Arc<dyn CaseKind>, KindParseError> {
    let mut comparison: ContactProblemsSpec =
        block.ok_or(ContactProblemsError::NoBlock)?.parse()?;
    if comparison.folder.is_relative() {
        comparison.folder = base.join(&comparison.folder);
    }
    refuse_parts(
        case,
        &["scene", "sweep", "variants", "plots"],
        "a `contact_problems` case runs no scene",
    )?;
    if comparison.tolerances.is_empty() || comparison.tolerances.iter().any(|t| !(*t > 0.0)) {
        return Err(ContactProblemsError::Tolerances {
            tolerances: comparison.tolerances.clone(),
        }
        .into());
    }
    if !(comparison.time_limit_s > 0.0 && comparison.time_limit_s.is_finite()) {
        return Err(ContactProblemsError::TimeLimit {
            limit: comparison.time_limit_s,
        }
        .into());
    }
    let solvers: Vec<String> = solver_entries(&comparison.solvers)
        .map_err(ContactProblemsError::Solvers)?
        .into_iter()
        .map(|s| s.name)
        .collect();
    let measures: Vec<ComparisonMeasure> = parse_measures(case, "contact_problems")?;
    for (m, measure) in case.metrics.iter().zip(&measures) {
        let ComparisonMeasure::ContactProblemError {
            solver, tolerance, ..
        } = measure;
        if !solvers.contains(solver) {
            return Err(ContactProblemsError::MetricSolver {
                metric: m.name.clone(),
                solver: solver.clone(),
                solvers: solvers.join(", "),
            }
            .into());
        }
        if !comparison
            .tolerances
            .iter()
            .any(|t| same_tolerance(*t, *tolerance))
        {
            return Err(ContactProblemsError::MetricTolerance {
                metric: m.name.clone(),
                tolerance: *tolerance,
                tolerances: comparison.tolerances.clone(),
            }
            .into());
        }
    }
    Ok(Arc::new(ContactProblemsCase {
        spec: comparison,
        measures,
    }))
}

impl CaseKind for ContactProblemsCase {
    fn name(&self) -> &'static str {
        "contact_problems"
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn run(&self, case: &LoadedCase, _: Option<&Variant>, options: &RunOptions) -> CaseResult {
        run_case(self, case, options)
    }
}

/// The value of a comparison measure: the error `solver` reached at `tolerance` on each named
/// problem (infinite for a solve that returned nothing), reduced by the statistic. A problem the
/// comparison lacks is an error naming it.
pub fn measure_value(
    measure: &ComparisonMeasure,
    c: &Comparison,
) -> Result<f64, ContactProblemsError> {
    let ComparisonMeasure::ContactProblemError {
        solver,
        problems,
        tolerance,
        statistic,
    } = measure;
    let names: Vec<String> = if problems.is_empty() {
        c.problem_names()
    } else {
        problems.clone()
    };
    let errors = names
        .iter()
        .map(|p| {
            if !c.problems.iter().any(|d| &d.name == p) {
                return Err(ContactProblemsError::UnknownProblem {
                    problem: p.clone(),
                    read: c.problem_names().join(", "),
                });
            }
            c.row(p, solver, *tolerance)
                .map(|r| {
                    if r.error.is_nan() {
                        f64::INFINITY
                    } else {
                        r.error
                    }
                })
                .ok_or_else(|| ContactProblemsError::NotRun {
                    solver: solver.clone(),
                    problem: p.clone(),
                    tolerance: *tolerance,
                })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    Ok(statistic.of(&errors))
}

/// Runs a `contact_problems` case: the comparison, its files under
/// `<output>/cases/<id>/contact-compare/`, and its metrics.
fn run_case(kind: &ContactProblemsCase, case: &LoadedCase, options: &RunOptions) -> CaseResult {
    let spec = &case.spec;
    let started = Instant::now();
    let mut result = unfinished_result(spec, "default");
    let cp = &kind.spec;
    if !cp.folder.is_dir() {
        // `unfinished_result` is already an error: say which folder and which file names it.
        result.message = Some(format!(
            "{}: contact_problems.folder `{}` is not a folder (the problems are committed under \
             `references/contact-problems/`: restore the checkout or correct the path, which is \
             relative to the case file)",
            case.path.display(),
            cp.folder.display()
        ));
        return result;
    }
    let prepared = collect_problem_files(std::slice::from_ref(&cp.folder))
        .and_then(|files| Ok((files, solver_entries(&cp.solvers)?)));
    let (files, solvers) = match prepared {
        Ok(p) => p,
        Err(e) => {
            result.message = Some(e.to_string());
            return result;
        }
    };
    let (problems, unreadable) = load_problems(&files);
    let settings = CompareSettings {
        tolerances: cp.tolerances.clone(),
        time_limit_s: cp.time_limit_s,
        ..CompareSettings::default()
    };
    let comparison = compare(&problems, unreadable, &solvers, &settings, &mut |_| {});
    let unreadable: Vec<String> = comparison
        .unreadable
        .iter()
        .map(|u| u.message.clone())
        .collect();
    let mut notes = vec![format!(
        "{} solver(s) on {} problem(s) at tolerances {:?}, {} s per solve",
        comparison.solvers.len(),
        comparison.problems.len(),
        comparison.tolerances,
        comparison.time_limit_s
    )];
    if let Some(dir) = &options.output_dir {
        let dir = case_dir(dir, &spec.id).join("contact-compare");
        match write_outputs(&dir, &comparison) {
            Ok(_) => notes.push(format!("tables and plots in {}", dir.display())),
            Err(e) => notes.push(format!("could not write {}: {e}", dir.display())),
        }
    }
    let mut judgement = judge_metrics(
        &spec.metrics,
        None,
        &mut |i, _, _| measure_value(&kind.measures[i], &comparison),
        &|_| None,
    );
    judgement.failures.splice(0..0, unreadable);
    let (status, message) = judgement.verdict(&notes);
    result.status = status;
    result.message = Some(message);
    result.metrics = judgement.metrics;
    result.set_record(Comparison::KEY, &comparison);
    result.wall_s = started.elapsed().as_secs_f64();
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(problem: &str, solver: &str, error: f64) -> crate::contact_compare::ComparisonRow {
        crate::contact_compare::ComparisonRow {
            problem: problem.into(),
            solver: solver.into(),
            tolerance: 1e-8,
            error,
            absolute_error: error,
            iterations: 1,
            outer_iterations: 1,
            seconds: 0.1,
            repeats: 1,
            status: "converged".into(),
            solved: error <= 1e-8,
            notes: vec![],
        }
    }

    #[test]
    fn the_measure_reduces_the_named_problems_and_names_a_missing_one() {
        let p = crate::contact_compare::test_problem(&[(0, 0, 1.0)], &[-1.0, 0.0, 0.0], &[0.1]);
        let c = Comparison {
            normalisation: String::new(),
            tolerances: vec![1e-8],
            time_limit_s: 1.0,
            solvers: vec!["gs".into()],
            problems: ["a", "b", "c"]
                .iter()
                .map(|n| crate::contact_compare::describe(&p, n, n))
                .collect(),
            unreadable: vec![],
            rows: vec![
                row("a", "gs", 1e-9),
                row("b", "gs", 4e-9),
                row("c", "gs", f64::NAN),
            ],
        };
        let measure = |problems: &[&str], statistic| ComparisonMeasure::ContactProblemError {
            solver: "gs".into(),
            problems: problems.iter().map(|s| s.to_string()).collect(),
            tolerance: 1e-8,
            statistic,
        };
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Max), &c).ok(),
            Some(4e-9)
        );
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Min), &c).ok(),
            Some(1e-9)
        );
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Mean), &c).ok(),
            Some(2.5e-9)
        );
        // A solve that returned nothing counts as an infinite error; empty means all problems.
        assert_eq!(
            measure_value(&measure(&[], Statistic::Max), &c).ok(),
            Some(f64::INFINITY)
        );
        let e = measure_value(&measure(&["a", "zz"], Statistic::Max), &c)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`zz`") && e.contains("a, b, c"), "{e}");
        let mut other = measure(&["a"], Statistic::Max);
        let ComparisonMeasure::ContactProblemError { solver, .. } = &mut other;
        *solver = "conic".into();
        assert!(measure_value(&other, &c)
            .unwrap_err()
            .to_string()
            .contains("conic"));
    }
}
