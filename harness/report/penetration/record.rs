//! What a case that remeshes records for its part of the report ([`PenetrationRecord`], under
//! the key [`KEY`] of its result): the remeshing table and the stress near the tip read from
//! the files the run wrote into the case's folder, and the names of its mesh pictures, which the
//! report reads from there when it draws them.

use std::path::Path;

use impact_solver::remesh::{SectionFrame, NEAR_TIP_CSV_HEADER, REMESHING_CSV_HEADER};
use serde::{Deserialize, Serialize};

use crate::results::{case_dir, CaseResult};

/// The key of the record in a case's result.
pub const KEY: &str = "penetration";

/// One remeshing, as the table shows it (from `<stem>_remeshing.csv`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RemeshRow {
    /// Time of the remeshing (s).
    pub time: f64,
    /// Elements of the model before and after.
    pub elements: [usize; 2],
    /// The largest collapse ratio (thesis 8.1) before and after.
    #[serde(deserialize_with = "crate::results::lenient::vec")]
    pub worst_collapse: Vec<f64>,
    /// Jump in kinetic energy, after minus before (J).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub kinetic_jump: f64,
    /// Jump in stored elastic energy (J; 0 for bodies without a potential).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub stored_jump: f64,
    /// Jump in kinetic plus stored energy (J).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub total_energy_jump: f64,
    /// Norm of the momentum jump (kg m/s).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub momentum_jump: f64,
    /// Mass that selective mass scaling put on the new mesh's nodes (kg; 0 without it).
    #[serde(default, deserialize_with = "crate::results::lenient::f64")]
    pub added_mass: f64,
    /// The kinetic energy the velocity transfer lost and the region's nodes were given back
    /// (J; already in the jumps).
    #[serde(default, deserialize_with = "crate::results::lenient::f64")]
    pub kinetic_restored: f64,
}

/// The stress near the tip at one state (a row of `<stem>_near_tip.csv`; see
/// `impact_solver::remesh::NearTipStress`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NearTipPoint {
    /// The remeshing whose window the row is in (from 1).
    pub remeshing: usize,
    /// Steps from it: negative before, 0 the transferred state, positive after.
    pub offset: i64,
    /// Time (s).
    pub time: f64,
    /// Elements measured.
    pub elements: usize,
    /// Their largest von Mises stress (Pa).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub max_von_mises: f64,
    /// Their volume-weighted mean von Mises stress (Pa).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub mean_von_mises: f64,
    /// Their volume-weighted mean pressure (Pa).
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub mean_pressure: f64,
}

/// What a case that remeshes records (see the module's documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PenetrationRecord {
    /// Stem of the run's files in the case's folder (`run`).
    pub stem: String,
    /// Every remeshing, in time order.
    pub remeshings: Vec<RemeshRow>,
    /// The stress near the tip around each remeshing; empty without `near_tip`.
    #[serde(default)]
    pub near_tip: Vec<NearTipPoint>,
    /// File names of the mesh pictures in the case's folder, in the order taken; empty
    /// without `section`.
    #[serde(default)]
    pub pictures: Vec<String>,
}

/// Why a remeshing record of a run does not read: each message names the file and the line.
#[derive(Debug, thiserror::Error)]
pub enum RecordFileError {
    /// The file cannot be read.
    #[error("{path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// The file's header is not the solver's.
    #[error("{path}: the header is not `{header}` (written by another version?)")]
    Header {
        /// The file.
        path: String,
        /// The header expected.
        header: String,
    },
    /// A value that is not a number.
    #[error("{path} line {line}: {source}")]
    Number {
        /// The file.
        path: String,
        /// The line (1-based, the header is line 1).
        line: usize,
        /// The number reader's error.
        source: std::num::ParseFloatError,
    },
    /// A row of the wrong width.
    #[error("{path} line {line}: {values} values for {columns} columns")]
    Width {
        /// The file.
        path: String,
        /// The line (1-based, the header is line 1).
        line: usize,
        /// Values in the row.
        values: usize,
        /// Columns of the header.
        columns: usize,
    },
}

/// The rows of a CSV whose header must be `header`, as numbers by column name; an empty cell is
/// a missing value, NaN (the near-tip stresses of a step with no element within the radius),
/// which the plots leave out.
fn read_csv(path: &Path, header: &str) -> Result<Vec<Vec<f64>>, RecordFileError> {
    let file = || path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| RecordFileError::Read {
        path: file(),
        message: e.to_string(),
    })?;
    let mut lines = text.lines();
    if lines.next() != Some(header) {
        return Err(RecordFileError::Header {
            path: file(),
            header: header.into(),
        });
    }
    let columns = header.split(',').count();
    lines
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let row: Vec<f64> = l
                .split(',')
                .map(|v| match v.trim() {
                    "" => Ok(f64::NAN),
                    v => v.parse::<f64>(),
                })
                .collect::<Result<_, _>>()
                .map_err(|source| RecordFileError::Number {
                    path: file(),
                    line: i + 2,
                    source,
                })?;
            if row.len() != columns {
                return Err(RecordFileError::Width {
                    path: file(),
                    line: i + 2,
                    values: row.len(),
                    columns,
                });
            }
            Ok(row)
        })
        .collect()
}

