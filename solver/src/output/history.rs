//! Time histories (energies, probe displacements, contact forces) as plain CSV, so that any
//! plotting tool can read them and a report can be rebuilt without rerunning the solver.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Result, SolverError};

/// A table of time histories: one row per recorded instant, one column per named quantity.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryTable {
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl HistoryTable {
    /// An empty table with the given column names (any text: names needing it are quoted in
    /// the CSV).
    pub fn new(columns: Vec<String>) -> Self {
        Self {
            columns,
            rows: Vec::new(),
        }
    }

    /// Appends one instant.
    ///
    /// # Panics
    /// If `row` does not have one value per column: a ragged table is a bug in the caller,
    /// not a condition a run can recover from.
    pub fn push(&mut self, row: Vec<f64>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "history row has {} values but the table has {} columns {:?}",
            row.len(),
            self.columns.len(),
            self.columns
        );
        self.rows.push(row);
    }

    /// The column names, in file order.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// The recorded rows, in the order they were pushed.
    pub fn rows(&self) -> &[Vec<f64>] {
        &self.rows
    }

    /// All values of the column called `name`, or `None` if there is no such column.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let index = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|row| row[index]).collect())
    }

    /// Writes the header line and then one line per row, creating parent directories.
    ///
    /// Every value is printed in its shortest form that parses back to the same `f64`, so
    /// [`HistoryTable::read_csv`] restores the table bit for bit (NaN payloads and the sign
    /// of zero aside).
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let mut text = String::new();
        push_header(&mut text, &self.columns);
        for row in &self.rows {
            push_row(&mut text, row);
        }
        create_parent(path)?;
        std::fs::write(path, text).map_err(|source| SolverError::Write {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Reads a table written by [`HistoryTable::write_csv`] (or any CSV with a header line and
    /// numeric rows of the same width).
    pub fn read_csv(path: &Path) -> Result<Self> {
        let invalid = |message: String| SolverError::InvalidScene {
            entity: format!("history file `{}`", path.display()),
            message,
        };
        let text =
            std::fs::read_to_string(path).map_err(|e| invalid(format!("cannot read it: {e}")))?;
        if text.trim().is_empty() {
            return Err(invalid("the file is empty; expected a header line".into()));
        }
        let (columns, body) = split_header(&text).map_err(|e| invalid(e.to_string()))?;
        let mut table = Self::new(columns);
        let lines = body.lines().filter(|line| !line.trim().is_empty());
        for (i, line) in lines.enumerate() {
            let row = line
                .split(',')
                .map(|field| field.trim().parse::<f64>())
                .collect::<std::result::Result<Vec<f64>, _>>()
                .map_err(|e| invalid(format!("data row {}: {e}", i + 1)))?;
            if row.len() != table.columns.len() {
                return Err(invalid(format!(
                    "data row {} has {} values but the header names {} columns",
                    i + 1,
                    row.len(),
                    table.columns.len()
                )));
            }
            table.rows.push(row);
        }
        Ok(table)
    }
}

/// The header line of a history CSV: the column names, quoted where needed.
fn push_header(text: &mut String, columns: &[String]) {
    let header: Vec<String> = columns.iter().map(|c| quote_field(c)).collect();
    text.push_str(&header.join(","));
    text.push('\n');
}

/// One data line of a history CSV.
fn push_row(text: &mut String, row: &[f64]) {
    for (i, &value) in row.iter().enumerate() {
        if i > 0 {
            text.push(',');
        }
        write_f64(text, value);
    }
    text.push('\n');
}

/// A history CSV written as the rows come, in the format of [`HistoryTable::write_csv`]: rows are
/// buffered and flushed at least every [`HistoryStream::FLUSH_EVERY`] of wall time (and whole
/// rows only), so a run that is killed outright still leaves every row up to the last flush.
#[derive(Debug)]
pub struct HistoryStream {
    path: std::path::PathBuf,
    writer: std::io::BufWriter<std::fs::File>,
    last_flush: std::time::Instant,
    line: String,
}

impl HistoryStream {
    /// Wall time between flushes.
    pub const FLUSH_EVERY: std::time::Duration = std::time::Duration::from_secs(2);

    /// Creates (or truncates) `path` and writes the header line.
    pub fn create(path: &Path, columns: &[String]) -> Result<Self> {
        create_parent(path)?;
        let io = |source| SolverError::Write {
            path: path.to_path_buf(),
            source,
        };
        let file = std::fs::File::create(path).map_err(io)?;
        let mut stream = Self {
            path: path.to_path_buf(),
            writer: std::io::BufWriter::new(file),
            last_flush: std::time::Instant::now(),
            line: String::new(),
        };
        push_header(&mut stream.line, columns);
        stream.write_line()?;
        stream.flush()?;
        Ok(stream)
    }

    /// Appends one row; flushes if the last flush is older than [`Self::FLUSH_EVERY`].
    pub fn append(&mut self, row: &[f64]) -> Result<()> {
        push_row(&mut self.line, row);
        self.write_line()?;
        if self.last_flush.elapsed() >= Self::FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes out everything buffered.
    pub fn flush(&mut self) -> Result<()> {
        use std::io::Write as _;
        self.last_flush = std::time::Instant::now();
        self.writer.flush().map_err(|source| SolverError::Write {
            path: self.path.clone(),
            source,
        })
    }

    fn write_line(&mut self) -> Result<()> {
        use std::io::Write as _;
        let result = self.writer.write_all(self.line.as_bytes());
        self.line.clear();
        result.map_err(|source| SolverError::Write {
            path: self.path.clone(),
            source,
        })
    }
}

/// Appends the shortest text that parses back to `value`: plain decimals where they are short,
/// exponent form for very large or small magnitudes (plain `{}` would spell 1e-300 with 300
/// zeros). Both forms are shortest round-trip in Rust's formatter.
pub(crate) fn write_f64(out: &mut String, value: f64) {
    let magnitude = value.abs();
    if value == 0.0 || !value.is_finite() || (1e-4..1e15).contains(&magnitude) {
        let _ = write!(out, "{value}");
    } else {
        let _ = write!(out, "{value:e}");
    }
}

/// Creates the directory that will hold `path`, reporting failures against `path` itself.
pub(crate) fn create_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|source| SolverError::Write {
                path: path.to_path_buf(),
                source,
            })
        }
        _ => Ok(()),
    }
}

