//! `impact-vv`: the command line of the concrete-impact V&V harness.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use clap::{Parser, Subcommand};
use impact_solver::distributed::Communicator;
use impact_vv::case_file::{load_case, load_catalogue, matches};
use impact_vv::case_kind::{LoadedCase, RunOptions};
use impact_vv::catalogue::Tier;
use impact_vv::registry::{KINDS, SECTIONS};
use impact_vv::results::{RunResults, Status};
use impact_vv::run_log::{self, RunLog};
use impact_vv::runner::run_cases;
use impact_vv::{metadata, report};

#[derive(Parser)]
#[command(
    name = "impact-vv",
    version,
    about = "Verification and validation of the concrete-impact solver"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the cases of the catalogue.
    List {
        /// Case ids, globs (`patch/*`), tags (`tag:wave`) or case files.
        patterns: Vec<String>,
        #[arg(long, value_parser = parse_tier)]
        tier: Option<Tier>,
        #[arg(long, default_value = "cases")]
        catalogue: PathBuf,
    },
    /// Run cases and write a report to `<reports>/<run-id>/index.html`.
    Run {
        /// Case ids, globs (`patch/*`), tags (`tag:wave`) or case files; empty: the whole tier.
        /// Ids, globs and tags select within `--tier` when it is given; a case file runs
        /// whatever its tier.
        patterns: Vec<String>,
        /// quick, nightly (quick + nightly), stress or long; without patterns, quick.
        #[arg(long, value_parser = parse_tier)]
        tier: Option<Tier>,
        /// Rerun the cases that failed in the last run.
        #[arg(long)]
        failed: bool,
        #[arg(long, default_value = "cases")]
        catalogue: PathBuf,
        #[arg(long, default_value = "reports")]
        reports: PathBuf,
        /// Wall-time limit per solver run (s), unless a case sets its own.
        #[arg(long, default_value_t = 900.0, value_parser = parse_time_limit)]
        time_limit: f64,
        /// Run cases one after the other.
        #[arg(long)]
        serial: bool,
        /// Print each case's log lines (each remeshing's summary, ...) on the terminal too; they
        /// are always in the case's log file, `<run>/cases/<case>/log.txt`.
        #[arg(long)]
        verbose: bool,
    },
    /// Rebuild a run's report from its `results.json`.
    Report {
        /// The run folder (`reports/<run-id>`).
        run: PathBuf,
        #[arg(long, default_value = "reports")]
        reports: PathBuf,
    },
    /// Compare the contact solvers on contact-problem files (contact-problem/1 JSON): error
    /// reached, iterations and median time per problem, solver and tolerance; performance
    /// profiles and a work-precision diagram. Writes results.json, results.csv, README.md, SVGs.
    ContactCompare {
        /// Problem files, or folders whose *.json files are all read (sorted by name).
        inputs: Vec<PathBuf>,
        #[arg(long, default_value = "reports/contact-compare")]
        out: PathBuf,
        /// Tolerances on the natural-map error ||F||/||q||, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "1e-4,1e-6,1e-8")]
        tolerances: Vec<f64>,
        /// Time limit of one solve (s).
        #[arg(long, default_value_t = impact_vv::contact_compare::DEFAULT_TIME_LIMIT_S)]
        time_limit: f64,
        /// Solvers, comma-separated (default: all of gauss-seidel/thesis, gauss-seidel/exact,
        /// conic/relaxed, conic/coulomb).
        #[arg(long, value_delimiter = ',')]
        solvers: Vec<String>,
    },
    /// Calibrate the microplane parameters of the thesis concrete against the targets of
    /// MICROPLANE.md (single-element tests driven by a Nelder-Mead optimiser) and write them, with
    /// the value every target reaches, to a material file. Exit status 1 if a target is missed.
    Calibrate {
        #[arg(long, default_value = "cases/materials/thesis-concrete.yaml")]
        out: PathBuf,
        /// Optimiser evaluations per stage.
        #[arg(long, default_value_t = 120)]
        evaluations: usize,
        /// Another concrete: a YAML file with `header`, `density`, `youngs_modulus`,
        /// `poisson_ratio` and `targets` (the fields of the record's `targets`), e.g.
        /// cases/materials/gregoire-2013-targets.yaml.
        #[arg(long)]
        targets: Option<PathBuf>,
    },
    /// Recompute the independent answers of the cross-check cases (`crosscheck` tag) with
    /// scikit-fem and ipctk and write them to references/crosscheck/cache/. Needs a build with
    /// `--features python` and the packages of references/crosscheck/requirements.txt.
    CrosscheckRefresh {
        /// Case ids, globs or tags; empty: every case with a `crosscheck`.
        patterns: Vec<String>,
        #[arg(long, default_value = "cases")]
        catalogue: PathBuf,
    },
    /// Run one scene file (or the `scene` of a catalogue case file) and write its history (CSV)
    /// and fields (VTU + PVD for ParaView).
    Scene {
        path: PathBuf,
        #[arg(long, default_value = "reports/scene")]
        out: PathBuf,
        /// Skip the VTU field frames.
        #[arg(long)]
        no_fields: bool,
        /// Write a checkpoint every SECONDS of wall time into OUT/<scene>-checkpoints (the
        /// last two kept); overrides the scene's `analysis.explicit.checkpoint`.
        #[arg(long, value_name = "SECONDS")]
        checkpoint_every: Option<f64>,
        /// Write a checkpoint every N steps.
        #[arg(long, value_name = "N")]
        checkpoint_every_steps: Option<usize>,
        /// Go on from the newest good checkpoint in OUT (from the start when there is none):
        /// the result is bitwise that of the run never stopped.
        #[arg(long)]
        resume: bool,
    },
    /// One rank of a case variant with `ranks: N`, started by the harness under `mpirun`
    /// (`impact_vv::rank_case`); rank 0 writes the judged result to `--result`.
    #[command(name = impact_vv::mpirun::RANK_COMMAND, hide = true)]
    RankCase {
        case: PathBuf,
        #[arg(long)]
        variant: String,
        #[arg(long)]
        result: PathBuf,
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long, default_value_t = 900.0, value_parser = parse_time_limit)]
        time_limit: f64,
    },
}

