//! `impact-vv rank-case` (hidden): one rank of an `mpirun` run of a case's variant.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Runs `variant` of the case file `case` as one rank and writes the result to `result`.
pub fn exec(
    case: &Path,
    variant: &str,
    result: &Path,
    out: Option<PathBuf>,
    time_limit: f64,
) -> ExitCode {
    let Some((_env, world)) = super::mpi_ranks() else {
        eprintln!(
            "error: `rank-case` is one rank of an `mpirun` run of a build with the \
             `mpi` feature; run the case with `impact-vv run` instead"
        );
        return ExitCode::from(2);
    };
    match crate::rank_case::rank_case(case, variant, result, out, time_limit, &world) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
