//! The "Independent cross-checks" part of the report, as data both outputs render: the cases
//! that compared the solver with code written by others (`crosscheck` cases), each with where
//! the independent answer came from (computed in this run, or read from the cache with its date
//! and package versions), its metrics, tables and plots.

use super::material::metric_rows;
use super::summary::status_name;
use crate::crosscheck::CrosscheckRecord;
use crate::results::{CaseResult, RunResults};

/// Cases carrying a cross-check record, in run order.
pub fn cases(results: &RunResults) -> Vec<(usize, &CaseResult, &CrosscheckRecord)> {
    results
        .cases
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.crosscheck.as_ref().map(|r| (i, c, r)))
        .collect()
}

/// `fresh` or `CACHED <date>`: the badge of an independent answer.
pub fn provenance_badge(record: &CrosscheckRecord) -> String {
    match &record.provenance {
        Some(p) if p.mode == "cached" => format!("CACHED {}", p.date),
        Some(_) => "fresh".into(),
        None => "no answer".into(),
    }
}

/// The section in Markdown for `summary.md`; empty when the run has nothing for it.
pub fn markdown(results: &RunResults) -> String {
    let list = cases(results);
    if list.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Independent cross-checks\n\nThe solver against code written by others (scikit-fem, \
         ipctk). Without the `python` feature their cached answers are judged; each says so.\n",
    );
    for (_, c, record) in list {
        md.push_str(&format!(
            "\n### {} ({}, {}, {})\n\n",
            c.id,
            status_name(c.status).to_uppercase(),
            record.kind,
            provenance_badge(record)
        ));
        for line in &record.setup {
            md.push_str(&format!("- {}\n", super::format::markdown_cell(line)));
        }
        if !c.metrics.is_empty() {
            md.push_str("\n| metric | value | target | verdict |\n|---|---:|---|---|\n");
            for r in metric_rows(c) {
                md.push_str(&format!(
                    "| {} | {} | {} | {} |\n",
                    super::format::markdown_cell(&r[0]),
                    r[1],
                    super::format::markdown_cell(&r[2]),
                    if r[4] == "pass" { "pass" } else { "**FAIL**" }
                ));
            }
        }
        for t in &record.tables {
            md.push_str(&format!("\n{}\n\n", t.title));
            md.push_str(&format!("| {} |\n", t.head.join(" | ")));
            md.push_str(&format!("|{}\n", "---|".repeat(t.head.len())));
            for row in &t.rows {
                let cells: Vec<String> = row
                    .iter()
                    .map(|c| super::format::markdown_cell(c))
                    .collect();
                md.push_str(&format!("| {} |\n", cells.join(" | ")));
            }
        }
        for note in &record.notes {
            md.push_str(&format!("\n- {}", super::format::first_line(note, 240)));
        }
        md.push('\n');
    }
    md
}
