//! The sections of the report that the kinds of case contribute (contact algorithms, concrete
//! material, cross-checks, beam failure modes): one trait, a list given to the report
//! (`crate::registry::SECTIONS`), and the scaffold they share, so that each section writes its
//! content and nothing else: the `<section>` with its anchor and title, each case's heading
//! with its status and the way back to the case, and the link from the case's own section.

use std::path::Path;

use super::blocks::{element, state_badge};
use super::format;
use super::summary::{CaseState, CaseSummary};
use crate::results::RunResults;
use serde::de::DeserializeOwned;

/// What a section sees of the run: its results, the summaries of its cases (with their
/// anchors), and the run folder (for records the kinds wrote beside the results).
pub struct Page<'a> {
    /// The results of every case of the run.
    pub results: &'a RunResults,
    /// One summary per case, in run order, with its anchor.
    pub summaries: &'a [CaseSummary<'a>],
    /// The run's folder.
    pub run_dir: &'a Path,
}

/// A section of the page and of `summary.md`.
pub trait Section: Sync {
    /// Its fragment id on the page.
    fn anchor(&self) -> &'static str;

    /// Its title (`<h2>` on the page, `##` in the summary).
    fn title(&self) -> &'static str;

    /// Its content on the page (HTML, after the title), or `None` when the run has nothing for
    /// it: then the section is left out.
    fn html(&self, page: &Page<'_>) -> Option<String>;

    /// What it adds to a case's own section (a link to the case's part, pictures); empty by
    /// default.
    fn in_case(&self, _case: &CaseSummary<'_>, _page: &Page<'_>) -> String {
        String::new()
    }

    /// Its content in `summary.md` (Markdown, after the title), or `None` for nothing.
    fn markdown(&self, _page: &Page<'_>) -> Option<String> {
        None
    }
}

/// The cases of the run whose kind stored a record under `key`, with their summaries and the
/// record read back, in run order.
pub fn cases_with<'p, T: DeserializeOwned>(
    page: &'p Page<'p>,
    key: &str,
) -> Vec<(&'p CaseSummary<'p>, T)> {
    page.summaries
        .iter()
        .filter_map(|s| Some((s, s.case.record(key)?)))
        .collect()
}

/// The section on the page: its anchor, title and content; empty when it has none.
pub fn html(section: &dyn Section, page: &Page<'_>) -> String {
    section.html(page).map_or_else(String::new, |body| {
        format!(
            "<section id=\"{}\">\n<h2>{}</h2>\n{body}</section>\n",
            section.anchor(),
            format::html(section.title())
        )
    })
}

/// The section in `summary.md`; empty when it has nothing.
pub fn markdown(section: &dyn Section, page: &Page<'_>) -> String {
    section.markdown(page).map_or_else(String::new, |body| {
        format!("\n## {}\n\n{body}", section.title())
    })
}

/// The fragment id of a case's part of a section.
pub fn part_anchor(section: &dyn Section, case: &CaseSummary<'_>) -> String {
    format!("{}-{}", section.anchor(), case.anchor)
}

/// The heading of a case's part of a section: its status, id, an optional badge (`extra`,
/// HTML) and the way back to the case's metrics, then its description.
pub fn part_heading(section: &dyn Section, case: &CaseSummary<'_>, extra: &str) -> String {
    let c = case.case;
    let mut html = format!(
        "<h3 id=\"{}\">{} {}{extra} <a href=\"#{}\">metrics and trend</a></h3>\n",
        part_anchor(section, case),
        state_badge(CaseState::of(c)),
        format::html(&c.id),
        case.anchor
    );
    if !c.description.is_empty() {
        html.push_str(&element("p", "description", &format::html(&c.description)));
    }
    html
}

/// The line in a case's own section that leads to its part of `section`: `what` (plain text)
/// says what the reader finds there.
pub fn part_link(section: &dyn Section, case: &CaseSummary<'_>, what: &str) -> String {
    element(
        "p",
        "",
        &format!(
            "{}: <a href=\"#{}\">{}</a>.",
            format::html(what),
            part_anchor(section, case),
            format::html(section.title())
        ),
    )
}
