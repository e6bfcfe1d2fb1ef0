//! `impact-vv run`: runs the selected cases, writes the report, the history and the list of
//! failed cases.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use crate::case_file::load_case;
use crate::case_kind::{LoadedCase, RunOptions};
use crate::catalogue::Tier;
use crate::registry::{KINDS, SECTIONS};
use crate::results::{RunResults, Status};
use crate::run_log::RunLog;
use crate::runner::run_jobs;
use crate::{metadata, report};

/// The arguments of `impact-vv run`.
#[derive(Debug, Clone)]
pub struct RunArgs {
    /// Case ids, globs, tags or case files; empty: the whole tier.
    pub patterns: Vec<String>,
    /// The tier to select in.
    pub tier: Option<Tier>,
    /// Rerun the cases that failed in the last run.
    pub failed: bool,
    /// The catalogue folder.
    pub catalogue: PathBuf,
    /// The reports folder.
    pub reports: PathBuf,
    /// Wall-time limit per solver run (s).
    pub time_limit: f64,
    /// Run cases one after the other.
    pub serial: bool,
    /// Print each case's log lines.
    pub verbose: bool,
    /// Finish the stopped run in this folder instead of starting one.
    pub resume: Option<PathBuf>,
}

/// Why the run's folder cannot be created.
#[derive(Debug, thiserror::Error)]
pub enum RunDirError {
    /// The reports folder cannot be created.
    #[error("cannot create the reports folder {folder}: {message}")]
    Reports {
        /// The reports folder.
        folder: String,
        /// The operating system's reason.
        message: String,
    },
    /// The run's folder cannot be created.
    #[error("cannot create {folder}: {message}")]
    Run {
        /// The run's folder.
        folder: String,
        /// The operating system's reason.
        message: String,
    },
    /// A thousand runs in one second.
    #[error("{reports}: a thousand runs already started in second {stamp}")]
    Exhausted {
        /// The reports folder.
        reports: String,
        /// The second's stamp.
        stamp: String,
    },
}

/// Selects the cases (by patterns, tier, or the last run's failures) and runs them. (`main`
/// hands `impact-vv run --resume` to the resume command instead.)
pub fn exec(args: &RunArgs) -> ExitCode {
    let names_files = args.patterns.iter().any(|p| Path::new(p).is_file());
    let cases = match super::catalogue(&args.catalogue, !names_files) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let patterns = if args.failed {
        match std::fs::read_to_string(args.reports.join("last-failed.txt")) {
            Ok(s) => s.lines().map(String::from).collect(),
            Err(_) => {
                eprintln!(
                    "no record of failed cases ({}): run first",
                    args.reports.join("last-failed.txt").display()
                );
                return ExitCode::from(2);
            }
        }
    } else {
        args.patterns.clone()
    };
    let tier = if patterns.is_empty() {
        args.tier.or(Some(Tier::Quick))
    } else {
        args.tier
    };
    let mut selected = super::select(&cases, &patterns, tier);
    match case_files_outside(&cases, &patterns) {
        Ok(mut outside) => selected.append(&mut outside),
        Err(code) => return code,
    }
    if selected.is_empty() {
        match tier {
            Some(t) => {
                eprintln!("error: no case matches {patterns:?} in tier {}", t.name())
            }
            None => eprintln!("error: no case matches {patterns:?}"),
        }
        return ExitCode::from(2);
    }
    run(selected, tier, args)
}

/// The patterns that name a case file outside the catalogue (in a temporary folder, say), loaded
/// as they are: an explicit file runs whatever its tier, its relative paths resolved from its own
/// folder. A file that does not load stops the run naming the file (and the line and key).
fn case_files_outside(
    cases: &[LoadedCase],
    patterns: &[String],
) -> Result<Vec<LoadedCase>, ExitCode> {
    let canonical = |p: &Path| std::fs::canonicalize(p).ok();
    let known: Vec<_> = cases.iter().filter_map(|c| canonical(&c.path)).collect();
    let mut outside = Vec::new();
    for pattern in patterns {
        let path = Path::new(pattern);
        let names_yaml = path.extension().is_some_and(|e| e == "yaml" || e == "yml");
        if names_yaml && !path.exists() {
            eprintln!(
                "error: {pattern}: no such case file (a case id is written without `.yaml`, as \
                 `impact-vv list` prints it)"
            );
            return Err(ExitCode::from(2));
        }
        let is_case_file =
            path.is_file() && path.extension().is_some_and(|e| e == "yaml" || e == "yml");
        if !is_case_file || canonical(path).is_some_and(|c| known.contains(&c)) {
            continue;
        }
        match load_case(path, &KINDS) {
            Ok(case) => outside.push(case),
            Err(e) => {
                eprintln!("error: {e}");
                eprintln!("1 case file error; nothing was run");
                return Err(ExitCode::from(2));
            }
        }
    }
    Ok(outside)
}

