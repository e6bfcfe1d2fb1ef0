//! The facts both the HTML page and the Markdown summary show: per-case counts, the worst
//! metric, and the run's verdict. Computed once here so that the two outputs cannot disagree.

use crate::results::{CaseResult, MetricResult, RunResults, Status};

/// Statuses in the order the page lists them.
pub const STATUSES: [Status; 5] = [
    Status::Pass,
    Status::Fail,
    Status::Error,
    Status::Skipped,
    Status::Interrupted,
];

/// The lowercase name of a status, as in `results.json`; also the CSS class of its badge.
pub fn status_name(status: Status) -> &'static str {
    match status {
        Status::Pass => "pass",
        Status::Fail => "fail",
        Status::Skipped => "skipped",
        Status::Error => "error",
        Status::Interrupted => "interrupted",
    }
}

/// How far a metric is from failing: error over tolerance, above 1 when it fails (for a floor,
/// `at_least` or `at_least_ratio`, the bound over the value). A NaN error counts as infinitely bad, so that a
/// broken metric is never hidden behind a passing one.
pub fn tolerance_ratio(m: &MetricResult) -> f64 {
    let ratio = if m.tolerance_kind.is_floor() {
        m.tolerance.abs() / m.error.abs()
    } else {
        m.error.abs() / m.tolerance.abs()
    };
    if ratio.is_nan() {
        if m.error == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        ratio
    }
}

/// The metric with the largest error/tolerance ratio: the one to look at first.
pub fn worst_metric(metrics: &[MetricResult]) -> Option<&MetricResult> {
    metrics
        .iter()
        .max_by(|a, b| tolerance_ratio(a).total_cmp(&tolerance_ratio(b)))
}

/// The worst metric as one line of plain text, e.g. `peak_force: 3.2× tolerance`.
pub fn worst_text(m: &MetricResult) -> String {
    format!("{}: {:.2}× tolerance", m.name, tolerance_ratio(m))
}

/// The acceptance band of a metric around its reference, where the tolerance kind says how
/// wide it is in the metric's own units (not for `relative_to_scale`, whose scale is unknown).
/// The acceptance band `[low, high]` of a metric in its own units, where its tolerance kind
/// defines one.
pub fn acceptance_band(m: &MetricResult) -> Option<[f64; 2]> {
    m.tolerance_kind.band(m.reference, m.tolerance)
}

/// One row of the summary table.
pub struct CaseSummary<'a> {
    /// The case's result.
    pub case: &'a CaseResult,
    /// Fragment id of the case's section, unique within the page.
    pub anchor: String,
    /// Metrics that passed.
    pub passed: usize,
    /// Metrics of the case.
    pub total: usize,
    /// The metric with the largest error over tolerance, if the case has metrics.
    pub worst: Option<&'a MetricResult>,
}

impl<'a> CaseSummary<'a> {
    /// The summary of the `index`-th case (the index keeps anchors unique across variants).
    pub fn new(index: usize, case: &'a CaseResult) -> Self {
        CaseSummary {
            case,
            anchor: anchor(index, &case.id, &case.variant),
            passed: case.metrics.iter().filter(|m| m.pass).count(),
            total: case.metrics.len(),
            worst: worst_metric(&case.metrics),
        }
    }
}

/// The summaries of all cases, in run order.
pub fn summaries(results: &RunResults) -> Vec<CaseSummary<'_>> {
    results
        .cases
        .iter()
        .enumerate()
        .map(|(i, c)| CaseSummary::new(i, c))
        .collect()
}

/// A fragment id made of the case id and variant, restricted to characters safe in URLs.
fn anchor(index: usize, id: &str, variant: &str) -> String {
    let slug: String = format!("{id}-{variant}")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    format!("case-{index}-{slug}")
}

/// How many cases ended with `status`.
pub fn count(results: &RunResults, status: Status) -> usize {
    results.cases.iter().filter(|c| c.status == status).count()
}

/// The run's overall verdict: the headline and whether it is good news.
pub struct Verdict {
    /// The headline, e.g. `All 12 cases passed` or `2 failed (1 known), 1 error`.
    pub text: String,
    /// Whether the run is good news: cases ran, none failed or errored, none interrupted.
    pub ok: bool,
}

/// `All N cases passed` when nothing failed or errored, otherwise `N failed, M errors`.
pub fn verdict(results: &RunResults) -> Verdict {
    let (failed, errors) = (count(results, Status::Fail), count(results, Status::Error));
    let skipped = count(results, Status::Skipped);
    let interrupted = count(results, Status::Interrupted);
    if interrupted > 0 {
        let finished = results.cases.len() - interrupted;
        return Verdict {
            text: format!(
                "Interrupted: {finished} of {} {} finished ({} passed)",
                results.cases.len(),
                plural(results.cases.len(), "case", "cases"),
                count(results, Status::Pass)
            ),
            ok: false,
        };
    }
    if results.cases.is_empty() {
        return Verdict {
            text: "No cases were run".to_string(),
            ok: false,
        };
    }
    if failed + errors == 0 {
        let passed = count(results, Status::Pass);
        let mut text = format!("All {passed} {} passed", plural(passed, "case", "cases"));
        if skipped > 0 {
            text.push_str(&format!(" ({skipped} skipped)"));
        }
        return Verdict { text, ok: true };
    }
    let known = results
        .cases
        .iter()
        .filter(|c| c.status == Status::Fail && c.known_failure.is_some())
        .count();
    let mut parts = Vec::new();
    if failed > 0 && known > 0 {
        parts.push(format!("{failed} failed ({known} known)"));
    } else if failed > 0 {
        parts.push(format!("{failed} failed"));
    }
    if errors > 0 {
        parts.push(format!("{errors} {}", plural(errors, "error", "errors")));
    }
    Verdict {
        text: parts.join(", "),
        // The page agrees with the exit status: known failures alone do not fail the run.
        ok: results.exit_code() == 0,
    }
}

/// `one` when `n` is 1, else `many`.
pub fn plural<'s>(n: usize, one: &'s str, many: &'s str) -> &'s str {
    if n == 1 {
        one
    } else {
        many
    }
}
