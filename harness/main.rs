//! `impact-vv`: the command line of the concrete-impact V&V harness.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use impact_solver::distributed::Communicator;
use impact_vv::catalogue::Tier;
use impact_vv::commands::{self, mpi_ranks, stop_on_signal};

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
        /// Finish the run in this folder (`reports/<run-id>`) that was stopped or killed: run
        /// only its cases that did not finish, then write the report of the whole run.
        #[arg(long, value_name = "RUN", conflicts_with_all = ["patterns", "tier", "failed"])]
        resume: Option<PathBuf>,
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
/// Why a command-line value is refused (clap prints the message after the option).
#[derive(Debug, thiserror::Error)]
enum ArgError {
    /// Not a number.
    #[error("{0}")]
    Number(#[from] std::num::ParseFloatError),
    /// Not a positive, finite number of seconds.
    #[error("{0}")]
    TimeLimit(#[from] impact_vv::case_file::RangeError),
    /// A tier nobody knows.
    #[error("unknown tier `{0}`: use quick, nightly, stress or long")]
    Tier(String),
}

fn parse_time_limit(s: &str) -> Result<f64, ArgError> {
    let limit: f64 = s.parse()?;
    impact_vv::case_file::check_time_limit(limit)
        .map(|()| limit)
        .map_err(ArgError::from)
}

fn parse_tier(s: &str) -> Result<Tier, ArgError> {
    match s {
        "quick" => Ok(Tier::Quick),
        "nightly" => Ok(Tier::Nightly),
        "stress" => Ok(Tier::Stress),
        "long" => Ok(Tier::Long),
        other => Err(ArgError::Tier(other.into())),
    }
}

fn main() -> ExitCode {
    impact_vv::memory::keep_large_blocks_mapped();
    let cli = Cli::parse();
    match cli.command {
        Command::List {
            patterns,
            tier,
            catalogue,
        } => commands::list::exec(&patterns, tier, &catalogue),
        Command::Run {
            patterns,
            tier,
            failed,
            catalogue,
            reports,
            time_limit,
            serial,
            verbose,
            resume,
        } => {
            let args = commands::run::RunArgs {
                patterns,
                tier,
                failed,
                catalogue,
                reports,
                time_limit,
                serial,
                verbose,
                resume,
            };
            match &args.resume {
                Some(dir) => commands::resume::exec(dir, &args),
                None => commands::run::exec(&args),
            }
        }
        Command::Calibrate {
            out,
            evaluations,
            targets,
        } => commands::calibrate::exec(&out, evaluations, targets.as_deref()),
        Command::Report { run, reports } => commands::report::exec(&run, &reports),
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
            catalogue,
        } => commands::crosscheck_refresh::exec(&patterns, &catalogue),
        Command::RankCase {
            case,
            variant,
            result,
            out,
            time_limit,
        } => commands::rank_case::exec(&case, &variant, &result, out, time_limit),
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
                    // A rank's own checkpoint refusal is its message alone (rank 0 names the
                    // rank); another rank count is every rank's, which rank 0 prints.
                    let own_checkpoint = matches!(
                        &e,
                        impact_vv::scene_run::SceneRunError::Checkpoint(c)
                            if !matches!(
                                c,
                                impact_solver::restart::CheckpointError::OtherRanks { .. }
                                    | impact_solver::restart::CheckpointError::RankCount { .. }
                            )
                    );
                    if root {
                        eprintln!("error: {e}");
                    } else if own_checkpoint {
                        let rank = comm.map_or(0, |c| c.rank());
                        eprintln!("rank {rank}: error: {e}");
                    }
                    ExitCode::from(e.exit_code())
                }
            }
        }
    }
}
