//! A run's results as they come, so that a run killed outright loses nothing that finished:
//! `run.json` (the run's facts, no cases) at the start, and one JSON line per finished case in
//! `cases.jsonl`, appended at once. `results.json` is the same run written whole at the end;
//! where it is missing, `impact-vv report` rebuilds it (and the report, and the history lines)
//! from these two files with [`rebuild`].

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::results::{CaseResult, RunResults};

/// Why a killed run's results cannot be rebuilt or written: each message names the file.
#[derive(Debug, thiserror::Error)]
pub enum RebuildError {
    /// A file of the run cannot be read.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// A file of the run is not valid JSON of its type.
    #[error("{path}: {message}")]
    Parse {
        /// The file, with the line for `cases.jsonl`.
        path: String,
        /// The JSON reader's error.
        message: String,
    },
    /// A file cannot be written or appended to.
    #[error("cannot {action} {path}: {message}")]
    Write {
        /// `write` or `append to`.
        action: &'static str,
        /// The file.
        path: String,
        /// The reason.
        message: String,
    },
}

/// The run's facts, without cases.
pub const RUN_FILE: &str = "run.json";
/// One finished case per line.
pub const CASES_FILE: &str = "cases.jsonl";

/// Appends finished cases to `<run>/cases.jsonl`, one whole line per write, from any thread.
pub struct RunLog {
    path: PathBuf,
    file: Mutex<std::fs::File>,
}

impl RunLog {
    /// Writes `<dir>/run.json` from `run` (its cases are left out) and starts an empty
    /// `<dir>/cases.jsonl`.
    pub fn start(dir: &Path, run: &RunResults) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let facts = RunResults {
            cases: Vec::new(),
            ..run.clone()
        };
        std::fs::write(
            dir.join(RUN_FILE),
            serde_json::to_string_pretty(&facts).map_err(std::io::Error::other)?,
        )?;
        let path = dir.join(CASES_FILE);
        let file = std::fs::File::create(&path)?;
        Ok(Self {
            path,
            file: Mutex::new(file),
        })
    }

    /// Rewrites `<dir>/cases.jsonl` with `kept` (the finished cases of a run being resumed)
    /// and goes on appending to it; `run.json` stays as the run wrote it.
    pub fn restart(dir: &Path, kept: &[CaseResult]) -> std::io::Result<Self> {
        let path = dir.join(CASES_FILE);
        let mut text = String::new();
        for case in kept {
            text += &serde_json::to_string(case).map_err(std::io::Error::other)?;
            text.push('\n');
        }
        std::fs::write(&path, text)?;
        let file = std::fs::OpenOptions::new().append(true).open(&path)?;
        Ok(Self {
            path,
            file: Mutex::new(file),
        })
    }

    /// Appends `case` as one line (a single write of the whole line).
    pub fn append(&self, case: &CaseResult) -> std::io::Result<()> {
        let mut line = serde_json::to_string(case).map_err(std::io::Error::other)?;
        line.push('\n');
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        file.write_all(line.as_bytes())
    }

    /// The log file, `<run>/cases.jsonl`.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// The run in `dir` from `run.json` and `cases.jsonl`: the cases in the order they finished, a
/// last line cut by the kill skipped (with a warning on standard error). The wall time of the
/// run is unknown (NaN).
pub fn rebuild(dir: &Path) -> Result<RunResults, RebuildError> {
    let read = |name: &str| {
        std::fs::read_to_string(dir.join(name)).map_err(|e| RebuildError::Read {
            path: dir.join(name).display().to_string(),
            message: e.to_string(),
        })
    };
    let mut run: RunResults =
        serde_json::from_str(&read(RUN_FILE)?).map_err(|e| RebuildError::Parse {
            path: dir.join(RUN_FILE).display().to_string(),
            message: e.to_string(),
        })?;
    let text = read(CASES_FILE)?;
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    for (i, line) in lines.iter().enumerate() {
        match serde_json::from_str::<CaseResult>(line) {
            Ok(case) => run.cases.push(case),
            Err(e) if i + 1 == lines.len() => eprintln!(
                "warning: {} line {}: {e} (cut by the end of the run), skipped",
                dir.join(CASES_FILE).display(),
                i + 1
            ),
            Err(e) => {
                return Err(RebuildError::Parse {
                    path: format!("{} line {}", dir.join(CASES_FILE).display(), i + 1),
                    message: e.to_string(),
                })
            }
        }
    }
    run.wall_s = f64::NAN;
    Ok(run)
}
