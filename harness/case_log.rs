//! A case's own log: the lines its runs print on the way (each remeshing's summary, a plot that
//! could not be drawn), kept out of the catalogue run's terminal, where one line per case and the
//! progress bar stand.
//!
//! The lines go to `<run>/cases/<case>/log.txt` (`log-<variant>.txt` for a variant: variants of
//! a case share its folder and may run at the same time), created at the first line, so a case
//! that logs nothing has no file; [`CaseLog::relative_path`] is what `CaseResult::log_file`
//! records for the report's link. With `RunOptions::verbose` every line is also printed to
//! standard error, prefixed with the case's label. One `CaseLog` per case run, handed to the
//! solver as its log sink (`ExecuteOptions::log`): cases run side by side on the catalogue's
//! threads, so nothing here is global.

use std::fs::File;
use std::io::{LineWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::case_kind::RunOptions;
use crate::results::{case_dir, file_safe};

/// The log file of one case run, and whether its lines are echoed to the terminal.
#[derive(Debug)]
pub struct CaseLog {
    /// The run folder and the file's path relative to it; `None` without an output folder.
    file: Option<(PathBuf, String)>,
    /// Opened at the first line; `Err` once opening failed (the lines then go to stderr).
    writer: Mutex<Option<Result<LineWriter<File>, ()>>>,
    /// Print every line to stderr as well (`impact-vv run --verbose`).
    echo: bool,
    /// `id` or `id [variant]`: the prefix of an echoed line.
    label: String,
}

impl CaseLog {
    /// The log of case `id` under `variant` (`default`: the case's own analysis) in the run
    /// `options` describe. Nothing is created until a line is written.
    pub fn new(options: &RunOptions, id: &str, variant: &str) -> Self {
        let name = if variant == "default" {
            "log.txt".to_string()
        } else {
            format!("log-{}.txt", file_safe(variant))
        };
        let file = options.output_dir.as_ref().map(|run| {
            let folder = case_dir(Path::new(""), id);
            let relative = folder.join(name).to_string_lossy().replace('\\', "/");
            (run.clone(), relative)
        });
        let label = if variant == "default" {
            id.to_string()
        } else {
            format!("{id} [{variant}]")
        };
        Self {
            file,
            writer: Mutex::new(None),
            echo: options.verbose,
            label,
        }
    }

    /// A log that writes nothing anywhere (a rank other than 0 of a distributed case run).
    pub fn silent(id: &str, variant: &str) -> Self {
        Self {
            file: None,
            writer: Mutex::new(None),
            echo: false,
            label: format!("{id} [{variant}]"),
        }
    }

    /// Writes one line (without its newline) to the file, and to stderr when verbose. A file
    /// that cannot be created or written is reported once on stderr, and the lines follow it
    /// there rather than being lost.
    pub fn line(&self, line: &str) {
        if self.echo {
            eprintln!("  {}: {line}", self.label);
        }
        let Some((run, relative)) = &self.file else {
            return;
        };
        let mut writer = self.writer.lock().unwrap_or_else(|e| e.into_inner());
        let opened = writer.get_or_insert_with(|| {
            let path = run.join(relative);
            let created = path
                .parent()
                .map_or(Ok(()), std::fs::create_dir_all)
                .and_then(|()| File::create(&path));
            created.map(LineWriter::new).map_err(|e| {
                eprintln!(
                    "warning: cannot create {}: {e}; {}'s log lines follow here",
                    path.display(),
                    self.label
                );
            })
        });
        let written = match opened {
            Ok(w) => writeln!(w, "{line}").map_err(|e| {
                eprintln!(
                    "warning: cannot write to {}: {e}; {}'s log lines follow here",
                    run.join(relative).display(),
                    self.label
                );
            }),
            Err(()) => Err(()),
        };
        if written.is_err() {
            *opened = Err(());
            if !self.echo {
                eprintln!("  {}: {line}", self.label);
            }
        }
    }

    /// The log file's path relative to the run folder (`cases/<case>/log.txt`), with `/`
    /// separators, once a line has been written to it; `None` when the case logged nothing,
    /// runs without an output folder, or its file could not be written.
    pub fn relative_path(&self) -> Option<String> {
        let writer = self.writer.lock().unwrap_or_else(|e| e.into_inner());
        match (&*writer, &self.file) {
            (Some(Ok(_)), Some((_, relative))) => Some(relative.clone()),
            _ => None,
        }
    }

    /// The sink the solver writes to (`ExecuteOptions::log`).
    pub fn sink(&self) -> impl Fn(&str) + Sync + '_ {
        move |line: &str| self.line(line)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(dir: Option<&Path>) -> RunOptions {
        RunOptions {
            output_dir: dir.map(Path::to_path_buf),
            time_limit_s: 1.0,
            parallel: false,
            stop: None,
            verbose: false,
        }
    }

    #[test]
    fn lines_go_to_the_case_folder_created_at_the_first_line() {
        let run = tempfile::tempdir().expect("temp dir");
        let log = CaseLog::new(&options(Some(run.path())), "contact/patch", "default");
        assert_eq!(log.relative_path(), None);
        assert!(!run.path().join("cases").exists(), "created before a line");
        log.line("first");
        (log.sink())("second");
        let relative = log.relative_path().expect("a line was written");
        assert_eq!(relative, "cases/contact__patch/log.txt");
        let text = std::fs::read_to_string(run.path().join(&relative)).expect("log file");
        assert_eq!(text, "first\nsecond\n");
    }

    #[test]
    fn variants_have_files_of_their_own() {
        let run = tempfile::tempdir().expect("temp dir");
        let a = CaseLog::new(&options(Some(run.path())), "c", "gauss-seidel/thesis");
        let b = CaseLog::new(&options(Some(run.path())), "c", "conic/coulomb");
        a.line("a");
        b.line("b");
        assert_eq!(
            a.relative_path().as_deref(),
            Some("cases/c/log-gauss-seidel_thesis.txt")
        );
        assert_eq!(
            b.relative_path().as_deref(),
            Some("cases/c/log-conic_coulomb.txt")
        );
    }

    #[test]
    fn without_an_output_folder_nothing_is_written() {
        let log = CaseLog::new(&options(None), "c", "default");
        log.line("dropped");
        assert_eq!(log.relative_path(), None);
    }
}
