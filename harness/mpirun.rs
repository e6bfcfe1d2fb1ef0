//! A variant with `ranks: N` run under `mpirun` (issue 22), in a build with the `mpi` feature:
//! the harness starts `mpirun -np N` on its own executable's hidden `rank-case` command, whose N
//! processes run the case as the ranks of one distributed run
//! ([`crate::scene_case::SceneCase::run_as_rank`]); rank 0 writes the judged result as JSON, and
//! the harness reads it back as the variant's result. So the report sets the same case on one
//! process and on N MPI ranks side by side, each with its own wall time.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::case_kind::{unfinished_result, LoadedCase, RunOptions};
use crate::catalogue::Variant;
use crate::results::{case_dir, CaseResult};

/// The hidden command that runs one case variant as one `mpirun` rank.
pub const RANK_COMMAND: &str = "rank-case";

/// Runs `variant` of `case` as `ranks` MPI ranks, one thread each, and returns rank 0's result;
/// an `Error` result that says why when `mpirun` cannot be started or a rank fails.
pub fn run_variant(
    case: &LoadedCase,
    variant: &Variant,
    ranks: usize,
    options: &RunOptions,
) -> CaseResult {
    let started = Instant::now();
    let mut failed = unfinished_result(&case.spec, &variant.name);
    let result_file = result_path(case, variant, options);
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            failed.message = Some(format!(
                "cannot find the harness executable for mpirun: {e}"
            ));
            return failed;
        }
    };
    let mut command = Command::new("mpirun");
    command
        .args(["-np", &ranks.to_string()])
        .args(["-x", "RAYON_NUM_THREADS=1"])
        .arg(&exe)
        .arg(RANK_COMMAND)
        .arg(&case.path)
        .args(["--variant", &variant.name])
        .arg("--result")
        .arg(&result_file)
        .args(["--time-limit", &options.time_limit_s.to_string()]);
    if let Some(dir) = &options.output_dir {
        command.arg("--out").arg(dir);
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    if ranks > cores {
        command.arg("--oversubscribe");
    }
    // Open MPI refuses to start as root unless told twice (containers and CI machines run as
    // root); these are its documented switches, read by this mpirun only.
    command
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    let output = match command.output() {
        Ok(o) => o,
        Err(e) => {
            failed.message = Some(format!(
                "`mpirun` could not be started ({e}): install Open MPI (`openmpi-bin`), or run \
                 the default build, which runs `ranks: {ranks}` as threads"
            ));
            return failed;
        }
    };
    // A signal to the harness reaches mpirun and its ranks too (one process group).
    if options
        .stop
        .as_ref()
        .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    {
        let _ = std::fs::remove_file(&result_file);
        failed.status = crate::results::Status::Interrupted;
        failed.message = Some(format!("`mpirun -np {ranks}` was interrupted"));
        failed.wall_s = started.elapsed().as_secs_f64();
        return failed;
    }
    let read = std::fs::read_to_string(&result_file)
        .map_err(|e| e.to_string())
        .and_then(|text| serde_json::from_str::<CaseResult>(&text).map_err(|e| e.to_string()));
    let _ = std::fs::remove_file(&result_file);
    match read {
        Ok(mut result) if output.status.success() => {
            result.wall_s = started.elapsed().as_secs_f64();
            result.message = Some(format!(
                "under `mpirun -np {ranks}`: {}",
                result.message.as_deref().unwrap_or("")
            ));
            result
        }
        outcome => {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let lines: Vec<&str> = stderr.lines().collect();
            let tail = &lines[lines.len().saturating_sub(6)..];
            failed.message = Some(format!(
                "`mpirun -np {ranks}` ended with {} ({}): {}",
                output.status,
                outcome.err().unwrap_or_else(|| "no result".into()),
                tail.join(" | ")
            ));
            failed.wall_s = started.elapsed().as_secs_f64();
            failed
        }
    }
}

/// Where rank 0 leaves the result: beside the case's output, or in the temporary folder when
/// the run keeps its output in memory.
fn result_path(case: &LoadedCase, variant: &Variant, options: &RunOptions) -> PathBuf {
    let name = format!(
        "{}-{}-rank-result.json",
        variant.name.replace('/', "_"),
        std::process::id()
    );
    match &options.output_dir {
        Some(dir) => case_dir(dir, &case.spec.id).join(name),
        None => std::env::temp_dir().join(format!("{}-{name}", case.spec.id.replace('/', "__"))),
    }
}

/// Writes `result` for the harness that started this rank (rank 0 only calls it).
pub fn write_result(path: &Path, result: &CaseResult) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let text = serde_json::to_string(result).map_err(std::io::Error::other)?;
    std::fs::write(path, text)
}
