//! The facts both the HTML page and the Markdown summary show: per-case counts, the worst
//! metric, and the run's verdict. Computed once here so that the two outputs cannot disagree.

use super::format;
use crate::beam::{FailureMode, FAILURE_MODE_METRIC};
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

/// The error as a multiple of the tolerance, e.g. `3.2×`, where that multiple says something:
/// `None` for a zero tolerance (any miss would be infinitely many tolerances, any hit zero) and
/// for a value that gives no finite ratio (NaN), which read better as the value against its
/// reference ([`against_reference`]).
pub fn ratio_text(m: &MetricResult) -> Option<String> {
    let ratio = tolerance_ratio(m);
    (m.tolerance != 0.0 && ratio.is_finite()).then(|| format!("{}×", format::tick(ratio)))
}

/// The metric's value against what it should be, in words: a class code by its name where the
/// reference source lists the codes or the metric is the beam's `failure_mode`
/// (`shear, expected mixed`), otherwise the numbers with the bound the tolerance kind sets
/// (`3, expected 0`; `0.2 m, expected at most 0`).
pub fn against_reference(m: &MetricResult) -> String {
    let class = |v: f64| class_name(m, v);
    if let (Some(value), Some(reference)) = (class(m.value), class(m.reference)) {
        return format!("{value}, expected {reference}");
    }
    let unit = |v: f64| {
        if m.unit.is_empty() {
            format::num(v)
        } else {
            format!("{} {}", format::num(v), m.unit)
        }
    };
    let expected = match m.tolerance_kind {
        ToleranceKind::AtMost => format!("expected at most {}", unit(m.tolerance)),
        ToleranceKind::AtLeast => format!("expected at least {}", unit(m.tolerance)),
        ToleranceKind::AtLeastRatio => format!(
            "expected at least {}× {}",
            format::num(m.tolerance),
            unit(m.reference)
        ),
        _ => format!("expected {}", unit(m.reference)),
    };
    format!("{}, {expected}", unit(m.value))
}

/// The name of class code `v` of a discrete metric: from the codes its reference source lists
/// (`code 0 none, 1 bending, ...`), or, for the beam's `failure_mode`, from
/// [`FailureMode::from_code`].
fn class_name(m: &MetricResult, v: f64) -> Option<String> {
    code_name(&m.reference_source, v).or_else(|| {
        (m.name == FAILURE_MODE_METRIC)
            .then(|| FailureMode::from_code(v))
            .flatten()
            .map(|mode| mode.name().to_string())
    })
}

/// The worst metric as one line of plain text: `peak_force: 3.2× tolerance`, or the value
/// against its reference where no finite multiple of the tolerance exists
/// (`failure_mode: shear, expected mixed`).
pub fn worst_text(m: &MetricResult) -> String {
    match ratio_text(m) {
        Some(ratio) => format!("{}: {ratio} tolerance", m.name),
        None => format!("{}: {}", m.name, against_reference(m)),
    }
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

/// How many cases are in `state`.
pub fn count_state(results: &RunResults, state: CaseState) -> usize {
    results
        .cases
        .iter()
        .filter(|c| CaseState::of(c) == state)
        .count()
}

/// What a case's result means to the reader: its status, with a failure the case records as
/// known (`known_failure`) told apart from a new one. A known failure neither passes nor fails
/// the run ([`RunResults::exit_code`]), so the page shows it in a colour of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseState {
    /// Every metric met its tolerance.
    Pass,
    /// Failed the way the case file says it is known to fail: debt, not a regression.
    KnownFailure,
    /// Failed without being known to: fails the run.
    Fail,
    /// Could not be evaluated: fails the run.
    Error,
    /// Not run (filtered out or not applicable here).
    Skipped,
    /// Stopped before it finished.
    Interrupted,
}

/// States in the order the page counts them: good news first, then what needs a look.
pub const STATES: [CaseState; 6] = [
    CaseState::Pass,
    CaseState::KnownFailure,
    CaseState::Fail,
    CaseState::Error,
    CaseState::Skipped,
    CaseState::Interrupted,
];

impl CaseState {
    /// The state of `case`.
    pub fn of(case: &CaseResult) -> Self {
        match case.status {
            Status::Pass => CaseState::Pass,
            Status::Fail if case.known_failure.is_some() => CaseState::KnownFailure,
            Status::Fail => CaseState::Fail,
            Status::Error => CaseState::Error,
            Status::Skipped => CaseState::Skipped,
            Status::Interrupted => CaseState::Interrupted,
        }
    }

