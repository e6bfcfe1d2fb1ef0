//! The plots the report derives itself: convergence and work-precision diagrams of a sweep, and
//! the trend of each metric across runs from the history.

use std::collections::BTreeSet;

use super::summary::acceptance_band;
use crate::results::{CaseResult, HistoryRecord, PlotData, ReferenceLine, Series, SweepResult};

/// How many past runs a trend shows: enough to see a drift, few enough to read each point.
pub const TREND_RUNS: usize = 30;

/// The metric names of a sweep, in name order (the union over levels: a level that failed may
/// lack some).
pub fn sweep_metrics(sweep: &SweepResult) -> Vec<String> {
    sweep
        .levels
        .iter()
        .flat_map(|l| l.errors.keys().cloned())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect()
}

/// Error against the swept parameter, log-log, one curve per metric named with its observed
/// order, so that the slope can be compared with the expected one at a glance.
pub fn convergence_plot(case: &CaseResult, sweep: &SweepResult) -> PlotData {
    let series = sweep_metrics(sweep)
        .into_iter()
        .map(|metric| {
            let name = match sweep.observed_order.get(&metric) {
                Some(order) => format!("{metric} (order {order:.2})"),
                None => metric.clone(),
            };
            sweep_series(sweep, &metric, name, |l| l.parameter)
        })
        .collect();
    PlotData {
        title: format!("Convergence: {}", case.id),
        x_label: sweep.parameter.clone(),
        y_label: "error".to_string(),
        series,
        reference_lines: Vec::new(),
        log_log: true,
    }
}

/// Error against wall time, log-log, one curve per metric of this variant: which variant buys a
/// given accuracy for the least time.
pub fn work_precision_plot(case: &CaseResult, sweep: &SweepResult) -> PlotData {
    let series = sweep_metrics(sweep)
        .into_iter()
        .map(|metric| {
            let name = format!("{metric} ({})", case.variant);
            sweep_series(sweep, &metric, name, |l| l.wall_s)
        })
        .collect();
    PlotData {
        title: format!("Work-precision: {}", case.id),
        x_label: "wall time [s]".to_string(),
        y_label: "error".to_string(),
        series,
        reference_lines: Vec::new(),
        log_log: true,
    }
}

/// One metric's error over the sweep levels against `x` of each level; a level without that
/// metric contributes a NaN, which the plot drops.
fn sweep_series(
    sweep: &SweepResult,
    metric: &str,
    name: String,
    x: impl Fn(&crate::results::SweepLevel) -> f64,
) -> Series {
    Series {
        name,
        x: sweep.levels.iter().map(&x).collect(),
        y: sweep
            .levels
            .iter()
            .map(|l| l.errors.get(metric).copied().unwrap_or(f64::NAN))
            .collect(),
    }
}

/// The trend of one case: the runs it covers (oldest first) and one plot per metric.
pub struct Trend<'h> {
    pub runs: Vec<&'h HistoryRecord>,
    pub plots: Vec<PlotData>,
}

/// The trend of `case` over the last [`TREND_RUNS`] history records of the same case id and
/// variant, in file order. A metric gets a plot when at least two of those runs recorded it;
/// the wall time always does. Empty when there are fewer than two runs.
pub fn trend<'h>(case: &CaseResult, history: &'h [HistoryRecord]) -> Trend<'h> {
    let matching: Vec<&HistoryRecord> = history
        .iter()
        .filter(|r| r.case == case.id && r.variant == case.variant)
        .collect();
    let runs = matching[matching.len().saturating_sub(TREND_RUNS)..].to_vec();
    if runs.len() < 2 {
        return Trend {
            runs,
            plots: Vec::new(),
        };
    }
    let mut plots: Vec<PlotData> = trend_metrics(case, &runs)
        .into_iter()
        .map(|name| metric_trend(case, &runs, &name))
        .collect();
    plots.push(wall_time_trend(&runs));
    Trend { runs, plots }
}

/// Metrics recorded by at least two of `runs`: the case's own metrics first, in its order, then
/// metrics only the history knows (renamed or dropped since), by name.
fn trend_metrics(case: &CaseResult, runs: &[&HistoryRecord]) -> Vec<String> {
    let recorded = |name: &str| runs.iter().filter(|r| r.metrics.contains_key(name)).count() >= 2;
    let current = case.metrics.iter().map(|m| m.name.clone());
    let historical: BTreeSet<String> = runs
        .iter()
        .flat_map(|r| r.metrics.keys().cloned())
        .filter(|n| !case.metrics.iter().any(|m| &m.name == n))
        .collect();
    current.chain(historical).filter(|n| recorded(n)).collect()
}

/// The run indices of a trend's x axis: 1 for the oldest shown run.
fn run_indices(runs: &[&HistoryRecord]) -> Vec<f64> {
    (1..=runs.len()).map(|i| i as f64).collect()
}

/// The value of one metric per run, with the current reference and acceptance band when the
/// case still has that metric.
fn metric_trend(case: &CaseResult, runs: &[&HistoryRecord], name: &str) -> PlotData {
    let current = case.metrics.iter().find(|m| m.name == name);
    let unit = current.map(|m| m.unit.as_str()).filter(|u| !u.is_empty());
    PlotData {
        title: format!("{name} per run"),
        x_label: "run".to_string(),
        y_label: match unit {
            Some(unit) => format!("{name} [{unit}]"),
            None => name.to_string(),
        },
        series: vec![Series {
            name: name.to_string(),
            x: run_indices(runs),
            y: runs
                .iter()
                .map(|r| r.metrics.get(name).copied().unwrap_or(f64::NAN))
                .collect(),
        }],
        reference_lines: current
            .map(|m| ReferenceLine {
                label: "reference".to_string(),
                y: m.reference,
                band: acceptance_band(m),
            })
            .into_iter()
            .collect(),
        log_log: false,
    }
}

/// The wall time of the case per run: performance regressions show here.
fn wall_time_trend(runs: &[&HistoryRecord]) -> PlotData {
    PlotData {
        title: "wall time per run".to_string(),
        x_label: "run".to_string(),
        y_label: "wall time [s]".to_string(),
        series: vec![Series {
            name: "wall time".to_string(),
            x: run_indices(runs),
            y: runs.iter().map(|r| r.wall_s).collect(),
        }],
        reference_lines: Vec::new(),
        log_log: false,
    }
}
