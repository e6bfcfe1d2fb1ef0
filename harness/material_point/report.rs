//! The "Concrete material" section of the report: per material-point case its setup, its
//! metrics against their targets, the tables and plots of its experiment (targets drawn as
//! windows, bands and dashed reference curves), its notes, and every value it measured folded
//! away.

use super::MaterialRecord;
use crate::report::blocks::{element, list, note, plots, table, text, Cell, Row};
use crate::report::format;
use crate::report::records::{metric_markdown, metric_table, record_table, target_plot};
use crate::report::section::{cases_with, part_heading, part_link, Page, Section};
use crate::report::summary::{status_name, CaseSummary};
use crate::results::{CaseResult, Status};

/// The section of the material-point cases.
pub struct MaterialSection;

impl Section for MaterialSection {
    fn anchor(&self) -> &'static str {
        "concrete-material"
    }

    fn title(&self) -> &'static str {
        "Concrete material"
    }

    fn html(&self, page: &Page<'_>) -> Option<String> {
        let list = cases_with::<MaterialRecord>(page, MaterialRecord::KEY);
        if list.is_empty() {
            return None;
        }
        let mut html = element(
            "p",
            "",
            "Virtual experiments on one material point of the microplane concrete model (thesis \
             chapter 5, MICROPLANE.md) against the targets of the catalogue. Stresses in MPa, \
             strains in 1e-3 on the axes; shaded windows and bands are acceptance targets, dashed \
             curves are published references.",
        );
        for (s, record) in list {
            html.push_str(&part_heading(self, s, ""));
            html.push_str(&case_part(s.case, &record));
        }
        Some(html)
    }

    fn in_case(&self, case: &CaseSummary<'_>, _page: &Page<'_>) -> String {
        if !case.case.records.contains_key(MaterialRecord::KEY) {
            return String::new();
        }
        part_link(self, case, "Curves, tables and targets")
    }

    fn markdown(&self, page: &Page<'_>) -> Option<String> {
        let list = cases_with::<MaterialRecord>(page, MaterialRecord::KEY);
        if list.is_empty() {
            return None;
        }
        let mut md = String::from(
            "Material-point experiments of the microplane model; the report page has their \
             curves.\n",
        );
        for (s, record) in list {
            let c = s.case;
            md.push_str(&format!(
                "\n### {} ({}, {})\n\n{}\n\n",
                c.id,
                status_name(c.status).to_uppercase(),
                record.material,
                record.setup.join("; ")
            ));
            if !c.metrics.is_empty() {
                md.push_str(&metric_markdown(c, true));
            }
            for note in &record.notes {
                md.push_str(&format!("\n- {}", format::first_line(note, 240)));
            }
            if !record.notes.is_empty() {
                md.push('\n');
            }
        }
        Some(md)
    }
}

/// One case's part: setup, notes, metrics, tables, plots, and every value measured.
fn case_part(c: &CaseResult, record: &MaterialRecord) -> String {
    let setup: String = std::iter::once(format!(
        "parameter file <code>{}</code>, experiment <code>{}</code>",
        format::html(&record.material),
        format::html(&record.experiment)
    ))
    .chain(record.setup.iter().map(|s| format::html(s)))
    .map(|s| format!("<li>{s}</li>"))
    .collect();
    let mut html = element("ul", "", &setup);
    if c.status == Status::Error {
        html.push_str(&note(c.message.as_deref().unwrap_or("no reason given")));
    }
    if !record.notes.is_empty() {
        html.push_str(&element(
            "div",
            "callout skipped",
            &format!(
                "<div class=\"callout-title\">Notes</div>\n{}",
                list(&record.notes)
            ),
        ));
    }
    if !c.metrics.is_empty() {
        html.push_str(&element("h4", "", "Measured against target"));
        html.push_str(&metric_table(c, true));
    }
    for t in &record.tables {
        html.push_str(&record_table(t));
    }
    if !record.plots.is_empty() {
        html.push_str(&plots("plots", record.plots.iter().map(target_plot)));
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
    html
}
