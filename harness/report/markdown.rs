//! `summary.md`: the summary table and the failures, short enough to paste into a chat.

use super::format;
use super::section::{self, Page, Section};
use super::summary::{self, worst_text, CaseState, CaseSummary};
use crate::results::Status;

/// How much of a failure message the summary quotes; the page has the rest.
const MESSAGE_CHARS: usize = 160;

/// The Markdown summary of a run.
pub fn summary(page: &Page<'_>, sections: &[&dyn Section]) -> String {
    let results = page.results;
    let mut md = format!(
        "# V&V run {}: {}\n\ncommit `{}` · tier {} · {} · {} · {} threads · {}\n\n",
        results.run_id,
        summary::verdict(results).text,
        results.commit,
        results.tier,
        results.date,
        results.machine,
        results.threads,
        format::seconds(results.wall_s),
    );
    md.push_str(&table(page.summaries));
    md.push_str(&failures(page.summaries));
    for s in sections {
        md.push_str(&section::markdown(*s, page));
    }
    md
}

/// The summary table, one row per case.
fn table(summaries: &[CaseSummary<'_>]) -> String {
    let mut md = String::from(
        "| case | variant | status | wall time | metrics passed | worst metric |\n|---|---|---|---:|---:|---|\n",
    );
    for s in summaries {
        let state = CaseState::of(s.case);
        let status = state.label().to_uppercase();
        let status = if state == CaseState::Pass {
            status
        } else {
            format!("**{status}**")
        };
        md.push_str(&format!(
            "| {} | {} | {status} | {} | {}/{} | {} |\n",
            format::markdown_cell(&s.case.id),
            format::markdown_cell(&s.case.variant),
            format::seconds(s.case.wall_s),
            s.passed,
            s.total,
            s.worst
                .map_or("—".to_string(), |m| format::markdown_cell(&worst_text(m))),
        ));
    }
    md
}

/// The cases that failed (known failures labelled so) or errored, each with its worst metric and
/// the first line of its message; nothing when all passed.
fn failures(summaries: &[CaseSummary<'_>]) -> String {
    let bad: Vec<&CaseSummary<'_>> = summaries
        .iter()
        .filter(|s| matches!(s.case.status, Status::Fail | Status::Error))
        .collect();
    if bad.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Failures\n\n");
    for s in bad {
        let c = s.case;
        let state = CaseState::of(c).label();
        let mut line = format!("- **{}** ({}) {state}", c.id, c.variant);
        if let Some(m) = s.worst {
            line.push_str(&match summary::ratio_text(m) {
                Some(ratio) => format!(
                    ": worst metric `{}` = {} vs {} ({ratio} tolerance)",
                    m.name,
                    format::num(m.value),
                    format::num(m.reference),
                ),
                None => format!(
                    ": worst metric `{}` = {}",
                    m.name,
                    summary::against_reference(m)
                ),
            });
        }
        if let Some(msg) = c.message.as_deref().filter(|m| !m.trim().is_empty()) {
            // A code span, so that chat renderers show `<tags>` in messages instead of eating them.
            let quoted = format::first_line(msg, MESSAGE_CHARS).replace('`', "'");
            line.push_str(&format!(": `{quoted}`"));
        }
        md.push_str(&line);
        md.push('\n');
    }
    md
}