/// A wall-time limit in seconds: positive and finite.
fn parse_time_limit(s: &str) -> Result<f64, String> {
    let limit: f64 = s.parse().map_err(|e| format!("{e}"))?;
    impact_vv::case_file::check_time_limit(limit).map(|()| limit)
}

fn parse_tier(s: &str) -> Result<Tier, String> {
    match s {
        "quick" => Ok(Tier::Quick),
        "nightly" => Ok(Tier::Nightly),
        "stress" => Ok(Tier::Stress),
        "long" => Ok(Tier::Long),
        other => Err(format!(
            "unknown tier `{other}`: use quick, nightly, stress or long"
        )),
    }
}

/// Loads the catalogue or prints every error (file and line) and gives exit status 2. A missing
/// folder is an error only when it is `needed`: a run of case files named on the command line
/// needs none.
fn catalogue(dir: &Path, needed: bool) -> Result<Vec<LoadedCase>, ExitCode> {
    if needed && !dir.is_dir() {
        eprintln!(
            "error: {}: no such catalogue folder; give the folder of the case files with \
             `--catalogue` (default `cases`, run from the repository root)",
            dir.display()
        );
        return Err(ExitCode::from(2));
    }
    load_catalogue(dir, &KINDS).map_err(|errors| {
        for e in &errors {
            eprintln!("error: {e}");
        }
        eprintln!("{} catalogue error(s); nothing was run", errors.len());
        ExitCode::from(2)
    })
}

