//! The "Independent cross-checks" section of the page (content from `report::crosscheck`): per
//! cross-check case a callout saying where the independent answer came from (fresh, or cached
//! with its date and versions), the setup, the metrics, the comparison tables and plots.

use super::{badge, element, note, plots, table, text, Cell, Row};
use crate::report::crosscheck::{self, provenance_badge};
use crate::report::format;
use crate::report::material::metric_rows;
use crate::report::summary::CaseSummary;
use crate::results::{RunResults, Status};

fn anchor(s: &CaseSummary<'_>) -> String {
    format!("crosscheck-{}", s.anchor)
}

/// A line in a cross-check case's own section pointing to its comparison; empty otherwise.
pub fn case_link(s: &CaseSummary<'_>) -> String {
    if s.case.crosscheck.is_none() {
        return String::new();
    }
    element(
        "p",
        "",
        &format!(
            "Tables, plots and the provenance of the independent answer: <a href=\"#{}\">Independent cross-checks</a>.",
            anchor(s)
        ),
    )
}

/// The section, or nothing when the run has no cross-check case.
pub fn section(results: &RunResults, summaries: &[CaseSummary<'_>]) -> String {
    let list = crosscheck::cases(results);
    if list.is_empty() {
        return String::new();
    }
    let mut html = String::from("<section id=\"crosscheck\">\n<h2>Independent cross-checks</h2>\n");
    html.push_str(&element(
        "p",
        "",
        "The solver against code written by others: scikit-fem (quadratic tetrahedra) for the \
         elastic beam, ipctk (Tight-Inclusion) for continuous collision detection. Built with \
         the <code>python</code> feature, their answers are computed in the run; otherwise the \
         cached answers in <code>references/crosscheck/cache/</code> are judged, and marked \
         CACHED with the date and versions that produced them.",
    ));
    for (index, c, record) in list {
        let Some(s) = summaries.get(index) else {
            continue;
        };
        html.push_str(&format!(
            "<h3 id=\"{}\">{} {} <span class=\"badge {}\">{}</span> <a href=\"#{}\">metrics and trend</a></h3>\n",
            anchor(s),
            badge(c.status),
            format::html(&c.id),
            if record.provenance.as_ref().is_some_and(|p| p.mode == "cached") { "skipped" } else { "pass" },
            format::html(&provenance_badge(record)),
            s.anchor
        ));
        if !c.description.is_empty() {
            html.push_str(&element("p", "description", &format::html(&c.description)));
        }
        let setup: String = record
            .setup
            .iter()
            .map(|s| format!("<li>{}</li>", format::html(s)))
            .collect();
        html.push_str(&element("ul", "", &setup));
        if c.status == Status::Error {
            html.push_str(&note(c.message.as_deref().unwrap_or("no reason given")));
        }
        if !c.metrics.is_empty() {
            let rows: Vec<Row> = metric_rows(c)
                .into_iter()
                .map(|r| {
                    let pass = r[4] == "pass";
                    Row {
                        class: if pass { "" } else { "bad" },
                        cells: vec![
                            text(&r[0]),
                            Cell::Num(r[1].clone()),
                            text(&r[2]),
                            Cell::Html(badge(if pass { Status::Pass } else { Status::Fail })),
                            Cell::Html(element("span", "source", &format::html(&r[5]))),
                        ],
                    }
                })
                .collect();
            let head: Vec<String> = ["metric", "value", "target", "verdict", "source"]
                .iter()
                .map(|s| s.to_string())
                .collect();
            html.push_str(&table(&head, &rows));
        }
        for t in &record.tables {
            html.push_str(&super::material::record_table(t));
        }
        if !record.plots.is_empty() {
            html.push_str(&plots(
                "plots",
                record.plots.iter().map(crate::report::material::render),
            ));
        }
        if !record.notes.is_empty() {
            let items: String = record
                .notes
                .iter()
                .map(|n| format!("<li>{}</li>", format::html(n)))
                .collect();
            html.push_str(&element("ul", "", &items));
        }
    }
    html.push_str("</section>\n");
    html
}
