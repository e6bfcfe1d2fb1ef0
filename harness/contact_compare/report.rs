//! The "Contact algorithms" section of the report: the comparisons on stored problems
//! (`contact_problems` cases) with their tables, performance profiles and work-precision
//! diagram; a table per catalogue case run with several contact solvers; and a work-precision
//! diagram across the solver variants of a sweep case. Everything here tolerates absent fields
//! (results written before they existed).

use std::collections::BTreeSet;

use super::tables::{descriptor_table, error_matrix, long_table, solver_summary, Table};
use super::{performance_profile, work_precision_plot, Comparison};
use crate::report::blocks::{element, note, plots, table, text, Row};
use crate::report::diagrams::sweep_metrics;
use crate::report::format::{self, num, seconds};
use crate::report::plot::render_plot;
use crate::report::section::{Page, Section};
use crate::report::summary::status_name;
use crate::results::{CaseResult, PlotData, RunResults, Series};

/// The section of contact-solver comparisons and of cases run with several contact solvers.
pub struct ContactSection;

impl Section for ContactSection {
    fn anchor(&self) -> &'static str {
        "contact-algorithms"
    }

    fn title(&self) -> &'static str {
        "Contact algorithms"
    }

    fn html(&self, page: &Page<'_>) -> Option<String> {
        let results = page.results;
        if !has_content(page) {
            return None;
        }
        let mut html = String::new();
        for (case, c) in comparisons(page) {
            html.push_str(&comparison(case, &c));
        }
        for t in solver_tables(results) {
            html.push_str(&element(
                "h3",
                "",
                &format!("{}: contact solvers", format::html(&t.id)),
            ));
            html.push_str(&plain_table(&t.table));
            html.push_str(&element("p", "", &format::html(&fastest_line(&t))));
        }
        let variant_plots = variant_work_precision(results);
        if !variant_plots.is_empty() {
            html.push_str(&element("h3", "", "Work-precision by contact solver"));
            html.push_str(&plots("plots", variant_plots.iter().map(render_plot)));
        }
        Some(html)
    }

    fn markdown(&self, page: &Page<'_>) -> Option<String> {
        has_content(page).then(|| markdown(page))
    }
}

/// Cases carrying a contact-solver comparison, in run order; one whose comparison does not
/// read is left to the page's error block ([`Page::record`]).
pub fn comparisons<'p>(page: &Page<'p>) -> Vec<(&'p CaseResult, Comparison)> {
    page.results
        .cases
        .iter()
        .filter_map(|c| page.record(c, Comparison::KEY).map(|cmp| (c, cmp)))
        .collect()
}

/// The results of each case id, in order of first appearance.
fn by_id(results: &RunResults) -> Vec<(&str, Vec<&CaseResult>)> {
    let mut groups: Vec<(&str, Vec<&CaseResult>)> = Vec::new();
    for c in &results.cases {
        match groups.iter_mut().find(|(id, _)| *id == c.id) {
            Some((_, list)) => list.push(c),
            None => groups.push((&c.id, vec![c])),
        }
    }
    groups
}

/// Contact time per step with contact (s); `None` without such steps.
pub fn seconds_per_step(c: &CaseResult) -> Option<f64> {
    let s = c.contact.as_ref()?;
    (s.steps_with_contact > 0).then(|| s.contact_seconds / s.steps_with_contact as f64)
}

/// The table of one case run with several contact solvers.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverTable {
    /// Id of the case.
    pub id: String,
    /// The table itself, one row per variant (contact solver) of the case.
    pub table: Table,
    /// The variant with the least contact time per step, among the passing ones when any
    /// passed, with that time.
    pub fastest: Option<(String, f64)>,
    /// Whether `fastest` was chosen among passing variants only.
    pub fastest_passing: bool,
}

