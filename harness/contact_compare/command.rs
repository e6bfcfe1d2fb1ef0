//! `impact-vv contact-compare`: the comparison of the contact solvers on problem files, with a
//! progress bar, written to a folder.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use super::error::CompareError;
use super::output::write_outputs_noting;
use super::run::compare_until;
use super::tables::solver_summary;
use super::{collect_problem_files, load_problems, solver_entries, CompareSettings};

/// Exit status of a comparison stopped by a signal, as for `scene` and `run` (128 + SIGINT).
pub const INTERRUPTED: u8 = 130;

/// What the command was asked.
#[derive(Debug, Clone)]
pub struct CompareArgs {
    /// Problem files or folders of them.
    pub inputs: Vec<PathBuf>,
    /// Output folder: the comparison JSON, tables, profiles and a README.
    pub out: PathBuf,
    /// The tolerances every solver runs at.
    pub tolerances: Vec<f64>,
    /// Time limit of one solve (s of wall time).
    pub time_limit_s: f64,
    /// Solver names (`contact::registry` spelling); empty: all.
    pub solvers: Vec<String>,
    /// Set by a signal handler: no solve starts once it is set; the solves that finished are
    /// written.
    pub stop: Option<Arc<AtomicBool>>,
}

/// Runs the command; returns the exit status: 0 done, 1 done but some file could not be read,
/// 2 bad input (no problem files, a missing path, an unknown solver, a bad tolerance or time
/// limit, nothing readable, or an output folder that cannot be written), each with a message
/// naming what is wrong on stderr, and [`INTERRUPTED`] when `stop` was set (the finished solves
/// are written).
pub fn run(args: &CompareArgs) -> u8 {
    match run_inner(args) {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            2
        }
    }
}

fn run_inner(args: &CompareArgs) -> Result<u8, CompareError> {
    if let Some(t) = args.tolerances.iter().find(|t| !(**t > 0.0)) {
        return Err(CompareError::Tolerance { tolerance: *t });
    }
    if args.tolerances.is_empty() {
        return Err(CompareError::NoTolerance);
    }
    if !(args.time_limit_s > 0.0 && args.time_limit_s.is_finite()) {
        return Err(CompareError::TimeLimit {
            limit: args.time_limit_s,
        });
    }
    let solvers = solver_entries(&args.solvers)?;
    let files = collect_problem_files(&args.inputs)?;
    let (problems, unreadable) = load_problems(&files);
    for u in &unreadable {
        eprintln!("error: {}", u.message);
    }
    if problems.is_empty() {
        return Err(CompareError::NothingReadable { files: files.len() });
    }
    // Before any solve: a comparison can take minutes, and an unwritable folder found only at
    // the end would lose them.
    check_writable(&args.out)?;
    let settings = CompareSettings {
        tolerances: args.tolerances.clone(),
        time_limit_s: args.time_limit_s,
        ..CompareSettings::default()
    };
    eprintln!(
        "contact-compare: {} problem(s) x {} solver(s) x {} tolerance(s), {} s per solve",
        problems.len(),
        solvers.len(),
        settings.tolerances.len(),
        settings.time_limit_s
    );
    let bar = progress_bar((problems.len() * solvers.len() * settings.tolerances.len()) as u64);
    let total = problems.len() * solvers.len() * settings.tolerances.len();
    let stop = args.stop.as_deref();
    let comparison = compare_until(&problems, unreadable, &solvers, &settings, stop, &mut |r| {
        bar.inc(1);
        bar.set_message(format!("{} {} {:e}", r.problem, r.solver, r.tolerance));
        let line = format!(
            "{:<36} {:<20} {:>7.0e} error {:>9.2e} {:>8} it {:>10.3e} s  {}",
            r.problem, r.solver, r.tolerance, r.error, r.iterations, r.seconds, r.status
        );
        if bar.is_hidden() {
            eprintln!("{line}");
        } else {
            bar.println(line);
        }
    });
    bar.finish_and_clear();
    let interrupted = stop.is_some_and(|s| s.load(Ordering::SeqCst));
    let note = interrupted.then(|| {
        format!(
            "Interrupted by a signal: {} of the {total} solves finished; the tables hold those \
             and their problems only.",
            comparison.rows.len()
        )
    });
    write_outputs_noting(&args.out, &comparison, note.as_deref()).map_err(|e| {
        CompareError::Write {
            out: args.out.display().to_string(),
            message: e.to_string(),
        }
    })?;
    println!("{}", solver_summary(&comparison).to_markdown());
    println!(
        "report: {}",
        Path::new(&args.out).join("README.md").display()
    );
    if interrupted {
        eprintln!(
            "interrupted: {} of the {total} solves finished and are written to `{}`",
            comparison.rows.len(),
            args.out.display()
        );
        return Ok(INTERRUPTED);
    }
    Ok(if comparison.unreadable.is_empty() {
        0
    } else {
        1
    })
}

