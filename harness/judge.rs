//! Judgement: a measured value against its reference and tolerance.

use impact_solver::scene::Scene;

use crate::catalogue::{MetricSpec, Tolerance};
use crate::results::{MetricResult, Status, ToleranceKind};

/// A measured value, with the measure's own verdict where it gives one.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// The value, in the metric's unit.
    pub value: f64,
    /// The measure's verdict on its own reading (a crack-tip speed judged with its
    /// resolution), `None` for measures whose value the tolerance alone judges.
    pub reading: Option<Reading>,
}

/// A measure's verdict on its own reading: a metric with one passes only if the reading passes
/// too. It says what the tolerance cannot see, such as a value within its resolution of the
/// bound ("inconclusive") or no value to judge ("no tip").
#[derive(Debug, Clone, PartialEq)]
pub struct Reading {
    /// Whether the reading passes.
    pub pass: bool,
    /// One line: its status and why, as the report shows it.
    pub text: String,
}

impl From<f64> for Measured {
    fn from(value: f64) -> Self {
        Self {
            value,
            reading: None,
        }
    }
}

/// The metrics of one case, judged, and why any could not be.
#[derive(Debug, Default)]
pub struct Judgement {
    /// Each judged metric with its value, reference, band and verdict.
    pub metrics: Vec<MetricResult>,
    /// Metrics that could not be judged: no reference, a reference or a measurement that failed.
    pub failures: Vec<String>,
}

/// The one judging loop of every case kind. For each metric: its reference (evaluated on
/// `scene` where the case has one), the value the kind measures for it (`measure` gets the
/// metric's index and spec and the reference value, for kinds that also record errors per sweep
/// level), and the
/// verdict of `judge`. A metric without a reference is a failure, never skipped.
pub fn judge_metrics<E: std::fmt::Display>(
    metrics: &[MetricSpec],
    scene: Option<&Scene>,
    measure: &mut dyn FnMut(usize, &MetricSpec, f64) -> Result<f64, E>,
    peak: &dyn Fn(&str) -> Option<f64>,
) -> Judgement {
    judge_readings(
        metrics,
        scene,
        &mut |i, m, r| measure(i, m, r).map(Measured::from),
        peak,
    )
}

/// [`judge_metrics`] for kinds whose measures may give their own verdict ([`Measured`]).
pub fn judge_readings<E: std::fmt::Display>(
    metrics: &[MetricSpec],
    scene: Option<&Scene>,
    measure: &mut dyn FnMut(usize, &MetricSpec, f64) -> Result<Measured, E>,
    peak: &dyn Fn(&str) -> Option<f64>,
) -> Judgement {
    let mut judgement = Judgement::default();
    for (i, m) in metrics.iter().enumerate() {
        let Some(reference) = &m.reference else {
            judgement.failures.push(format!(
                "metric `{}` has no reference: every metric needs one",
                m.name
            ));
            continue;
        };
        let judged = reference
            .evaluate_for(scene)
            .map_err(|e| format!("metric `{}`: reference: {e}", m.name))
            .and_then(|(r, source)| {
                measure(i, m, r)
                    .map(|v| (v, r, source))
                    .map_err(|e| format!("metric `{}`: {e}", m.name))
            });
        match judged {
            Ok((measured, r, source)) => {
                let r = reference.judged_value(r, measured.value);
                let mut result = judge(m, measured.value, r, &source, peak);
                if let Some(reading) = measured.reading {
                    result.pass &= reading.pass;
                    result.reading = Some(reading.text);
                }
                judgement.metrics.push(result);
            }
            Err(e) => judgement.failures.push(e),
        }
    }
    judgement
}

impl Judgement {
    /// The case's status and message, in the one format of every kind: the metrics that could
    /// not be judged, then `failed:` with each failed metric (`failure_line`), then the kind's
    /// `notes` (its setup, provenance or plan).
    pub fn verdict(&self, notes: &[String]) -> (Status, String) {
        let failed: Vec<String> = self
            .metrics
            .iter()
            .filter(|m| !m.pass)
            .map(failure_line)
            .collect();
        let mut lines = self.failures.clone();
        if !failed.is_empty() {
            lines.push(format!("failed: {}", failed.join("; ")));
        }
        let status = if lines.is_empty() {
            Status::Pass
        } else {
            Status::Fail
        };
        lines.extend(notes.iter().cloned());
        (status, lines.join("; "))
    }
}