/// One table per case id whose results carry contact statistics for two variants or more.
pub fn solver_tables(results: &RunResults) -> Vec<SolverTable> {
    by_id(results)
        .into_iter()
        .filter(|(_, cases)| cases.iter().filter(|c| c.contact.is_some()).count() >= 2)
        .map(|(id, cases)| solver_table(id, &cases))
        .collect()
}

fn solver_table(id: &str, cases: &[&CaseResult]) -> SolverTable {
    let with_stats: Vec<&CaseResult> = cases
        .iter()
        .copied()
        .filter(|c| c.contact.is_some())
        .collect();
    let passing: Vec<&CaseResult> = with_stats
        .iter()
        .copied()
        .filter(|c| c.status == crate::results::Status::Pass)
        .collect();
    let pool = if passing.is_empty() {
        &with_stats
    } else {
        &passing
    };
    let fastest = pool
        .iter()
        .filter_map(|c| seconds_per_step(c).map(|t| (c.variant.clone(), t)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let rows = with_stats
        .iter()
        .map(|c| {
            let s = c.contact.as_ref().expect("filtered on contact statistics");
            let share = if s.solves > 0 {
                format!(
                    "{} ({}%)",
                    s.not_converged,
                    num(100.0 * s.not_converged as f64 / s.solves as f64)
                )
            } else {
                s.not_converged.to_string()
            };
            let mean_iterations = if s.solves > 0 {
                num(s.iterations as f64 / s.solves as f64)
            } else {
                "—".into()
            };
            let per_step = seconds_per_step(c).map_or("—".into(), seconds);
            let is_fastest = fastest.as_ref().is_some_and(|(v, _)| v == &c.variant);
            vec![
                c.variant.clone(),
                s.solver.clone(),
                status_name(c.status).to_string(),
                s.solves.to_string(),
                share,
                s.unresolved.to_string(),
                mean_iterations,
                per_step,
                seconds(c.wall_s),
                if is_fastest { "fastest" } else { "" }.to_string(),
            ]
        })
        .collect();
    SolverTable {
        id: id.to_string(),
        table: Table {
            head: [
                "variant",
                "contact solver",
                "case status",
                "solves",
                "not converged",
                "unresolved",
                "mean iterations per solve",
                "contact time per step",
                "wall time",
                "",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect(),
            rows,
        },
        fastest,
        fastest_passing: !passing.is_empty(),
    }
}

/// For each case id with contact whose sweep ran under two solver variants or more: one
/// work-precision diagram per metric, one curve per variant (error against wall time per
/// level, log-log).
pub fn variant_work_precision(results: &RunResults) -> Vec<PlotData> {
    let mut plots = Vec::new();
    for (id, cases) in by_id(results) {
        let swept: Vec<&CaseResult> = cases
            .iter()
            .copied()
            .filter(|c| c.sweep.is_some())
            .collect();
        if swept.len() < 2 || !cases.iter().any(|c| c.contact.is_some()) {
            continue;
        }
        let metrics: BTreeSet<String> = swept
            .iter()
            .flat_map(|c| sweep_metrics(c.sweep.as_ref().expect("filtered on sweep")))
            .collect();
        for metric in metrics {
            let series = swept
                .iter()
                .map(|c| {
                    let levels = &c.sweep.as_ref().expect("filtered on sweep").levels;
                    Series {
                        name: c.variant.clone(),
                        x: levels.iter().map(|l| l.wall_s).collect(),
                        y: levels
                            .iter()
                            .map(|l| l.errors.get(&metric).copied().unwrap_or(f64::NAN))
                            .collect(),
                    }
                })
                .collect();
            plots.push(PlotData {
                title: format!("Work-precision by solver: {id}, {metric}"),
                x_label: "wall time [s]".into(),
                y_label: format!("error of {metric}"),
                series,
                reference_lines: Vec::new(),
                log_log: true,
            });
        }
    }
    plots
}

/// Whether the run has anything for the section.
pub fn has_content(page: &Page<'_>) -> bool {
    let results = page.results;
    !comparisons(page).is_empty()
        || !solver_tables(results).is_empty()
        || !variant_work_precision(results).is_empty()
}

/// A line naming the fastest variant of a solver table.
pub fn fastest_line(t: &SolverTable) -> String {
    match &t.fastest {
        Some((variant, time)) => format!(
            "Fastest{}: {variant}, {} of contact per step with contact.",
            if t.fastest_passing {
                " among the passing variants"
            } else {
                " (no variant passed)"
            },
            seconds(*time)
        ),
        None => "No variant recorded a step with contact.".into(),
    }
}

/// The section in Markdown for `summary.md`.
fn markdown(page: &Page<'_>) -> String {
    let results = page.results;
    let mut md = String::new();
    for (case, c) in comparisons(page) {
        md.push_str(&format!(
            "\n### {}: {} problems\n\nError: {}; ✓ error at most the tolerance within {} s.\n\n",
            case.id,
            c.problems.len(),
            c.normalisation,
            c.time_limit_s
        ));
        md.push_str(&solver_summary(&c).to_markdown());
        for &tol in &c.tolerances {
            md.push_str(&format!("\nTolerance {tol:e}:\n\n"));
            md.push_str(&error_matrix(&c, tol).to_markdown());
        }
    }
    for t in solver_tables(results) {
        md.push_str(&format!("\n### {}: contact solvers\n\n", t.id));
        md.push_str(&t.table.to_markdown());
        md.push_str(&format!("\n{}\n", fastest_line(&t)));
    }
    md
}

/// A table of plain-text cells.
fn plain_table(t: &Table) -> String {
    let rows: Vec<Row> = t
        .rows
        .iter()
        .map(|r| Row::new(r.iter().map(|c| text(c)).collect()))
        .collect();
    table(&t.head, &rows)
}

/// One comparison: what was measured, the problems, the solvers' summary, the error matrix of
/// each tolerance, the profiles and the work-precision diagram, and every solve folded away.
fn comparison(case: &CaseResult, c: &Comparison) -> String {
    let mut html = element(
        "h3",
        "",
        &format!(
            "{}: {} problems, {} solvers",
            format::html(&case.id),
            c.problems.len(),
            c.solvers.len()
        ),
    );
    html.push_str(&element(
        "p",
        "",
        &format::html(&format!(
            "Error: {}. Times: median wall time of repeated solves. ✓: error at most the \
             tolerance within {} s (the criterion of the performance profiles, Dolan & More \
             2002), whatever the solver's own status.",
            c.normalisation, c.time_limit_s
        )),
    ));
    for u in &c.unreadable {
        html.push_str(&note(&format!("not read: {}", u.message)));
    }
    html.push_str(&element("h4", "", "Problems"));
    html.push_str(&plain_table(&descriptor_table(c)));
    html.push_str(&element("h4", "", "Solvers"));
    html.push_str(&plain_table(&solver_summary(c)));
    for &tol in &c.tolerances {
        html.push_str(&element("h4", "", &format!("Tolerance {tol:e}")));
        html.push_str(&plain_table(&error_matrix(c, tol)));
        let unsolved = performance_profile(c, tol).unsolved().join(", ");
        if !unsolved.is_empty() {
            html.push_str(&note(&format!("solved by no solver: {unsolved}")));
        }
    }
    let figures = c
        .tolerances
        .iter()
        .map(|&tol| render_plot(&performance_profile(c, tol).plot()))
        .chain(std::iter::once(render_plot(&work_precision_plot(c))));
    html.push_str(&element(
        "h4",
        "",
        "Performance profiles and work-precision",
    ));
    html.push_str(&plots("plots", figures));
    html.push_str(&format!(
        "<details><summary>Every solve ({})</summary>\n{}</details>\n",
        c.rows.len(),
        plain_table(&long_table(c))
    ));
    html
}
