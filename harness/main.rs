//! `impact-vv`: the command line of the concrete-impact V&V harness.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
    /// Run one scene file and write its history (CSV) and fields (VTU + PVD for ParaView).
    Scene {
        /// The scene, a YAML file (see cases/examples/).
        path: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "reports/scene")]
        out: PathBuf,
        /// Skip the VTU field frames.
        #[arg(long)]
        no_fields: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Scene {
            path,
            out,
            no_fields,
        } => match impact_vv::scene_run::run_scene_file(&path, &out, !no_fields) {
            Ok(report) => {
                println!("{report}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(e.exit_code())
            }
        },
    }
}