/// The tier a run reports: the one given, or `selected` for cases named by patterns alone.
fn tier_label(tier: Option<Tier>) -> &'static str {
    tier.map_or("selected", Tier::name)
}

/// Creates the run's folder `<reports>/<stamp>` and returns its id and path; when a run of the
/// same second has it, `<stamp>-2`, `<stamp>-3`, ...: two runs into one reports folder never
/// share a folder, whichever starts first.
fn claim_run_dir(reports: &Path, stamp: &str) -> Result<(String, PathBuf), RunDirError> {
    std::fs::create_dir_all(reports).map_err(|e| RunDirError::Reports {
        folder: reports.display().to_string(),
        message: e.to_string(),
    })?;
    for k in 1..1000 {
        let id = if k == 1 {
            stamp.to_string()
        } else {
            format!("{stamp}-{k}")
        };
        let dir = reports.join(&id);
        match std::fs::create_dir(&dir) {
            Ok(()) => return Ok((id, dir)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => {
                return Err(RunDirError::Run {
                    folder: dir.display().to_string(),
                    message: e.to_string(),
                })
            }
        }
    }
    Err(RunDirError::Exhausted {
        reports: reports.display().to_string(),
        stamp: stamp.into(),
    })
}

/// Runs `cases` into a new run folder of `args.reports`, writes the report and the history, and
/// prints the summary.
fn run(cases: Vec<LoadedCase>, tier: Option<Tier>, args: &RunArgs) -> ExitCode {
    let reports = args.reports.as_path();
    let (date, stamp) = metadata::now();
    let (run_id, dir) = match claim_run_dir(reports, &stamp) {
        Ok(claimed) => claimed,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let started = Instant::now();
    let threads = rayon::current_num_threads();
    eprintln!(
        "impact-vv: {} case(s), tier {}, {} thread(s), run {run_id}",
        cases.len(),
        tier_label(tier),
        threads
    );
    let stop = super::stop_on_signal();
    let facts = RunResults {
        run_id: run_id.clone(),
        commit: metadata::commit(),
        tier: tier_label(tier).into(),
        cases: Vec::new(),
        date,
        machine: metadata::machine(),
        threads,
        versions: metadata::versions(),
        wall_s: f64::NAN,
    };
    if let Err(e) = write_plan(&dir, &cases) {
        eprintln!(
            "warning: cannot write {}: {e}; the run cannot be resumed if it stops",
            dir.join(PLAN_FILE).display()
        );
    }
    let log = match RunLog::start(&dir, &facts) {
        Ok(log) => Some(log),
        Err(e) => {
            eprintln!(
                "warning: cannot start {}: {e}; a killed run would lose its results",
                dir.join(crate::run_log::CASES_FILE).display()
            );
            None
        }
    };
    let results = run_with_progress(&cases, &|_, _| true, &dir, log.as_ref(), &stop, args);
    let results = RunResults {
        cases: results,
        wall_s: started.elapsed().as_secs_f64(),
        ..facts
    };
    finish(&dir, reports, &results, stop.load(Ordering::Relaxed))
}

/// The end of a run: its records appended to the history, the failed cases listed for
/// `--failed`, the report written and the summary printed; the exit code.
pub(super) fn finish(dir: &Path, reports: &Path, results: &RunResults, stopped: bool) -> ExitCode {
    let history_path = reports.join("history.jsonl");
    if let Err(e) = report::append_history(&history_path, &results.history_records()) {
        eprintln!("warning: cannot append to {}: {e}", history_path.display());
    }
    let failed: Vec<&str> = results
        .cases
        .iter()
        .filter(|c| matches!(c.status, Status::Fail | Status::Error))
        .map(|c| c.id.as_str())
        .collect();
    let _ = std::fs::create_dir_all(reports);
    let _ = std::fs::write(reports.join("last-failed.txt"), failed.join("\n"));
    let history = report::read_history(&history_path).unwrap_or_default();
    match report::write_report(dir, results, &history, SECTIONS) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => {
            eprintln!("error: cannot write the report: {e}");
            return ExitCode::from(2);
        }
    }
    print_summary(results);
    if stopped {
        // The finished cases are judged, reported and in the history; the others are marked
        // interrupted. A status of its own, whatever the verdicts.
        eprintln!(
            "interrupted: the report holds the cases that finished; `impact-vv run --resume {}` \
             runs the others",
            dir.display()
        );
        return ExitCode::from(130);
    }
    ExitCode::from(results.exit_code())
}

/// The file in a run's folder that lists the case files it runs, one per line, for
/// `impact-vv run --resume`.
pub(super) const PLAN_FILE: &str = "plan.txt";

/// Writes `<dir>/plan.txt`: the case files of `cases`, absolute, in order.
fn write_plan(dir: &Path, cases: &[LoadedCase]) -> std::io::Result<()> {
    let lines: Vec<String> = cases
        .iter()
        .map(|c| {
            std::fs::canonicalize(&c.path)
                .unwrap_or_else(|_| c.path.clone())
                .display()
                .to_string()
        })
        .collect();
    std::fs::write(dir.join(PLAN_FILE), lines.join("\n") + "\n")
}

/// Runs the jobs of `cases` for which `wanted(id, variant)` holds into the run folder `dir`,
/// each finished one appended to `log`, with a progress bar and one line per job on the
/// terminal.
pub(super) fn run_with_progress(
    cases: &[LoadedCase],
    wanted: &(dyn Fn(&str, &str) -> bool + Sync),
    dir: &Path,
    log: Option<&RunLog>,
    stop: &std::sync::Arc<std::sync::atomic::AtomicBool>,
    args: &RunArgs,
) -> Vec<crate::results::CaseResult> {
    let jobs = crate::runner::job_names(cases)
        .iter()
        .filter(|(id, v)| wanted(id, v))
        .count();
    let bar = indicatif::ProgressBar::new(jobs as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix:>10} [{bar:40}] {pos}/{len} cases, {elapsed_precise}, left {eta}  {msg}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.set_prefix("running");
    if args.verbose {
        // The cases' log lines come from every worker thread at any time: without a bar to
        // redraw around them, they and the case lines stay whole.
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let results = run_jobs(
        cases,
        wanted,
        &RunOptions {
            output_dir: Some(dir.to_path_buf()),
            time_limit_s: args.time_limit,
            parallel: !args.serial,
            stop: Some(stop.clone()),
            verbose: args.verbose,
        },
        &|r| {
            if let Some(log) = log {
                if let Err(e) = log.append(r) {
                    eprintln!("warning: cannot append to {}: {e}", log.path().display());
                }
            }
            bar.inc(1);
            bar.set_message(format!("{} {:?}", r.id, r.status));
            let label = if r.variant == "default" {
                r.id.clone()
            } else {
                format!("{} [{}]", r.id, r.variant)
            };
            let mut line = format!(
                "{:<8} {:<40} {:>8.2} s",
                format!("{:?}", r.status).to_lowercase(),
                label,
                r.wall_s
            );
            // An error is the input's or the run's, and says which: print it where it shows.
            if let (Status::Error, Some(message)) = (r.status, &r.message) {
                line += &format!("\n         {message}");
            }
            if bar.is_hidden() {
                eprintln!("{line}");
            } else {
                bar.println(line);
            }
        },
    );
    bar.finish_and_clear();
    results
}

/// The run's summary on the terminal: the counts, every case that did not pass with its
/// message, the wall time, and the known failures.
fn print_summary(results: &RunResults) {
    let passed = results
        .cases
        .iter()
        .filter(|c| c.status == Status::Pass)
        .count();
    println!("{passed} passed, {} failed", results.cases.len() - passed);
    for c in results.cases.iter().filter(|c| c.status != Status::Pass) {
        println!(
            "  {} {:?}: {}",
            c.id,
            c.status,
            c.message.as_deref().unwrap_or("")
        );
    }
    println!("wall time {:.1} s", results.wall_s);
    for c in results.cases.iter().filter(|c| c.status == Status::Fail) {
        if let Some(why) = &c.known_failure {
            println!("  known failure {}: {why}", c.id);
        }
    }
}
