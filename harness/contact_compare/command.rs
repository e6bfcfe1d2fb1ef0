//! `impact-vv contact-compare`: the comparison of the contact solvers on problem files, with a
//! progress bar, written to a folder.

use std::path::{Path, PathBuf};

use super::output::write_outputs;
use super::tables::solver_summary;
use super::{collect_problem_files, compare, load_problems, solver_entries, CompareSettings};

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
}

/// Runs the command; returns the exit status: 0 done, 1 done but some file could not be read,
/// 2 bad input (no problem files, a missing path, an unknown solver, a bad tolerance, or
/// nothing readable), each with a message naming what is wrong on stderr.
pub fn run(args: &CompareArgs) -> u8 {
    match run_inner(args) {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            2
        }
    }
}

fn run_inner(args: &CompareArgs) -> Result<u8, String> {
    if let Some(t) = args.tolerances.iter().find(|t| !(**t > 0.0)) {
        return Err(format!("tolerance {t} is not positive"));
    }
    if args.tolerances.is_empty() {
        return Err("no tolerance given (--tolerances 1e-4,1e-6,1e-8)".into());
    }
    if !(args.time_limit_s > 0.0) {
        return Err(format!(
            "--time-limit {} is not positive",
            args.time_limit_s
        ));
    }
    let solvers = solver_entries(&args.solvers)?;
    let files = collect_problem_files(&args.inputs)?;
    let (problems, unreadable) = load_problems(&files);
    for u in &unreadable {
        eprintln!("error: {}", u.message);
    }
    if problems.is_empty() {
        return Err(format!(
            "none of the {} file(s) could be read as a contact problem",
            files.len()
        ));
    }
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
    let comparison = compare(&problems, unreadable, &solvers, &settings, &mut |r| {
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
    write_outputs(&args.out, &comparison)
        .map_err(|e| format!("cannot write into `{}`: {e}", args.out.display()))?;
    println!("{}", solver_summary(&comparison).to_markdown());
    println!(
        "report: {}",
        Path::new(&args.out).join("README.md").display()
    );
    Ok(if comparison.unreadable.is_empty() {
        0
    } else {
        1
    })
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
