//! The sections of the report that the kinds of case contribute (contact algorithms, concrete
//! material, cross-checks, beam failure modes): one trait, a list given to the report
//! (`crate::registry::SECTIONS`), and the scaffold they share, so that each section writes its
//! content and nothing else: the `<section>` with its anchor and title, each case's heading
//! with its status and the way back to the case, and the link from the case's own section.

use std::cell::RefCell;
use std::path::Path;

use super::blocks::{element, state_badge};
use super::format;
use super::summary::{CaseState, CaseSummary};
use crate::results::{CaseResult, RecordError, RunResults};
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
    /// The records that did not read while the current section was written
    /// ([`Page::record`]); [`html`] and [`markdown`] show them in that section.
    pending: RefCell<Vec<RecordError>>,
    /// Every record that did not read on the page, each once: the run's warnings.
    failed: RefCell<Vec<RecordError>>,
}

impl<'a> Page<'a> {
    /// The page of `results` written into `run_dir`.
    pub fn new(
        results: &'a RunResults,
        summaries: &'a [CaseSummary<'a>],
        run_dir: &'a Path,
    ) -> Self {
        Self {
            results,
            summaries,
            run_dir,
            pending: RefCell::new(Vec::new()),
            failed: RefCell::new(Vec::new()),
        }
    }

    /// The record `case`'s kind stored under `key`: `None` when there is none, and also when it
    /// does not read, which the section being written then shows as an error.
    pub fn record<T: DeserializeOwned>(&self, case: &CaseResult, key: &str) -> Option<T> {
        self.read(case.read_record(key))
    }

    /// A record read by the section itself (from a file of the run): its error, if any, is
    /// shown in the section being written, as [`Page::record`] does.
    pub fn read<T>(&self, record: Result<Option<T>, RecordError>) -> Option<T> {
        record.unwrap_or_else(|e| {
            let mut failed = self.failed.borrow_mut();
            if !failed.contains(&e) {
                failed.push(e.clone());
            }
            let mut pending = self.pending.borrow_mut();
            if !pending.contains(&e) {
                pending.push(e);
            }
            None
        })
    }

    /// Every record that did not read on the page so far, each once.
    pub fn record_errors(&self) -> Vec<RecordError> {
        self.failed.borrow().clone()
    }

    /// The errors of the section just written, leaving none pending.
    fn take_pending(&self) -> Vec<RecordError> {
        std::mem::take(&mut *self.pending.borrow_mut())
    }
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
        .filter_map(|s| Some((s, page.record(s.case, key)?)))
        .collect()
}

/// The section on the page: its anchor, title and content, after an error block for each record
/// of its cases that did not read; empty when it has none of either.
pub fn html(section: &dyn Section, page: &Page<'_>) -> String {
    page.take_pending();
    let body = section.html(page);
    let errors: String = page
        .take_pending()
        .iter()
        .map(|e| {
            element(
                "div",
                "callout error",
                &format!(
                    "<div class=\"callout-title\">Record of {} not shown</div>\n{}",
                    format::html(&e.case),
                    element("p", "", &format::html(&e.to_string()))
                ),
            )
        })
        .collect();
    if body.is_none() && errors.is_empty() {
        return String::new();
    }
    format!(
        "<section id=\"{}\">\n<h2>{}</h2>\n{errors}{}</section>\n",
        section.anchor(),
        format::html(section.title()),
        body.unwrap_or_default()
    )
}

/// The section in `summary.md`, after a line for each record of its cases that did not read;
/// empty when it has none of either.
pub fn markdown(section: &dyn Section, page: &Page<'_>) -> String {
    page.take_pending();
    let body = section.markdown(page);
    let errors: String = page
        .take_pending()
        .iter()
        .map(|e| format!("**Error:** {}\n\n", format::markdown_cell(&e.to_string())))
        .collect();
    if body.is_none() && errors.is_empty() {
        return String::new();
    }
    format!(
        "\n## {}\n\n{errors}{}",
        section.title(),
        body.unwrap_or_default()
    )
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
