//! What the report tests share: scratch folders, and a run of three cases (a pass, a failing
//! sweep, an error) with its metrics, plots and history.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::fs;
use std::path::PathBuf;

use impact_vv::results::{
    CaseResult, HistoryRecord, MetricResult, PlotData, ReferenceLine, RunResults, Series, Status,
    SweepLevel, SweepResult,
};

pub const PASS_ID: &str = "bar-wave-speed";
pub const FAIL_ID: &str = "cantilever-mesh-convergence";
pub const ERROR_ID: &str = "projectile-penetration";
pub const WORST: &str = "tip_deflection_error";
pub const NASTY: &str = "solver diverged: <script>alert('x')</script> & energy > 1e9";

/// A fresh, empty scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("impact-vv-report-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn metric(name: &str, value: f64, reference: f64, tolerance: f64, kind: &str) -> MetricResult {
    let error = match kind {
        "relative" => (value - reference).abs() / reference.abs(),
        _ => (value - reference).abs(),
    };
    MetricResult {
        name: name.to_string(),
        value,
        reference,
        error,
        tolerance,
        unit: "m/s".to_string(),
        pass: error <= tolerance,
        tolerance_kind: serde_json::from_value(serde_json::Value::String(kind.into())).unwrap(),
        reference_source: "c = sqrt(E/rho), Graff (1975) eq. 2.1.8".to_string(),
        reading: None,
    }
}

/// A time history with a reference plateau and its acceptance band.
pub fn history_plot() -> PlotData {
    let t: Vec<f64> = (0..200).map(|i| i as f64 * 1e-6).collect();
    let v: Vec<f64> = t
        .iter()
        .map(|t| 3000.0 * (1.0 - (-t / 2e-5).exp()))
        .collect();
    PlotData {
        title: "Particle velocity at x = 0.5 m".to_string(),
        x_label: "time [s]".to_string(),
        y_label: "velocity [m/s]".to_string(),
        series: vec![Series {
            name: "solver".to_string(),
            x: t,
            y: v,
        }],
        reference_lines: vec![ReferenceLine {
            label: "plateau (analytic)".to_string(),
            y: 3000.0,
            band: Some([2940.0, 3060.0]),
        }],
        log_log: false,
    }
}

pub fn pass_case() -> CaseResult {
    CaseResult {
        id: PASS_ID.to_string(),
        variant: "explicit-lumped".to_string(),
        status: Status::Pass,
        wall_s: 1.234,
        metrics: vec![
            metric("wave_speed", 3510.0, 3500.0, 0.02, "relative"),
            metric("plateau_velocity", 2990.0, 3000.0, 60.0, "absolute"),
        ],
        description: "Elastic bar struck at one end: the front travels at c.".to_string(),
        tier: "smoke".to_string(),
        tags: vec!["wave".to_string(), "1d".to_string()],
        message: Some("plan: 200 steps of 1e-6 s, 4000 elements".to_string()),
        plots: vec![history_plot()],
        sweep: None,
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        peak_memory_mib: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

pub fn level(h: f64, wall_s: f64, deflection: f64, frequency: f64) -> SweepLevel {
    SweepLevel {
        parameter: h,
        wall_s,
        errors: BTreeMap::from([
            (WORST.to_string(), deflection),
            ("frequency_error".to_string(), frequency),
        ]),
        values: BTreeMap::new(),
        status: impact_vv::results::LevelStatus::Completed,
    }
}

pub fn fail_case() -> CaseResult {
    let sweep = SweepResult {
        parameter: "element size [m]".to_string(),
        levels: vec![
            level(0.1, 0.05, 4e-2, 1e-2),
            level(0.05, 0.31, 2.1e-2, 2.6e-3),
            level(0.025, 2.2, 1.1e-2, 6.4e-4),
            level(0.0125, 17.0, 5.6e-3, 1.6e-4),
        ],
        observed_order: BTreeMap::from([
            (WORST.to_string(), 0.95),
            ("frequency_error".to_string(), 2.0),
        ]),
    };
    CaseResult {
        id: FAIL_ID.to_string(),
        variant: "explicit-lumped".to_string(),
        status: Status::Fail,
        wall_s: 19.6,
        metrics: vec![
            metric("frequency", 101.0, 100.0, 0.05, "relative"),
            metric(WORST, 0.1056, 0.1, 0.001, "absolute"),
        ],
        description: "Cantilever under tip load, refined four times.".to_string(),
        tier: "nightly".to_string(),
        tags: vec!["convergence".to_string()],
        message: Some("tip deflection order 0.95 < expected 2".to_string()),
        plots: vec![],
        sweep: Some(sweep),
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        peak_memory_mib: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

pub fn error_case() -> CaseResult {
    CaseResult {
        id: ERROR_ID.to_string(),
        status: Status::Error,
        wall_s: 0.2,
        metrics: vec![],
        description: "Steel projectile into a concrete slab.".to_string(),
        tier: "nightly".to_string(),
        tags: vec![],
        message: Some(NASTY.to_string()),
        plots: vec![],
        ..pass_case()
    }
}

pub fn results(run_id: &str) -> RunResults {
    RunResults {
        run_id: run_id.to_string(),
        commit: "50c344d".to_string(),
        tier: "nightly".to_string(),
        cases: vec![pass_case(), fail_case(), error_case()],
        date: "2025-01-03T10:00:00Z".to_string(),
        machine: "ci-runner-7 (16 cores)".to_string(),
        threads: 16,
        versions: BTreeMap::from([
            ("impact-solver".to_string(), "0.1.0".to_string()),
            ("rustc".to_string(), "1.85.0".to_string()),
        ]),
        wall_s: 21.0,
    }
}

/// Three runs: two earlier ones with drifting values, then the current run.
pub fn three_run_history(current: &RunResults) -> Vec<HistoryRecord> {
    let mut history = Vec::new();
    for (run, drift) in [("run-1", 0.97), ("run-2", 0.99)] {
        for mut record in current.history_records() {
            record.run_id = run.to_string();
            record.wall_s *= drift;
            record.metrics.values_mut().for_each(|v| *v *= drift);
            history.push(record);
        }
    }
    history.extend(current.history_records());
    history
}
