//! `impact-vv run --resume <run>`: finishes a catalogue run that was stopped (a signal) or
//! killed outright. The run's folder holds the case files it runs (`plan.txt`), its facts
//! (`run.json`) and a line per finished case and variant (`cases.jsonl`). The jobs recorded
//! there with a verdict are kept; the others (never started, interrupted, or cut by the kill)
//! run now into the same folder, their lines appended as they finish; then the report, the
//! history and the summary are written for the whole run, as if it had never stopped.

use std::collections::HashSet;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use super::run::{finish, run_with_progress, RunArgs, PLAN_FILE};
use crate::case_file::load_case;
use crate::registry::KINDS;
use crate::results::{CaseResult, RunResults, Status};
use crate::run_log::{self, RunLog};
use crate::runner::job_names;

/// Finishes the run in `dir` (see the module's documentation).
pub fn exec(dir: &Path, args: &RunArgs) -> ExitCode {
    let plan_path = dir.join(PLAN_FILE);
    let plan = match std::fs::read_to_string(&plan_path) {
        Ok(text) => text,
        Err(e) => {
            eprintln!(
                "error: cannot read {}: {e}; give the folder of a run (`reports/<run-id>`) \
                 started by this version of impact-vv",
                plan_path.display()
            );
            return ExitCode::from(2);
        }
    };
    let mut cases = Vec::new();
    for line in plan.lines().filter(|l| !l.trim().is_empty()) {
        match load_case(Path::new(line), &KINDS) {
            Ok(c) => cases.push(c),
            Err(e) => {
                eprintln!("error: {e} (a case of {})", plan_path.display());
                return ExitCode::from(2);
            }
        }
    }
    let before = match run_log::rebuild(dir) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let finished = |c: &CaseResult| c.status != Status::Interrupted;
    let kept: Vec<CaseResult> = before
        .cases
        .iter()
        .filter(|c| finished(c))
        .cloned()
        .collect();
    let done: HashSet<(String, String)> = kept
        .iter()
        .map(|c| (c.id.clone(), c.variant.clone()))
        .collect();
    let jobs = job_names(&cases);
    let left = jobs.iter().filter(|j| !done.contains(*j)).count();
    eprintln!(
        "impact-vv: resuming run {} ({} of {} case runs finished, {left} to run), {} thread(s)",
        before.run_id,
        jobs.len() - left,
        jobs.len(),
        rayon::current_num_threads()
    );
    // The log starts again from the kept lines: interrupted ones go, and a line the kill cut.
    let log = match RunLog::restart(dir, &kept) {
        Ok(log) => Some(log),
        Err(e) => {
            eprintln!(
                "warning: cannot rewrite {}: {e}; a killed run would lose its results",
                dir.join(run_log::CASES_FILE).display()
            );
            None
        }
    };
    let started = Instant::now();
    let stop = super::stop_on_signal();
    let wanted = |id: &str, variant: &str| !done.contains(&(id.to_string(), variant.to_string()));
    let new = run_with_progress(&cases, &wanted, dir, log.as_ref(), &stop, args);
    // The whole run in catalogue order: each job's kept or new result.
    let mut new = new.into_iter();
    let mut kept = kept
        .into_iter()
        .map(|c| ((c.id.clone(), c.variant.clone()), c));
    let mut kept: std::collections::HashMap<_, _> = kept.by_ref().collect();
    let cases = jobs
        .iter()
        .filter_map(|job| kept.remove(job).or_else(|| new.next()))
        .collect();
    let results = RunResults {
        cases,
        wall_s: started.elapsed().as_secs_f64(),
        ..before
    };
    finish(dir, &args.reports, &results, stop.load(Ordering::Relaxed))
}