/// RFC 4180 quoting, only where a name would otherwise break the line apart.
fn quote_field(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) || name.trim() != name {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_string()
    }
}

/// Why a history header does not read (the caller names the file).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum HeaderError {
    /// A quoted column name without its closing quote.
    #[error("unterminated quoted column name in the header")]
    Unterminated,
    /// Something other than a comma or the line's end after a quoted name.
    #[error("unexpected `{0}` after a quoted column name")]
    AfterQuote(char),
}

/// Splits the header line off `text`, undoing [`quote_field`]; returns the names and the rest.
fn split_header(text: &str) -> std::result::Result<(Vec<String>, &str), HeaderError> {
    let mut names = Vec::new();
    let mut chars = text.char_indices().peekable();
    loop {
        let mut name = String::new();
        if matches!(chars.peek(), Some((_, '"'))) {
            chars.next();
            loop {
                match chars.next() {
                    Some((_, '"')) if matches!(chars.peek(), Some((_, '"'))) => {
                        chars.next();
                        name.push('"');
                    }
                    Some((_, '"')) => {
                        // Tolerate blanks and a CRLF line end after the closing quote.
                        while matches!(chars.peek(), Some((_, ' ' | '\t' | '\r'))) {
                            chars.next();
                        }
                        break;
                    }
                    Some((_, c)) => name.push(c),
                    None => return Err(HeaderError::Unterminated),
                }
            }
        } else {
            while let Some(&(_, c)) = chars.peek() {
                if matches!(c, ',' | '\n') {
                    break;
                }
                name.push(c);
                chars.next();
            }
            name = name.trim().to_string();
        }
        names.push(name);
        match chars.next() {
            Some((_, ',')) => continue,
            Some((i, '\n')) => return Ok((names, &text[i + 1..])),
            None => return Ok((names, "")),
            Some((_, c)) => return Err(HeaderError::AfterQuote(c)),
        }
    }
}