    /// The CSS class of its badge, row and call-out (`known` for a known failure, the status
    /// name otherwise).
    pub fn class(self) -> &'static str {
        match self {
            CaseState::Pass => "pass",
            CaseState::KnownFailure => "known",
            CaseState::Fail => "fail",
            CaseState::Error => "error",
            CaseState::Skipped => "skipped",
            CaseState::Interrupted => "interrupted",
        }
    }

    /// Its name in badges and tables (`known failure`, the status name otherwise).
    pub fn label(self) -> &'static str {
        match self {
            CaseState::KnownFailure => "known failure",
            other => other.class(),
        }
    }

    /// `n` cases in this state, in words: `3 passed`, `1 known failure`, `2 errors`.
    pub fn counted(self, n: usize) -> String {
        let what = match self {
            CaseState::Pass => "passed",
            CaseState::KnownFailure => plural(n, "known failure", "known failures"),
            CaseState::Fail => "failed",
            CaseState::Error => plural(n, "error", "errors"),
            CaseState::Skipped => "skipped",
            CaseState::Interrupted => "interrupted",
        };
        format!("{n} {what}")
    }
}

/// How the run reads at a glance, by its worst case: the colour of the banner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    /// Every case that ran passed (some may have been skipped).
    Good,
    /// Nothing new failed, but known failures remain.
    Known,
    /// A case failed, errored or was interrupted, or no case ran.
    Bad,
}

impl Tone {
    /// The CSS class of the banner.
    pub fn class(self) -> &'static str {
        match self {
            Tone::Good => "ok",
            Tone::Known => "known",
            Tone::Bad => "bad",
        }
    }
}

/// The run's overall verdict: the headline and its tone.
pub struct Verdict {
    /// The headline: the cases counted per state, e.g.
    /// `41 passed · 20 known failures · 0 failed · 1 error`.
    pub text: String,
    /// Red for any failure, error or interruption, amber for known failures alone, green
    /// otherwise.
    pub tone: Tone,
}

/// Counts passes and failures always, known failures, errors, skipped and interrupted cases
/// where there are any, so that the headline says at a glance what the run found; its tone is
/// that of the worst case.
pub fn verdict(results: &RunResults) -> Verdict {
    if results.cases.is_empty() {
        return Verdict {
            text: "No cases were run".to_string(),
            tone: Tone::Bad,
        };
    }
    let n = |state| count_state(results, state);
    let text = STATES
        .iter()
        .filter(|&&s| matches!(s, CaseState::Pass | CaseState::Fail) || n(s) > 0)
        .map(|&s| s.counted(n(s)))
        .collect::<Vec<_>>()
        .join(" · ");
    let tone = if n(CaseState::Fail) + n(CaseState::Error) + n(CaseState::Interrupted) > 0 {
        Tone::Bad
    } else if n(CaseState::KnownFailure) > 0 {
        Tone::Known
    } else {
        Tone::Good
    };
    Verdict { text, tone }
}

/// `one` when `n` is 1, else `many`.
pub fn plural<'s>(n: usize, one: &'s str, many: &'s str) -> &'s str {
    if n == 1 {
        one
    } else {
        many
    }
}

/// The name of an integer code `v` where `text` lists the codes as `code 0 none, 1 bending, ...`.
pub fn code_name(text: &str, v: f64) -> Option<String> {
    if v.fract() != 0.0 || !v.is_finite() {
        return None;
    }
    let list = &text[text.find("code ")? + 5..];
    let list = list.split([')', ';']).next()?;
    list.split(',').find_map(|item| {
        let mut words = item.split_whitespace();
        let code: f64 = words.next()?.parse().ok()?;
        (code == v).then(|| words.collect::<Vec<_>>().join(" "))
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn code_names_are_read_from_the_reference_source() {
        let text =
            "failure mode `bending` (thesis 10.3.2; code 0 none, 1 bending, 2 mixed, 3 shear)";
        assert_eq!(code_name(text, 2.0).as_deref(), Some("mixed"));
        assert_eq!(code_name(text, 1.5), None);
        assert_eq!(code_name("no codes", 1.0), None);
    }

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
            reading: None,
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
