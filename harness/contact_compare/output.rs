//! The files of a comparison: `results.json` (the [`Comparison`]), `results.csv` (one line per
//! solve), `README.md` (tables and plots) and the SVG plots.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::tables::{descriptor_table, error_matrix, long_table, solver_summary};
use super::{performance_profile, work_precision_plot, Comparison};
use crate::report::render_plot;

/// File name of the performance profile at `tolerance`, e.g. `profile-1e-8.svg`.
pub fn profile_file(tolerance: f64) -> String {
    format!("profile-{tolerance:e}.svg")
}

/// File name of the work-precision diagram of the comparison in the output folder.
pub const WORK_PRECISION_FILE: &str = "work-precision.svg";

/// Writes every file into `dir` (created if needed); returns the paths written.
pub fn write_outputs(dir: &Path, c: &Comparison) -> io::Result<Vec<PathBuf>> {
    write_outputs_noting(dir, c, None)
}

/// [`write_outputs`] with `note` (e.g. that the comparison was interrupted) as the first
/// paragraph of `README.md`.
pub fn write_outputs_noting(
    dir: &Path,
    c: &Comparison,
    note: Option<&str>,
) -> io::Result<Vec<PathBuf>> {
    fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let mut write = |name: &str, text: String| -> io::Result<()> {
        let path = dir.join(name);
        fs::write(&path, text)?;
        written.push(path);
        Ok(())
    };
    let json = serde_json::to_string_pretty(c).map_err(io::Error::other)?;
    write("results.json", json + "\n")?;
    write("results.csv", csv(c))?;
    for &tol in &c.tolerances {
        write(
            &profile_file(tol),
            render_plot(&performance_profile(c, tol).plot()),
        )?;
    }
    write(WORK_PRECISION_FILE, render_plot(&work_precision_plot(c)))?;
    let mut md = readme(c);
    if let Some(note) = note {
        let title_end = md.find("\n\n").map_or(0, |i| i + 2);
        md.insert_str(title_end, &format!("**{note}**\n\n"));
    }
    write("README.md", md)?;
    Ok(written)
}

/// One line per solve, with the problem's size; notes quoted.
pub fn csv(c: &Comparison) -> String {
    let mut out = String::from(
        "problem,contacts,unknowns,solver,tolerance,error,absolute_error,iterations,\
         outer_iterations,seconds,repeats,status,solved,notes\n",
    );
    for r in &c.rows {
        let size = c.problems.iter().find(|p| p.name == r.problem);
        out.push_str(&format!(
            "{},{},{},{},{:e},{:e},{:e},{},{},{:e},{},{},{},\"{}\"\n",
            r.problem,
            size.map_or(0, |p| p.contacts),
            size.map_or(0, |p| p.unknowns),
            r.solver,
            r.tolerance,
            r.error,
            r.absolute_error,
            r.iterations,
            r.outer_iterations,
            r.seconds,
            r.repeats,
            r.status,
            r.solved,
            r.notes.join("; ").replace('"', "\"\""),
        ));
    }
    out
}

/// The Markdown summary: settings, descriptors, per-solver summary, the error matrix and
/// profile of each tolerance, the work-precision diagram, and every row.
pub fn readme(c: &Comparison) -> String {
    let mut md = String::from("# Contact-solver comparison\n\n");
    md.push_str(&format!(
        "{} problem(s), solvers {}, tolerances {}, time limit {} s per solve. Error: {}. \
         Times: median wall time over repeats of the same solve. A solve counts as solved when \
         its error is at most the tolerance within the time limit (✓), whatever the solver's \
         own status.\n\n",
        c.problems.len(),
        c.solvers.join(", "),
        c.tolerances
            .iter()
            .map(|t| format!("{t:e}"))
            .collect::<Vec<_>>()
            .join(", "),
        c.time_limit_s,
        c.normalisation,
    ));
    if !c.unreadable.is_empty() {
        md.push_str("## Problems that could not be read\n\n");
        for u in &c.unreadable {
            md.push_str(&format!("- `{}`: {}\n", u.file, u.message));
        }
        md.push('\n');
    }
    md.push_str("## Problems\n\n");
    md.push_str(&descriptor_table(c).to_markdown());
    md.push_str("\n## Solvers\n\n");
    md.push_str(&solver_summary(c).to_markdown());
    for &tol in &c.tolerances {
        md.push_str(&format!("\n## Tolerance {tol:e}\n\n"));
        md.push_str(&error_matrix(c, tol).to_markdown());
        let profile = performance_profile(c, tol);
        let unsolved = profile.unsolved();
        if !unsolved.is_empty() {
            md.push_str(&format!(
                "\nSolved by no solver: {}.\n",
                unsolved.join(", ")
            ));
        }
        md.push_str(&format!(
            "\n![performance profile at {tol:e}]({})\n",
            profile_file(tol)
        ));
    }
    md.push_str(&format!(
        "\n## Work-precision\n\nPer solver, one point per tolerance: total median time over \
         the problems against the worst error reached.\n\n![work-precision]({WORK_PRECISION_FILE})\n"
    ));
    md.push_str("\n## Every solve\n\n");
    md.push_str(&long_table(c).to_markdown());
    md
}
