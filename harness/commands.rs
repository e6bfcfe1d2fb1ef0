//! The `impact-vv` commands, one file each: what a command does once its arguments are parsed
//! (`main.rs` holds the command line itself). Each `exec` returns the process's exit status.

pub mod calibrate;
pub mod crosscheck_refresh;
pub mod list;
pub mod rank_case;
pub mod report;
pub mod resume;
pub mod run;

use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::case_file::{load_catalogue, matches};
use crate::case_kind::LoadedCase;
use crate::catalogue::Tier;
use crate::registry::KINDS;

/// Loads the catalogue or prints every error (file and line) and gives exit status 2. A missing
/// folder is an error only when it is `needed`: a run of case files named on the command line
/// needs none.
pub fn catalogue(dir: &Path, needed: bool) -> Result<Vec<LoadedCase>, ExitCode> {
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
pub fn select(cases: &[LoadedCase], patterns: &[String], tier: Option<Tier>) -> Vec<LoadedCase> {
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

/// A flag that the first SIGINT or SIGTERM sets (the run stops at the end of its step and writes
/// what it has); a second signal exits at once with status 130.
pub fn stop_on_signal() -> Arc<AtomicBool> {
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

/// The MPI environment and world when this process was started by `mpirun` (Open MPI sets
/// `OMPI_COMM_WORLD_SIZE`) in a build with the `mpi` feature; `None` otherwise, and the scene runs
/// on one process.
#[cfg(feature = "mpi")]
pub fn mpi_ranks() -> Option<(impl Sized, impact_solver::distributed::MpiWorld)> {
    std::env::var_os("OMPI_COMM_WORLD_SIZE")?;
    impact_solver::distributed::MpiWorld::initialize()
}

/// Without the `mpi` feature a scene always runs on one process.
#[cfg(not(feature = "mpi"))]
pub fn mpi_ranks() -> Option<((), impact_solver::distributed::ThreadGroup)> {
    None
}