/// The index of column `name` of `header`.
fn col(header: &str, name: &str) -> usize {
    header
        .split(',')
        .position(|c| c == name)
        .expect("the names asked for are columns of the solver's header")
}

/// The remeshings of `<stem>_remeshing.csv` ([`REMESHING_CSV_HEADER`]).
pub fn read_remeshings(path: &Path) -> Result<Vec<RemeshRow>, RecordFileError> {
    let h = REMESHING_CSV_HEADER;
    let c = |name| col(h, name);
    Ok(read_csv(path, h)?
        .into_iter()
        .map(|r| RemeshRow {
            time: r[c("time")],
            elements: [
                r[c("elements_before")] as usize,
                r[c("elements_after")] as usize,
            ],
            worst_collapse: vec![r[c("worst_collapse_before")], r[c("worst_collapse_after")]],
            kinetic_jump: r[c("kinetic_after")] - r[c("kinetic_before")],
            stored_jump: r[c("stored_after")] - r[c("stored_before")],
            total_energy_jump: r[c("total_energy_jump")],
            momentum_jump: r[c("momentum_jump")],
            added_mass: r[c("added_mass")],
            kinetic_restored: r[c("kinetic_restored")],
        })
        .collect())
}

/// The rows of `<stem>_near_tip.csv` ([`NEAR_TIP_CSV_HEADER`]).
pub fn read_near_tip(path: &Path) -> Result<Vec<NearTipPoint>, RecordFileError> {
    let h = NEAR_TIP_CSV_HEADER;
    let c = |name| col(h, name);
    Ok(read_csv(path, h)?
        .into_iter()
        .map(|r| NearTipPoint {
            remeshing: r[c("remeshing")] as usize,
            offset: r[c("offset")] as i64,
            time: r[c("time")],
            elements: r[c("elements")] as usize,
            max_von_mises: r[c("max_von_mises")],
            mean_von_mises: r[c("mean_von_mises")],
            mean_pressure: r[c("mean_pressure")],
        })
        .collect())
}

/// The record of the run whose files, stem `stem`, are in `dir` (a case's folder): `None`
/// when it wrote no `<stem>_remeshing.csv` (it did not remesh), an error when a file does not
/// read.
pub fn read_record(dir: &Path, stem: &str) -> Result<Option<PenetrationRecord>, RecordFileError> {
    let remeshing = dir.join(format!("{stem}_remeshing.csv"));
    if !remeshing.is_file() {
        return Ok(None);
    }
    let near = dir.join(format!("{stem}_near_tip.csv"));
    let near_tip = if near.is_file() {
        read_near_tip(&near)?
    } else {
        Vec::new()
    };
    let pictures = (0..)
        .map(|k| format!("{stem}_mesh_{k}.json"))
        .take_while(|name| dir.join(name).is_file())
        .collect();
    Ok(Some(PenetrationRecord {
        stem: stem.to_string(),
        remeshings: read_remeshings(&remeshing)?,
        near_tip,
        pictures,
    }))
}

/// Stores the record of the run with stem `stem` in `case_dir` into `result`, if it remeshed;
/// a file that does not read is said on stderr and leaves the record out (the section is a
/// by-product: it does not fail the case).
pub fn record(result: &mut CaseResult, case_dir: &Path, stem: &str) {
    match read_record(case_dir, stem) {
        Ok(Some(r)) => result.set_record(KEY, &r),
        Ok(None) => {}
        Err(e) => eprintln!("{}: no penetration record: {e}", result.id),
    }
}

/// The mesh pictures of a case's record, read from the case's folder in `run_dir`; a picture
/// that does not read is left out.
pub fn load_pictures(
    run_dir: &Path,
    case: &CaseResult,
    record: &PenetrationRecord,
) -> Vec<SectionFrame> {
    let dir = case_dir(run_dir, &case.id);
    record
        .pictures
        .iter()
        .filter_map(|name| {
            let text = std::fs::read_to_string(dir.join(name)).ok()?;
            serde_json::from_str(&text).ok()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step with no element within the radius has empty stress cells (the solver's
    /// `near_tip.rs`); they read as NaN, beside the numbers of the other rows.
    #[test]
    fn empty_near_tip_cells_read_as_missing() {
        let dir = tempfile::tempdir().expect("a scratch folder");
        let path = dir.path().join("s_near_tip.csv");
        let text =
            format!("{NEAR_TIP_CSV_HEADER}\n1,-1,36,1.05e-4,0,,,\n1,0,36,1.05e-4,3,2e5,1e5,-4e4\n");
        std::fs::write(&path, text).expect("written");
        let rows = read_near_tip(&path).expect("read");
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[0].offset, rows[0].elements), (-1, 0));
        assert!(rows[0].max_von_mises.is_nan() && rows[0].mean_pressure.is_nan());
        assert_eq!(
            [
                rows[1].max_von_mises,
                rows[1].mean_von_mises,
                rows[1].mean_pressure
            ],
            [2e5, 1e5, -4e4]
        );
    }
}
