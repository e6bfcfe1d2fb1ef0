//! Judgement: a measured value against its reference and tolerance.

use crate::catalogue::{MetricSpec, Tolerance};
use crate::results::{MetricResult, ToleranceKind};

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
        Tolerance::AtMost(t) => (value, *t, value <= *t, ToleranceKind::AtMost),
        Tolerance::AtLeast(t) => (value, *t, value >= *t, ToleranceKind::AtLeast),
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
