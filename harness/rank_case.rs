//! The hidden `rank-case` command: one rank of a case variant that the harness started under
//! `mpirun` ([`crate::mpirun::run_variant`]). Its own module, above the case kinds and the
//! registry that it reads, so that neither imports it.

use std::path::{Path, PathBuf};

use impact_solver::distributed::Communicator;

use crate::case_file::load_case;
use crate::case_kind::RunOptions;
use crate::mpirun::write_result;
use crate::registry::KINDS;
use crate::results::CaseResult;
use crate::scene_case::SceneCase;

/// Why one rank of a distributed case cannot run or write its result.
#[derive(Debug, thiserror::Error)]
pub enum RankCaseError {
    /// The case file does not load.
    #[error(transparent)]
    Case(#[from] crate::case_file::CatalogueError),
    /// The case has no such variant.
    #[error("{case}: no variant `{variant}`")]
    NoVariant {
        /// The case file.
        case: String,
        /// The variant asked for.
        variant: String,
    },
    /// Only scene cases run on ranks.
    #[error("{case}: a `{kind}` case does not run on ranks; only scene cases do")]
    NotAScene {
        /// The case file.
        case: String,
        /// The case's kind.
        kind: &'static str,
    },
    /// The result cannot be written.
    #[error("{path}: {message}")]
    Write {
        /// The result file.
        path: String,
        /// The reason.
        message: String,
    },
}

/// The `rank-case` command: runs `variant` of the case file `case_path` as this rank of `world`
/// and, on rank 0, writes the judged result to `result_file`. `out` is the harness run's folder
/// (`None`: output kept in memory).
pub fn rank_case(
    case_path: &Path,
    variant: &str,
    result_file: &Path,
    out: Option<PathBuf>,
    time_limit_s: f64,
    world: &dyn Communicator,
) -> Result<(), RankCaseError> {
    let case = load_case(case_path, &KINDS)?;
    let chosen = case
        .spec
        .variants
        .iter()
        .find(|v| v.name == variant)
        .ok_or_else(|| RankCaseError::NoVariant {
            case: case_path.display().to_string(),
            variant: variant.into(),
        })?;
    let scene = case
        .kind
        .as_any()
        .downcast_ref::<SceneCase>()
        .ok_or_else(|| RankCaseError::NotAScene {
            case: case_path.display().to_string(),
            kind: case.kind.name(),
        })?;
    let options = RunOptions {
        output_dir: out,
        time_limit_s,
        parallel: false,
        stop: None,
        verbose: false,
    };
    let result = scene.run_as_rank(&case, Some(chosen), &options, world);
    let memory = crate::memory::peak_resident_mib_per_rank(Some(world));
    if world.rank() == 0 {
        let result = CaseResult {
            known_failure: case.spec.known_failure.clone(),
            peak_memory_mib: Some(memory),
            ..result
        };
        write_result(result_file, &result).map_err(|e| RankCaseError::Write {
            path: result_file.display().to_string(),
            message: e.to_string(),
        })?;
    }
    Ok(())
}
