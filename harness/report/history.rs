//! `reports/history.jsonl`: one JSON object per case per run, appended by every run, read back
//! for the trend plots. JSON lines keep appends cheap and let one bad line cost only itself.

use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

use crate::results::HistoryRecord;

/// Reads the history file. A missing file is an empty history (first run); a line that does not
/// parse is skipped with a warning naming its line number, so that one truncated write (a run
/// killed mid-append) does not hide every other run's trend.
pub fn read_history(path: &Path) -> io::Result<Vec<HistoryRecord>> {
    let bytes = match fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    Ok(parse_lines(path, &bytes))
}

/// Parses each non-blank line, warning on stderr about the ones that are not a record.
fn parse_lines(path: &Path, bytes: &[u8]) -> Vec<HistoryRecord> {
    let mut records = Vec::new();
    for (index, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        match serde_json::from_slice::<HistoryRecord>(line) {
            Ok(record) => records.push(record),
            Err(e) => eprintln!(
                "warning: {}:{}: skipping malformed history line: {e}",
                path.display(),
                index + 1
            ),
        }
    }
    records
}

/// Appends `records`, one JSON object per line, creating the file and its folder if needed.
///
/// Non-finite metric values are left out of the line: JSON has no NaN or infinity (serde_json
/// would write `null`, which then fails to read back as a number and would lose the whole line);
/// a missing metric shows as a gap in the trend, which is what a NaN would have shown anyway.
/// A non-finite wall time (never measured) is written as 0 for the same reason.
pub fn append_history(path: &Path, records: &[HistoryRecord]) -> io::Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        fs::create_dir_all(parent)?;
    }
    let mut text = String::new();
    for record in records {
        text.push_str(&serde_json::to_string(&finite_only(record)).map_err(io::Error::other)?);
        text.push('\n');
    }
    // One write call per run, so that concurrent runs do not interleave within a line.
    let mut file = OpenOptions::new().create(true).append(true).open(path)?;
    file.write_all(text.as_bytes())
}

/// A copy of `record` without its non-finite metric values.
fn finite_only(record: &HistoryRecord) -> HistoryRecord {
    let mut record = record.clone();
    record.metrics.retain(|_, v| v.is_finite());
    if !record.wall_s.is_finite() {
        record.wall_s = 0.0;
    }
    record
}