/// One failed metric: its value against the reference, the error and the tolerance.
pub fn failure_line(m: &MetricResult) -> String {
    let reading = m
        .reading
        .as_ref()
        .map_or(String::new(), |r| format!(" [{r}]"));
    format!(
        "`{}` = {:.6e} against {:.6e} (error {:.3e}, tolerance {:.3e}){reading}",
        m.name, m.value, m.reference, m.error, m.tolerance
    )
}

/// Relative round-off a one-sided bound allows: a value that meets its bound exactly in exact
/// arithmetic passes although the floating-point sums that produced it land a few ulps past it
/// (a coalescence of exactly one 50 mm cell, summed from centroid heights, reads
/// 0.05 + 4e-17 m in `beam/drop-2ms`).
pub const BOUND_ROUND_OFF: f64 = 1e-12;

/// The round-off allowance of a one-sided bound `bound` on `value` ([`BOUND_ROUND_OFF`]).
fn round_off(value: f64, bound: f64) -> f64 {
    BOUND_ROUND_OFF * value.abs().max(bound.abs())
}

/// Judges `value` for `spec` against the evaluated `reference` (value and source). `peak` gives
/// `max |column|` of the run's history for `relative_to_peak` tolerances.
pub fn judge(
    spec: &MetricSpec,
    value: f64,
    reference: f64,
    source: &str,
    peak: &dyn Fn(&str) -> Option<f64>,
) -> MetricResult {
    let (error, tolerance, pass, kind) = match &spec.tolerance {
        Tolerance::Absolute(t) => {
            let e = (value - reference).abs();
            (e, *t, e <= *t, ToleranceKind::Absolute)
        }
        Tolerance::Relative(t) => {
            let e = (value - reference).abs() / reference.abs();
            (e, *t, e <= *t, ToleranceKind::Relative)
        }
        Tolerance::AtMost(t) => (
            value,
            *t,
            value <= *t + round_off(value, *t),
            ToleranceKind::AtMost,
        ),
        Tolerance::AtLeast(t) => (
            value,
            *t,
            value >= *t - round_off(value, *t),
            ToleranceKind::AtLeast,
        ),
        Tolerance::AtLeastRatio(t) => {
            let e = value / reference;
            (e, *t, e >= *t, ToleranceKind::AtLeastRatio)
        }
        Tolerance::RelativeToPeak { fraction, column } => {
            // A missing column leaves the scale NaN, and a NaN never passes.
            let scale = peak(column).unwrap_or(f64::NAN);
            let e = (value - reference).abs() / scale;
            (e, *fraction, e <= *fraction, ToleranceKind::RelativeToPeak)
        }
    };
    MetricResult {
        name: spec.name.clone(),
        value,
        reference,
        error,
        tolerance,
        unit: spec.unit.clone(),
        // NaN compares false: a NaN value never passes.
        pass: pass && value.is_finite(),
        tolerance_kind: kind,
        reference_source: source.to_string(),
        reading: None,
    }
}

/// The error of a value against its reference in the metric's own sense, for convergence
/// orders and work-precision diagrams: relative when the tolerance is relative, else absolute.
pub fn error_for_sweep(spec: &MetricSpec, value: f64, reference: f64) -> f64 {
    match spec.tolerance {
        Tolerance::Relative(_) | Tolerance::RelativeToPeak { .. } => {
            (value - reference).abs() / reference.abs()
        }
        Tolerance::AtMost(_) | Tolerance::AtLeast(_) => value.abs(),
        Tolerance::AtLeastRatio(_) => value / reference,
        Tolerance::Absolute(_) => (value - reference).abs(),
    }
}

