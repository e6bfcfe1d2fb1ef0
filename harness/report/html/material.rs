//! The "Concrete material" section of the page (content from `report::material`): per
//! material-point case its setup, its metrics against their targets, the tables and plots of
//! its experiment (targets drawn as windows, bands and dashed reference curves), its notes, and
//! every value it measured folded away.

use super::{badge, element, note, plots, table, text, Cell, Row};
use crate::report::format;
use crate::report::material::{self, metric_rows};
use crate::report::summary::CaseSummary;
use crate::results::{RunResults, Status};

/// The anchor of a case's part of the section.
fn anchor(s: &CaseSummary<'_>) -> String {
    format!("material-{}", s.anchor)
}

/// A line in a material case's own section pointing to its curves; empty for other cases.
pub fn case_link(s: &CaseSummary<'_>) -> String {
    if s.case.material.is_none() {
        return String::new();
    }
    element(
        "p",
        "",
        &format!(
            "Curves, tables and targets: <a href=\"#{}\">Concrete material</a>.",
            anchor(s)
        ),
    )
}

/// The section, or nothing when the run has no material-point case.
pub fn section(results: &RunResults, summaries: &[CaseSummary<'_>]) -> String {
    let list = material::cases(results);
    if list.is_empty() {
        return String::new();
    }
    let mut html = String::from("<section id=\"concrete-material\">\n<h2>Concrete material</h2>\n");
    html.push_str(&element(
        "p",
        "",
        "Virtual experiments on one material point of the microplane concrete model (thesis \
         chapter 5, MICROPLANE.md) against the targets of the catalogue. Stresses in MPa, strains \
         in 1e-3 on the axes; shaded windows and bands are acceptance targets, dashed curves are \
         published references.",
    ));
    for (index, c, record) in list {
        let Some(s) = summaries.get(index) else {
            continue;
        };
        html.push_str(&format!(
            "<h3 id=\"{}\">{} {} <a href=\"#{}\">metrics and trend</a></h3>\n",
            anchor(s),
            badge(c.status),
            format::html(&c.id),
            s.anchor
        ));
        if !c.description.is_empty() {
            html.push_str(&element("p", "description", &format::html(&c.description)));
        }
        let setup: String = std::iter::once(format!(
            "parameter file <code>{}</code>, experiment <code>{}</code>",
            format::html(&record.material),
            format::html(&record.experiment)
        ))
        .chain(record.setup.iter().map(|s| format::html(s)))
        .map(|s| format!("<li>{s}</li>"))
        .collect();
        html.push_str(&element("ul", "", &setup));
        if c.status == Status::Error {
            html.push_str(&note(c.message.as_deref().unwrap_or("no reason given")));
        }
        if !record.notes.is_empty() {
            let items: String = record
                .notes
                .iter()
                .map(|n| format!("<li>{}</li>", format::html(n)))
                .collect();
            html.push_str(&element(
                "div",
                "callout skipped",
                &format!(
                    "<div class=\"callout-title\">Notes</div>\n{}",
                    element("ul", "", &items)
                ),
            ));
        }
        if !c.metrics.is_empty() {
            html.push_str(&element("h4", "", "Measured against target"));
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
                            text(&r[3]),
                            Cell::Html(badge(if pass { Status::Pass } else { Status::Fail })),
                            Cell::Html(element("span", "source", &format::html(&r[5]))),
                        ],
                    }
                })
                .collect();
            let head: Vec<String> = ["metric", "value", "target", "unit", "verdict", "source"]
                .iter()
                .map(|s| s.to_string())
                .collect();
            html.push_str(&table(&head, &rows));
        }
        for t in &record.tables {
            html.push_str(&record_table(t));
        }
        if !record.plots.is_empty() {
            html.push_str(&plots("plots", record.plots.iter().map(material::render)));
        }
        if !record.values.is_empty() {
            let rows: Vec<Row> = record
                .values
                .iter()
                .map(|v| {
                    Row::new(vec![
                        text(&v.quantity),
                        text(&v.at),
                        Cell::Num(format::num(v.value)),
                        text(&v.unit),
                        text(&v.judged_by.join(", ")),
                    ])
                })
                .collect();
            let head: Vec<String> = ["quantity", "at", "value", "unit", "judged by"]
                .iter()
                .map(|s| s.to_string())
                .collect();
            html.push_str(&format!(
                "<details><summary>Every value measured ({})</summary>\n{}</details>\n",
                record.values.len(),
                table(&head, &rows)
            ));
        }
    }
    html.push_str("</section>\n");
    html
}

/// A record's table (material-point experiments, cross-checks): title, cells as text, note.
pub(super) fn record_table(t: &crate::material_point::RecordTable) -> String {
    let rows: Vec<Row> = t
        .rows
        .iter()
        .map(|r| Row::new(r.iter().map(|c| text(c)).collect()))
        .collect();
    let mut html = element("h4", "", &format::html(&t.title));
    html.push_str(&table(&t.head, &rows));
    if !t.note.is_empty() {
        html.push_str(&element("p", "muted", &format::html(&t.note)));
    }
    html
}