/// Creates `out` if needed and checks that a file can be written in it.
fn check_writable(out: &Path) -> Result<(), CompareError> {
    let cannot = |e: std::io::Error| CompareError::NotWritable {
        out: out.display().to_string(),
        message: e.to_string(),
    };
    std::fs::create_dir_all(out).map_err(cannot)?;
    let probe = out.join(".contact-compare-write-check");
    std::fs::write(&probe, b"").map_err(cannot)?;
    std::fs::remove_file(&probe).map_err(cannot)
}

fn progress_bar(len: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix:>10} [{bar:40}] {pos}/{len} solves, {elapsed_precise}, left {eta}  {msg}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.set_prefix("comparing");
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder with one small problem file, and the arguments that compare it into `out`.
    fn args(dir: &Path, out: PathBuf, time_limit_s: f64) -> CompareArgs {
        let file = dir.join("one.json");
        let problem = crate::contact_compare::test_problem(
            &[(0, 0, 2.0), (1, 1, 2.0), (2, 2, 2.0)],
            &[-1.0, 0.0, 0.0],
            &[0.5],
        );
        impact_solver::contact::problem_file::ProblemFile::from_problem(&problem, vec![])
            .write(&file)
            .unwrap();
        CompareArgs {
            inputs: vec![file],
            out,
            tolerances: vec![1e-6],
            time_limit_s,
            solvers: vec!["gauss-seidel/exact".into()],
            stop: None,
        }
    }

    /// `--time-limit` must be positive and finite (inf and 1e300 used to panic in
    /// `Duration::from_secs_f64`); the message names the flag.
    #[test]
    fn a_time_limit_that_is_not_finite_and_positive_is_refused_naming_the_flag() {
        let dir = tempfile::tempdir().unwrap();
        for limit in [f64::INFINITY, 1e300, f64::NAN, 0.0, -1.0] {
            let e = run_inner(&args(dir.path(), dir.path().join("out"), limit));
            if limit == 1e300 {
                // Finite and positive: a legal (if long) limit, beyond what a Duration holds;
                // the comparison runs without a limit instead of panicking.
                assert_eq!(e.ok(), Some(0));
                continue;
            }
            let e = e.unwrap_err().to_string();
            assert!(e.contains("--time-limit"), "{limit}: {e}");
        }
    }

    /// An output folder that cannot be written (here a path under a file) is an error before
    /// any solve, naming the folder; with a stop flag already set, nothing is solved, what there
    /// is (no rows) is written, and the status is 130.
    #[test]
    fn the_output_folder_is_checked_before_solving_and_a_stop_gives_130() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a-file");
        std::fs::write(&file, "").unwrap();
        let e = run_inner(&args(dir.path(), file.join("out"), 10.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("a-file/out") && e.contains("--out"), "{e}");

        let out = dir.path().join("out");
        let mut stopped = args(dir.path(), out.clone(), 10.0);
        stopped.stop = Some(Arc::new(AtomicBool::new(true)));
        assert_eq!(run_inner(&stopped).ok(), Some(INTERRUPTED));
        let readme = std::fs::read_to_string(out.join("README.md")).unwrap();
        assert!(
            readme.contains("Interrupted by a signal: 0 of the 1 solves"),
            "{readme}"
        );
    }
}