/// Least-squares slope of `log(error)` against `log(parameter)`: the observed order of
/// convergence (Roache 1998). `None` with fewer than two usable points.
pub fn observed_order(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(h, e)| *h > 0.0 && *e > 0.0 && h.is_finite() && e.is_finite())
        .map(|(h, e)| (h.ln(), e.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_to_peak_scales_by_the_largest_history_value() {
        let spec: MetricSpec = serde_json::from_value(serde_json::json!({
            "name": "reaction_at_end",
            "measure": { "history_final": { "column": "force" } },
            "tolerance": { "relative_to_peak": { "fraction": 0.01, "column": "force" } }
        }))
        .unwrap();
        let peak = |c: &str| (c == "force").then_some(200.0);
        // A value near zero, judged against 1 % of the 200 N peak: 1.5 N off passes, 2.5 N fails.
        assert!(judge(&spec, 1.5, 0.0, "", &peak).pass);
        assert!(!judge(&spec, 2.5, 0.0, "", &peak).pass);
        // Without the column the scale is unknown and the metric never passes.
        assert!(!judge(&spec, 0.0, 0.0, "", &|_| None).pass);
    }

    /// A failure-mode metric as a case file writes it, with the reference `modes`.
    fn mode_metric(modes: &str) -> MetricSpec {
        let yaml = format!(
            "{{ name: failure_mode, measure: {{ failure_mode: {{ body: beam }} }}, reference: {{ failure_mode: {modes} }}, tolerance: {{ absolute: 0.0 }} }}"
        );
        // As the catalogue reads a case: externally tagged enums as single-key maps.
        serde_norway::with::singleton_map_recursive::deserialize(
            serde_norway::Deserializer::from_str(&yaml),
        )
        .expect("parses")
    }

    /// Whether a measured failure-mode code passes against the reference `modes`.
    fn mode_passes(modes: &str, measured: crate::beam::FailureMode) -> bool {
        let metrics = [mode_metric(modes)];
        let j = judge_readings(
            &metrics,
            None,
            &mut |_, _, _| Ok::<_, String>(Measured::from(measured.code())),
            &|_| None,
        );
        assert!(j.failures.is_empty(), "{:?}", j.failures);
        j.metrics[0].pass
    }

    #[test]
    fn a_failure_mode_passes_when_it_is_one_the_reference_accepts() {
        use crate::beam::FailureMode::*;
        assert!(mode_passes("bending", Bending));
        assert!(!mode_passes("bending", Mixed));
        for m in [Mixed, Shear] {
            assert!(mode_passes("[mixed, shear]", m), "{m:?}");
        }
        for m in [None, Bending, BendingInclined] {
            assert!(!mode_passes("[mixed, shear]", m), "{m:?}");
        }
        assert!(mode_passes("[bending_inclined, mixed]", BendingInclined));
        assert!(!mode_passes("[bending_inclined, mixed]", Shear));
        // An empty list accepts nothing.
        assert!(!mode_passes("[]", Mixed));
    }

    #[test]
    fn a_one_sided_bound_holds_to_round_off_only() {
        let spec = |tolerance: serde_json::Value| -> MetricSpec {
            serde_json::from_value(serde_json::json!({
                "name": "coalescence",
                "measure": { "history_final": { "column": "x" } },
                "tolerance": tolerance
            }))
            .unwrap()
        };
        let none = |_: &str| None;
        let at_most = spec(serde_json::json!({ "at_most": 0.05 }));
        // One cell from centroid heights: 6 * 0.0125 - 2 * 0.0125 lands 1e-17 past 0.05.
        let one_cell = 6.0 * 0.0125 - 2.0 * 0.0125;
        assert!(one_cell > 0.05);
        assert!(judge(&at_most, one_cell, 0.0, "", &none).pass);
        assert!(!judge(&at_most, 0.05 + 1e-9, 0.0, "", &none).pass);
        assert!(!judge(&at_most, 0.0625, 0.0, "", &none).pass);
        let at_least = spec(serde_json::json!({ "at_least": 0.05 }));
        assert!(judge(&at_least, 0.05 - 4e-17, 0.0, "", &none).pass);
        assert!(!judge(&at_least, 0.05 - 1e-9, 0.0, "", &none).pass);
        // A bound of zero allows nothing: 1e-300 above it fails.
        let zero = spec(serde_json::json!({ "at_most": 0.0 }));
        assert!(judge(&zero, 0.0, 0.0, "", &none).pass);
        assert!(!judge(&zero, 1e-300, 0.0, "", &none).pass);
        // NaN never passes.
        assert!(!judge(&at_most, f64::NAN, 0.0, "", &none).pass);
    }

    #[test]
    fn observed_order_of_an_exact_power_law() {
        let pts: Vec<(f64, f64)> = [0.1, 0.05, 0.025]
            .iter()
            .map(|h| (*h, 3.0 * h * h))
            .collect();
        assert!((observed_order(&pts).unwrap() - 2.0).abs() < 1e-12);
        assert!(observed_order(&pts[..1]).is_none());
    }
}
