//! `impact-vv report`: writes the report of a finished run, rebuilding its results first when
//! the run was killed before it wrote them.

use std::path::Path;
use std::process::ExitCode;

use crate::registry::SECTIONS;
use crate::results::RunResults;
use crate::run_log::RebuildError;
use crate::{report, run_log};

/// Writes the report of the run in `run`, with the history of `reports`.
pub fn exec(run: &Path, reports: &Path) -> ExitCode {
    if !run.join("results.json").exists() && run.join(run_log::CASES_FILE).exists() {
        // A run that was killed outright: its finished cases are in cases.jsonl.
        if let Err(e) = rebuild_results(run, reports) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    let text = match std::fs::read_to_string(run.join("results.json")) {
        Ok(t) => t,
        Err(e) => {
            eprintln!(
                "error: cannot read {}: {e}",
                run.join("results.json").display()
            );
            return ExitCode::from(2);
        }
    };
    let results: RunResults = match serde_json::from_str(&text) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {}: {e}", run.join("results.json").display());
            return ExitCode::from(2);
        }
    };
    let history = report::read_history(&reports.join("history.jsonl")).unwrap_or_default();
    match report::write_report(run, &results, &history, SECTIONS) {
        Ok(index) => {
            println!("report: {}", index.display());
            ExitCode::from(results.exit_code())
        }
        Err(e) => {
            eprintln!("error: cannot write the report: {e}");
            ExitCode::from(2)
        }
    }
}

/// Writes `<run>/results.json` from `run.json` and `cases.jsonl` of a run that was killed before
/// it wrote it, and appends its cases to the history.
fn rebuild_results(run: &Path, reports: &Path) -> Result<(), RebuildError> {
    let results = run_log::rebuild(run)?;
    let results_file = run.join("results.json");
    let cannot = |action, path: &Path, e: &dyn std::fmt::Display| RebuildError::Write {
        action,
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let text =
        serde_json::to_string_pretty(&results).map_err(|e| cannot("write", &results_file, &e))?;
    std::fs::write(run.join("results.json"), text)
        .map_err(|e| cannot("write", &results_file, &e))?;
    let history = reports.join("history.jsonl");
    report::append_history(&history, &results.history_records())
        .map_err(|e| cannot("append to", &history, &e))?;
    eprintln!(
        "rebuilt {} from {} ({} finished cases)",
        run.join("results.json").display(),
        run.join(run_log::CASES_FILE).display(),
        results.cases.len()
    );
    Ok(())
}
