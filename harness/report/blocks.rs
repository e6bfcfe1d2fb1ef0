//! The building blocks of the page, shared by the report and the sections the kinds of case
//! contribute: elements, badges, tables, figures and notes. Text goes through
//! [`format::html`]; each helper says whether it takes escaped HTML or plain text.

use super::format;
use super::summary::{status_name, CaseState};
use crate::results::Status;

/// `<tag class="class">inner</tag>`; `inner` must already be HTML.
pub fn element(tag: &str, class: &str, inner: &str) -> String {
    if class.is_empty() {
        format!("<{tag}>{inner}</{tag}>\n")
    } else {
        format!("<{tag} class=\"{class}\">{inner}</{tag}>\n")
    }
}

/// A coloured status badge.
pub fn badge(status: Status) -> String {
    let name = status_name(status);
    format!("<span class=\"badge {name}\">{name}</span>")
}

/// A coloured badge of a case's state: a status, or `known failure` in amber.
pub fn state_badge(state: CaseState) -> String {
    format!(
        "<span class=\"badge {}\">{}</span>",
        state.class(),
        state.label()
    )
}

/// A table cell: escaped HTML content, or a number (right-aligned, tabular figures).
pub enum Cell {
    /// HTML content, already escaped, left-aligned.
    Html(String),
    /// A number already formatted, right-aligned in tabular figures.
    Num(String),
}

/// A cell showing plain `text`.
pub fn text(text: &str) -> Cell {
    Cell::Html(format::html(text))
}

/// A cell showing the number `v`.
pub fn number(v: f64) -> Cell {
    Cell::Num(format::num(v))
}

/// A table row with an optional CSS class (`bad` for failing rows, `known` for known failures).
pub struct Row {
    /// CSS class of the row (`bad` for a failing row, `known` for a known failure), empty for
    /// none.
    pub class: &'static str,
    /// The row's cells, in column order.
    pub cells: Vec<Cell>,
}

impl Row {
    /// A row of `cells` without a class.
    pub fn new(cells: Vec<Cell>) -> Self {
        Row { class: "", cells }
    }
}

/// A table with a header row of plain-text titles; wrapped so that wide tables scroll instead of
/// widening the page.
pub fn table(head: &[String], rows: &[Row]) -> String {
    let head: String = head
        .iter()
        .map(|h| format!("<th>{}</th>", format::html(h)))
        .collect();
    let body: String = rows.iter().map(row_html).collect();
    format!(
        "<div class=\"table-wrap\"><table>\n<thead><tr>{head}</tr></thead>\n<tbody>\n{body}</tbody>\n</table></div>\n"
    )
}

/// One `<tr>`.
pub fn row_html(row: &Row) -> String {
    let cells: String = row
        .cells
        .iter()
        .map(|c| match c {
            Cell::Html(h) => format!("<td>{h}</td>"),
            Cell::Num(n) => format!("<td class=\"num\">{n}</td>"),
        })
        .collect();
    if row.class.is_empty() {
        format!("<tr>{cells}</tr>\n")
    } else {
        format!("<tr class=\"{}\">{cells}</tr>\n", row.class)
    }
}

/// Owned header titles from string literals.
pub fn titles(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// SVG plots side by side, wrapping to the next line when the page is narrow; `class` is
/// `plots`, or `plots small` for the trend plots.
pub fn plots(class: &str, svgs: impl IntoIterator<Item = String>) -> String {
    let figures: String = svgs
        .into_iter()
        .map(|svg| element("figure", "", &svg))
        .collect();
    element("div", class, &figures)
}

/// A bulleted list of plain-text items; empty without items.
pub fn list<'a>(items: impl IntoIterator<Item = &'a String>) -> String {
    let items: String = items
        .into_iter()
        .map(|i| format!("<li>{}</li>", format::html(i)))
        .collect();
    if items.is_empty() {
        String::new()
    } else {
        element("ul", "", &items)
    }
}

/// A greyed note, for absent content.
pub fn note(text: &str) -> String {
    element("p", "muted", &format::html(text))
}
