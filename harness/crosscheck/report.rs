//! The "Independent cross-checks" section of the report: per cross-check case where the
//! independent answer came from (computed in this run, or read from the cache with its date and
//! package versions), the setup, the metrics, the comparison tables and plots.

use super::{AnswerMode, CrosscheckRecord};
use crate::report::blocks::{element, list, note, plots};
use crate::report::format;
use crate::report::records::{metric_markdown, metric_table, record_table, target_plot};
use crate::report::section::{cases_with, part_heading, part_link, Page, Section};
use crate::report::summary::{status_name, CaseSummary};
use crate::results::{CaseResult, Status};

/// The section of the cross-check cases.
pub struct CrosscheckSection;

/// `fresh` or `CACHED <date>`: the badge of an independent answer.
pub fn provenance_badge(record: &CrosscheckRecord) -> String {
    match &record.provenance {
        Some(p) if p.mode == AnswerMode::Cached => format!("CACHED {}", p.date),
        Some(_) => "fresh".into(),
        None => "no answer".into(),
    }
}

impl Section for CrosscheckSection {
    fn anchor(&self) -> &'static str {
        "crosscheck"
    }

    fn title(&self) -> &'static str {
        "Independent cross-checks"
    }

    fn html(&self, page: &Page<'_>) -> Option<String> {
        let list = cases_with::<CrosscheckRecord>(page, CrosscheckRecord::KEY);
        if list.is_empty() {
            return None;
        }
        let mut html = element(
            "p",
            "",
            "The solver against code written by others: scikit-fem (quadratic tetrahedra) for the \
             elastic beam, ipctk (Tight-Inclusion) for continuous collision detection. Built with \
             the <code>python</code> feature, their answers are computed in the run; otherwise the \
             cached answers in <code>references/crosscheck/cache/</code> are judged, and marked \
             CACHED with the date and versions that produced them.",
        );
        for (s, record) in list {
            let cached = record
                .provenance
                .as_ref()
                .is_some_and(|p| p.mode == AnswerMode::Cached);
            let provenance = format!(
                " <span class=\"badge {}\">{}</span>",
                if cached { "skipped" } else { "pass" },
                format::html(&provenance_badge(&record))
            );
            html.push_str(&part_heading(self, s, &provenance));
            html.push_str(&case_part(s.case, &record));
        }
        Some(html)
    }

    fn in_case(&self, case: &CaseSummary<'_>, _page: &Page<'_>) -> String {
        if !case.case.records.contains_key(CrosscheckRecord::KEY) {
            return String::new();
        }
        part_link(
            self,
            case,
            "Tables, plots and the provenance of the independent answer",
        )
    }

    fn markdown(&self, page: &Page<'_>) -> Option<String> {
        let list = cases_with::<CrosscheckRecord>(page, CrosscheckRecord::KEY);
        if list.is_empty() {
            return None;
        }
        let mut md = String::from(
            "The solver against code written by others (scikit-fem, ipctk). Without the `python` \
             feature their cached answers are judged; each says so.\n",
        );
        for (s, record) in list {
            let c = s.case;
            md.push_str(&format!(
                "\n### {} ({}, {}, {})\n\n",
                c.id,
                status_name(c.status).to_uppercase(),
                record.kind,
                provenance_badge(&record)
            ));
            for line in &record.setup {
                md.push_str(&format!("- {}\n", format::markdown_cell(line)));
            }
            if !c.metrics.is_empty() {
                md.push('\n');
                md.push_str(&metric_markdown(c, false));
            }
            for t in &record.tables {
                md.push_str(&format!("\n{}\n\n", t.title));
                md.push_str(&format!("| {} |\n", t.head.join(" | ")));
                md.push_str(&format!("|{}\n", "---|".repeat(t.head.len())));
                for row in &t.rows {
                    let cells: Vec<String> = row.iter().map(|c| format::markdown_cell(c)).collect();
                    md.push_str(&format!("| {} |\n", cells.join(" | ")));
                }
            }
            for note in &record.notes {
                md.push_str(&format!("\n- {}", format::first_line(note, 240)));
            }
            md.push('\n');
        }
        Some(md)
    }
}

/// One case's part: setup, metrics, tables, plots and notes.
fn case_part(c: &CaseResult, record: &CrosscheckRecord) -> String {
    let mut html = list(&record.setup);
    if c.status == Status::Error {
        html.push_str(&note(c.message.as_deref().unwrap_or("no reason given")));
    }
    if !c.metrics.is_empty() {
        html.push_str(&metric_table(c, false));
    }
    for t in &record.tables {
        html.push_str(&record_table(t));
    }
    if !record.plots.is_empty() {
        html.push_str(&plots("plots", record.plots.iter().map(target_plot)));
    }
    html.push_str(&list(&record.notes));
    html
}
