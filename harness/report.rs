//! The report of a run: a self-contained `index.html` (summary, per-case metrics, plots, sweep
//! diagrams and trends), a `summary.md` to paste into a chat, and `results.json` for scripts;
//! plus the `reports/history.jsonl` file the trends are read from.
//!
//! The page is plain HTML with inline CSS and inline SVG (drawn with plotters' SVG backend), so
//! it opens from a CI artifact or a mail attachment without network access or fonts.

mod axis;
pub mod beam;
pub mod blocks;
pub(crate) mod diagrams;
pub mod format;
mod history;
mod html;
mod markdown;
pub mod penetration;
pub mod plot;
pub mod records;
pub mod section;
pub mod summary;
pub mod text_fit;

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::results::{HistoryRecord, RunResults};
use section::{Page, Section};

pub use history::{append_history, read_history};
pub use plot::render_plot;

/// Writes `<dir>/index.html` (one self-contained page), `<dir>/summary.md`, and
/// `<dir>/results.json`, creating `dir` if needed; returns the index path.
///
/// `history` should already contain this run's records (see [`RunResults::history_records`]),
/// so that each trend ends with the run being reported. `sections` are the sections the kinds
/// of case contribute (`crate::registry::SECTIONS`), in page order.
pub fn write_report(
    dir: &Path,
    results: &RunResults,
    history: &[HistoryRecord],
    sections: &[&dyn Section],
) -> io::Result<PathBuf> {
    fs::create_dir_all(dir)?;
    let json = serde_json::to_string_pretty(results).map_err(io::Error::other)?;
    fs::write(dir.join("results.json"), json + "\n")?;
    let summaries = summary::summaries(results);
    let page = Page::new(results, &summaries, dir);
    fs::write(dir.join("summary.md"), markdown::summary(&page, sections))?;
    let index = dir.join("index.html");
    fs::write(&index, html::page(&page, history, sections))?;
    // The page shows each in its section; the run's log says that the page has them.
    for e in page.record_errors() {
        eprintln!("warning: {e}; the report shows the error in its section");
    }
    Ok(index)
}
