//! The facts both the HTML page and the Markdown summary show: per-case counts, the worst
//! metric, and the run's verdict. Computed once here so that the two outputs cannot disagree.

use crate::results::{CaseResult, MetricResult, RunResults, Status, ToleranceKind};

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

/// How far a metric is from failing: error over tolerance, above 1 exactly when it fails, so
/// that the worst metric of a failed case is one that failed. Two-sided tolerances compare
/// `|error|` with the tolerance. One-sided bounds are read with their sign: a ceiling
/// (`at_most`) gives `error / tolerance`, 0 at or below zero (the whole admissible side of a zero
/// ceiling, such as a support reaction that may only be negative, is as far from failing as a
/// ceiling allows); a floor (`at_least`, `at_least_ratio`) gives `tolerance / error`, 0 where the
/// bound is not positive and is met. A side that fails with a bound that gives no ratio counts as
/// infinitely bad, and so does a NaN error, so that a broken metric is never hidden behind a
/// passing one.
pub fn tolerance_ratio(m: &MetricResult) -> f64 {
    let (error, tolerance) = (m.error, m.tolerance);
    if error.is_nan() {
        return f64::INFINITY;
    }
    let ratio = match m.tolerance_kind {
        ToleranceKind::AtMost if error <= tolerance => {
            if tolerance > 0.0 {
                (error / tolerance).max(0.0)
            } else {
                0.0
            }
        }
        ToleranceKind::AtMost if tolerance > 0.0 => error / tolerance,
        ToleranceKind::AtMost => f64::INFINITY,
        ToleranceKind::AtLeast | ToleranceKind::AtLeastRatio if error >= tolerance => {
            if tolerance > 0.0 {
                tolerance / error
            } else {
                0.0
            }
        }
        ToleranceKind::AtLeast | ToleranceKind::AtLeastRatio if error > 0.0 => tolerance / error,
        ToleranceKind::AtLeast | ToleranceKind::AtLeastRatio => f64::INFINITY,
        _ => error.abs() / tolerance.abs(),
    };
    if ratio.is_nan() {
        // A two-sided metric's 0 / 0 (exactly on a zero reference with a zero tolerance) meets
        // it; inf / inf does not.
        if error == 0.0 {
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn metric(
        name: &str,
        kind: ToleranceKind,
        error: f64,
        tolerance: f64,
        pass: bool,
    ) -> MetricResult {
        MetricResult {
            name: name.into(),
            value: error,
            reference: 0.0,
            error,
            tolerance,
            unit: String::new(),
            pass,
            tolerance_kind: kind,
            reference_source: String::new(),
        }
    }

    /// The ratio is above 1 exactly where the metric fails, whatever the kind and the sign.
    #[test]
    fn the_ratio_exceeds_one_exactly_where_the_metric_fails() {
        use ToleranceKind::*;
        let cases = [
            // A zero ceiling met far below (an uplift reaction of -160 kN) and broken.
            (AtMost, -1.6e5, 0.0, true),
            (AtMost, 0.0, 0.0, true),
            (AtMost, 3.0, 0.0, false),
            (AtMost, 0.5, 1.0, true),
            (AtMost, -0.5, 1.0, true),
            (AtMost, 1.5, 1.0, false),
            (AtMost, -6.0, -5.0, true),
            (AtMost, -4.0, -5.0, false),
            // Floors: a zero floor broken by a negative value, a ratio floor met and broken.
            (AtLeast, 2.0e-4, 0.0, true),
            (AtLeast, -2.0e-4, 0.0, false),
            (AtLeast, 0.0, 0.0, true),
            (AtLeastRatio, 25.0, 5.0, true),
            (AtLeastRatio, 4.0, 5.0, false),
            (AtLeastRatio, -1.0, 5.0, false),
            (Absolute, -0.2, 0.1, false),
            (Absolute, 0.05, 0.1, true),
            (Relative, 0.0, 0.0, true),
            // An infinite value never passes (`judge`), whatever the tolerance: inf / inf is no
            // 0 / 0.
            (Absolute, f64::INFINITY, f64::INFINITY, false),
        ];
        for (kind, error, tolerance, pass) in cases {
            let r = tolerance_ratio(&metric("m", kind, error, tolerance, pass));
            assert_eq!(
                r > 1.0,
                !pass,
                "{kind:?} error {error} tolerance {tolerance}: ratio {r}"
            );
            assert!(r >= 0.0, "{kind:?} error {error}: ratio {r}");
        }
        let nan = metric("m", AtMost, f64::NAN, 1.0, false);
        assert_eq!(tolerance_ratio(&nan), f64::INFINITY);
    }

    /// A failed case names a failed metric as its worst, not a met zero ceiling.
    #[test]
    fn the_worst_metric_of_a_failed_case_is_one_that_failed() {
        let metrics = [
            metric("failure_mode", ToleranceKind::Absolute, 1.0, 0.0, false),
            metric("uplift_right", ToleranceKind::AtMost, -1.6e5, 0.0, true),
            metric(
                "energy_balance_error",
                ToleranceKind::AtMost,
                1.2e-3,
                0.01,
                true,
            ),
        ];
        assert_eq!(worst_metric(&metrics).unwrap().name, "failure_mode");
    }
}
