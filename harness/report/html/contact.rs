//! The "Contact algorithms" section of the page (content from `report::contact`): comparisons
//! on stored problems with their tables, performance profiles and work-precision diagram; the
//! per-case tables of catalogue cases run with several contact solvers; and the work-precision
//! diagrams across solver variants of sweep cases.

use super::{element, note, plots, table, text, Row};
use crate::contact_compare::tables::{
    descriptor_table, error_matrix, long_table, solver_summary, Table,
};
use crate::contact_compare::{performance_profile, work_precision_plot, Comparison};
use crate::report::contact::{self, fastest_line};
use crate::report::format;
use crate::report::plot::render_plot;
use crate::results::{CaseResult, RunResults};

/// The section, or nothing when the run has no contact-solver content.
pub fn section(results: &RunResults) -> String {
    if !contact::has_content(results) {
        return String::new();
    }
    let mut html =
        String::from("<section id=\"contact-algorithms\">\n<h2>Contact algorithms</h2>\n");
    for (case, c) in contact::comparisons(results) {
        html.push_str(&comparison(case, c));
    }
    for t in contact::solver_tables(results) {
        html.push_str(&element(
            "h3",
            "",
            &format!("{}: contact solvers", format::html(&t.id)),
        ));
        html.push_str(&plain_table(&t.table));
        html.push_str(&element("p", "", &format::html(&fastest_line(&t))));
    }
    let variant_plots = contact::variant_work_precision(results);
    if !variant_plots.is_empty() {
        html.push_str(&element("h3", "", "Work-precision by contact solver"));
        html.push_str(&plots("plots", variant_plots.iter().map(render_plot)));
    }
    html.push_str("</section>\n");
    html
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