/// The cases a command names: every case of `tier` without patterns; with patterns, the cases
/// an id, glob or tag selects within `tier` (when given), and every case file named, whatever
/// its tier.
fn select(cases: &[LoadedCase], patterns: &[String], tier: Option<Tier>) -> Vec<LoadedCase> {
    let canonical = |p: &Path| std::fs::canonicalize(p).ok();
    cases
        .iter()
        .filter(|c| {
            let in_tier = tier.is_none_or(|t| t.includes(c.spec.tier));
            if patterns.is_empty() {
                return in_tier;
            }
            patterns.iter().any(|p| {
                let names_file = Path::new(p).is_file()
                    && canonical(Path::new(p)).is_some_and(|f| Some(f) == canonical(&c.path));
                names_file || (in_tier && matches(c, p))
            })
        })
        .cloned()
        .collect()
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

/// Writes `<run>/results.json` from `run.json` and `cases.jsonl` of a run that was killed before
/// it wrote it, and appends its cases to the history.
fn rebuild_results(run: &Path, reports: &Path) -> Result<(), String> {
    let results = run_log::rebuild(run)?;
    let text = serde_json::to_string_pretty(&results).map_err(|e| e.to_string())?;
    std::fs::write(run.join("results.json"), text)
        .map_err(|e| format!("cannot write {}: {e}", run.join("results.json").display()))?;
    let history = reports.join("history.jsonl");
    report::append_history(&history, &results.history_records())
        .map_err(|e| format!("cannot append to {}: {e}", history.display()))?;
    eprintln!(
        "rebuilt {} from {} ({} finished cases)",
        run.join("results.json").display(),
        run.join(run_log::CASES_FILE).display(),
        results.cases.len()
    );
    Ok(())
}

/// A flag that the first SIGINT or SIGTERM sets (the run stops at the end of its step and writes
/// what it has); a second signal exits at once with status 130.
fn stop_on_signal() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = flag.clone();
    let installed = ctrlc::set_handler(move || {
        if handler_flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: stopping at the end of the current step (again to quit at once)");
    });
    if let Err(e) = installed {
        eprintln!("warning: no signal handler ({e}): an interrupted run will not write its output");
    }
    flag
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::List {
            patterns,
            tier,
            catalogue: dir,
        } => {
            let cases = match catalogue(&dir, true) {
                Ok(c) => c,
                Err(code) => return code,
            };
            for c in select(&cases, &patterns, tier) {
                println!(
                    "{:<40} {:<8} {:<30} {}",
                    c.spec.id,
                    c.spec.tier.name(),
                    c.spec.tags.join(","),
                    c.spec.description
                );
            }
            ExitCode::SUCCESS
        }
        Command::Run {
            patterns,
            tier,
            failed,
            catalogue: dir,
            reports,
            time_limit,
            serial,
            verbose,
        } => {
            let names_files = patterns.iter().any(|p| Path::new(p).is_file());
            let cases = match catalogue(&dir, !names_files) {
                Ok(c) => c,
                Err(code) => return code,
            };
            let patterns = if failed {
                match std::fs::read_to_string(reports.join("last-failed.txt")) {
                    Ok(s) => s.lines().map(String::from).collect(),
                    Err(_) => {
                        eprintln!(
                            "no record of failed cases ({}): run first",
                            reports.join("last-failed.txt").display()
                        );
                        return ExitCode::from(2);
                    }
                }
            } else {
                patterns
            };
            let tier = if patterns.is_empty() {
                tier.or(Some(Tier::Quick))
            } else {
                tier
            };
            let mut selected = select(&cases, &patterns, tier);
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
            run(selected, tier, &reports, time_limit, !serial, verbose)
        }
        Command::Calibrate {
            out,
            evaluations,
            targets,
        } => match impact_vv::calibrate::run(&out, evaluations, targets.as_deref()) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => {
                eprintln!(
                    "some targets are missed: see the table above and {}",
                    out.display()
                );
                ExitCode::from(1)
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Command::Report { run, reports } => {
            if !run.join("results.json").exists() && run.join(run_log::CASES_FILE).exists() {
                // A run that was killed outright: its finished cases are in cases.jsonl.
                if let Err(e) = rebuild_results(&run, &reports) {
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
            match report::write_report(&run, &results, &history, SECTIONS) {
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
        Command::ContactCompare {
            inputs,
            out,
            tolerances,
            time_limit,
            solvers,
        } => ExitCode::from(impact_vv::contact_compare::command::run(
            &impact_vv::contact_compare::command::CompareArgs {
                inputs,
                out,
                tolerances,
                time_limit_s: time_limit,
                solvers,
                stop: Some(stop_on_signal()),
            },
        )),
        Command::CrosscheckRefresh {
            patterns,
            catalogue: dir,
        } => {
            let cases = match catalogue(&dir, true) {
                Ok(c) => c,
                Err(code) => return code,
            };
            let chosen: Vec<&LoadedCase> = cases
                .iter()
                .filter(|c| patterns.is_empty() || patterns.iter().any(|p| matches(c, p)))
                .collect();
            let mut refreshed = 0;
            let mut code = ExitCode::SUCCESS;
            for case in chosen {
                let Some(outcome) = case.kind.refresh(case) else {
                    continue;
                };
                refreshed += 1;
                match outcome {
                    Ok(line) => println!(
                        "{}: {}",
                        case.spec.id,
                        line.replace("fresh answer", "cached answer")
                    ),
                    Err(e) => {
                        eprintln!("error: {}: {e}", case.spec.id);
                        code = ExitCode::from(2);
                    }
                }
            }
            if refreshed == 0 {
                eprintln!(
                    "error: no case with a cache of independent answers matches {patterns:?}"
                );
                return ExitCode::from(2);
            }
            code
        }
        Command::RankCase {
            case,
            variant,
            result,
            out,
            time_limit,
        } => {
            let Some((_env, world)) = mpi_ranks() else {
                eprintln!(
                    "error: `rank-case` is one rank of an `mpirun` run of a build with the \
                     `mpi` feature; run the case with `impact-vv run` instead"
                );
                return ExitCode::from(2);
            };
            match impact_vv::rank_case::rank_case(&case, &variant, &result, out, time_limit, &world)
            {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::Scene {
            path,
            out,
            no_fields,
            checkpoint_every,
            checkpoint_every_steps,
            resume,
        } => {
            let ranks = mpi_ranks();
            let comm = ranks.as_ref().map(|(_, world)| world as &dyn Communicator);
            let root = comm.is_none_or(|c| c.rank() == 0);
            let restart = impact_vv::scene_restart::RestartRequest {
                every_s: checkpoint_every,
                every_steps: checkpoint_every_steps,
                resume,
            };
            match impact_vv::scene_run::run_scene_file_with(
                &path,
                &out,
                !no_fields,
                Some(stop_on_signal()),
                comm,
                &restart,
            ) {
                Ok(report) => {
                    if root {
                        println!("{report}");
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    if root {
                        eprintln!("error: {e}");
                    }
                    ExitCode::from(e.exit_code())
                }
            }
        }
    }
}

/// The MPI environment and world when this process was started by `mpirun` (Open MPI sets
/// `OMPI_COMM_WORLD_SIZE`) in a build with the `mpi` feature; `None` otherwise, and the scene runs
/// on one process.
#[cfg(feature = "mpi")]
fn mpi_ranks() -> Option<(impl Sized, impact_solver::distributed::MpiWorld)> {
    std::env::var_os("OMPI_COMM_WORLD_SIZE")?;
    impact_solver::distributed::MpiWorld::initialize()
}

/// Without the `mpi` feature a scene always runs on one process.
#[cfg(not(feature = "mpi"))]
fn mpi_ranks() -> Option<((), impact_solver::distributed::ThreadGroup)> {
    None
}

/// The tier a run reports: the one given, or `selected` for cases named by patterns alone.
fn tier_label(tier: Option<Tier>) -> &'static str {
    tier.map_or("selected", Tier::name)
}

/// Creates the run's folder `<reports>/<stamp>` and returns its id and path; when a run of the
/// same second has it, `<stamp>-2`, `<stamp>-3`, ...: two runs into one reports folder never
/// share a folder, whichever starts first.
fn claim_run_dir(reports: &Path, stamp: &str) -> Result<(String, PathBuf), String> {
    std::fs::create_dir_all(reports).map_err(|e| {
        format!(
            "cannot create the reports folder {}: {e}",
            reports.display()
        )
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
            Err(e) => return Err(format!("cannot create {}: {e}", dir.display())),
        }
    }
    Err(format!(
        "{}: a thousand runs already started in second {stamp}",
        reports.display()
    ))
}

fn run(
    cases: Vec<LoadedCase>,
    tier: Option<Tier>,
    reports: &Path,
    time_limit: f64,
    parallel: bool,
    verbose: bool,
) -> ExitCode {
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
    let bar = indicatif::ProgressBar::new(cases.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix:>10} [{bar:40}] {pos}/{len} cases, {elapsed_precise}, left {eta}  {msg}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.set_prefix("running");
    if verbose {
        // The cases' log lines come from every worker thread at any time: without a bar to
        // redraw around them, they and the case lines stay whole.
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let stop = stop_on_signal();
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
    let log = match RunLog::start(&dir, &facts) {
        Ok(log) => Some(log),
        Err(e) => {
            eprintln!(
                "warning: cannot start {}: {e}; a killed run would lose its results",
                dir.join(impact_vv::run_log::CASES_FILE).display()
            );
            None
        }
    };
    let results = run_cases(
        &cases,
        &RunOptions {
            output_dir: Some(dir.clone()),
            time_limit_s: time_limit,
            parallel,
            stop: Some(stop.clone()),
            verbose,
        },
        &|r| {
            if let Some(log) = &log {
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
    let results = RunResults {
        cases: results,
        wall_s: started.elapsed().as_secs_f64(),
        ..facts
    };
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
    match report::write_report(&dir, &results, &history, SECTIONS) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => {
            eprintln!("error: cannot write the report: {e}");
            return ExitCode::from(2);
        }
    }
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
    if stop.load(Ordering::Relaxed) {
        // The finished cases are judged, reported and in the history; the others are marked
        // interrupted. A status of its own, whatever the verdicts.
        eprintln!("interrupted: the report holds the cases that finished");
        return ExitCode::from(130);
    }
    ExitCode::from(results.exit_code())
}
