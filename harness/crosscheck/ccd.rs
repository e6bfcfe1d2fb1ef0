//! Our vertex-face continuous collision detection against ipctk's (issue 8).
//!
//! The queries are vertex-face CCD calls recorded from our own runs (a sphere impact and the
//! first contact of a beam drop test) plus constructed random ones
//! ([`super::ccd_queries`]). ipctk's Tight-Inclusion point-triangle CCD
//! (`references/crosscheck/ipctk_ccd.py`) is conservative: when it finds no impact there is
//! none, and a false impact can only be a near miss within its tolerance. So the check that
//! must hold is one-sided: no query where ipctk finds an impact in the step and we find none.
//! The other disagreements (we find an impact ipctk does not; both find one at different times)
//! are counted and their sizes shown, each with the smallest distance between the point and the
//! triangle over the step, computed here independently of both algorithms.
//!
//! Without the `python` feature the queries and ipctk's answers come from the cache; our side
//! always runs now.

mod compare;
mod distance;
mod report;

pub use compare::{compare, Agreement, Compared};
pub use distance::{distance_at, min_distance, point_triangle_distance, touch_level};
use report::{agreement_table, disagreement_table, toi_plot};

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use super::cache::{cache_path, obtain, Provenance};
use super::ccd_queries::{
    random_queries, read_queries, record_from_case, write_queries, CcdQuery, QuerySource,
};
use super::error::CrosscheckError;
use crate::results::{MaterialPlot, RecordTable};

/// The `crosscheck: { ccd: ... }` entry of a case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CcdSpec {
    /// ipctk's cached answers, in `references/crosscheck/cache/`.
    pub cache: String,
    /// The cached queries (binary, see `ccd_queries`), in the same folder.
    pub queries: String,
    /// Runs whose CCD calls are recorded when the queries are made afresh.
    pub record: Vec<RecordSpec>,
    /// Constructed random queries added to the recorded ones, and their seed.
    pub random: usize,
    /// Seed of the random queries' generator.
    pub seed: u64,
    /// Barycentric tolerance given to our CCD (the contact detection's).
    pub tolerance: f64,
    /// Tight-Inclusion's tolerance (distance) in ipctk.
    pub ipctk_tolerance: f64,
}

/// One recorded run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordSpec {
    /// A catalogue case file, relative to this case's file.
    pub case: PathBuf,
    /// Simulated time the run is cut at (s).
    pub end_time: f64,
    /// Record every n-th step.
    pub every: usize,
    /// Keep at most this many queries (evenly subsampled).
    pub max: usize,
    /// The label its queries carry.
    pub source: QuerySource,
}

/// FNV-1a over the bytes of the query file: ties a cached answer to its queries.
pub fn checksum(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The queries made afresh: the recorded runs, then the random ones.
pub fn fresh_queries(spec: &CcdSpec, case_dir: &Path) -> Result<Vec<CcdQuery>, CrosscheckError> {
    let mut queries = Vec::new();
    for r in &spec.record {
        let file = case_dir.join(&r.case);
        queries.extend(record_from_case(
            &file, r.end_time, r.every, r.max, r.source,
        )?);
    }
    queries.extend(random_queries(spec.random, spec.seed));
    Ok(queries)
}

/// The request to `ipctk_ccd.py` for the query file `file` (as the script will find it).
fn request(spec: &CcdSpec, file: &str, bytes: &[u8], count: usize) -> Value {
    json!({
        "queries_file": file,
        "count": count,
        "checksum": checksum(bytes),
        "tolerance": spec.ipctk_tolerance,
        "conservative_rescaling": 1.0,
    })
}

/// Writes the queries to the cache and ipctk's answer beside them (`crosscheck-refresh`).
pub fn refresh(spec: &CcdSpec, case_dir: &Path) -> Result<Provenance, CrosscheckError> {
    let queries = fresh_queries(spec, case_dir)?;
    let path = cache_path(&spec.queries);
    write_queries(&path, &queries)?;
    let bytes = std::fs::read(&path).map_err(|e| file_error(&path, e))?;
    let req = request(
        spec,
        &format!("cache/{}", spec.queries),
        &bytes,
        queries.len(),
    );
    super::cache::refresh("ipctk_ccd.py", &req, &cache_path(&spec.cache))
}

/// The measured quantities (metric `measure: { crosscheck: <name> }`).
pub const QUANTITIES: [&str; 10] = [
    "missed_impacts_raw",
    "missed_within_ipctk_tolerance",
    "missed_beyond_ipctk_tolerance",
    "starting_in_contact",
    "missed_impacts",
    "extra_impacts",
    "extra_impacts_beyond_ipctk_tolerance",
    "false_positive_rate",
    "largest_toi_difference",
    "queries",
];

/// Everything the case measured.
pub struct Outcome {
    /// Each quantity the metrics may measure, by name.
    pub quantities: std::collections::BTreeMap<String, f64>,
    /// Where the independent answer came from.
    pub provenance: Provenance,
    /// Lines describing the setup of both sides.
    pub setup: Vec<String>,
    /// Tables of the report.
    pub tables: Vec<RecordTable>,
    /// Plots of the report.
    pub plots: Vec<MaterialPlot>,
    /// What a reader should know.
    pub notes: Vec<String>,
}

/// Runs the cross-check: queries and ipctk's answers (fresh with Python, else cached), our CCD
/// on every query, the comparison.
pub fn run(spec: &CcdSpec, case_dir: &Path, scratch: &Path) -> Result<Outcome, CrosscheckError> {
    let (queries, answer, provenance) = if super::python::ENABLED {
        let queries = fresh_queries(spec, case_dir)?;
        std::fs::create_dir_all(scratch).map_err(|e| file_error(scratch, e))?;
        let file = scratch.join("ccd-queries.bin");
        write_queries(&file, &queries)?;
        let bytes = std::fs::read(&file).map_err(|e| file_error(&file, e))?;
        let req = request(spec, &file.display().to_string(), &bytes, queries.len());
        let (answer, p) = obtain("ipctk_ccd.py", &req, &cache_path(&spec.cache))?;
        (queries, answer, p)
    } else {
        let path = cache_path(&spec.queries);
        let queries = read_queries(&path)?;
        let bytes = std::fs::read(&path).map_err(|e| file_error(&path, e))?;
        let req = request(
            spec,
            &format!("cache/{}", spec.queries),
            &bytes,
            queries.len(),
        );
        let (answer, p) = obtain("ipctk_ccd.py", &req, &cache_path(&spec.cache))?;
        (queries, answer, p)
    };
    let compared = compare(&queries, &answer, spec.tolerance)?;
    let count = |a: Agreement| compared.iter().filter(|c| c.agreement == a).count();
    let largest_toi = compared
        .iter()
        .filter(|c| c.agreement == Agreement::BothHit)
        .filter_map(|c| Some((c.ours? - c.theirs?).abs()))
        .fold(0.0, f64::max);
    let mut q = std::collections::BTreeMap::new();
    // A query ipctk finds an impact in and we do not is a miss of ours only if the point really
    // reaches the triangle: its smallest distance over the step is at the rounding level of its
    // coordinates. A positive distance up to ipctk's tolerance is Tight-Inclusion's documented
    // false positive (conservative: a near miss within `tolerance` may be reported as an impact).
    let missed: Vec<(&Compared, f64)> = compared
        .iter()
        .zip(&queries)
        .filter(|(c, _)| c.agreement == Agreement::Missed)
        .map(|(c, q)| (c, touch_level(q)))
        .collect();
    q.insert(
        "missed_impacts".to_string(),
        missed.iter().filter(|(c, t)| c.min_distance <= *t).count() as f64,
    );
    q.insert("missed_impacts_raw".to_string(), missed.len() as f64);
    q.insert(
        "missed_within_ipctk_tolerance".to_string(),
        missed
            .iter()
            .filter(|(c, t)| c.min_distance > *t && c.min_distance <= spec.ipctk_tolerance)
            .count() as f64,
    );
    q.insert(
        "missed_beyond_ipctk_tolerance".to_string(),
        missed
            .iter()
            .filter(|(c, _)| c.min_distance > spec.ipctk_tolerance)
            .count() as f64,
    );
    q.insert("extra_impacts".to_string(), count(Agreement::Extra) as f64);
    q.insert(
        "extra_impacts_beyond_ipctk_tolerance".to_string(),
        compared
            .iter()
            .filter(|c| c.agreement == Agreement::Extra && c.min_distance > spec.ipctk_tolerance)
            .count() as f64,
    );
    // Our false positives against ipctk: impacts we report where ipctk (conservative) finds
    // none, over the queries where it finds none (those starting in contact left out).
    let ipctk_none = count(Agreement::BothNone) + count(Agreement::Extra);
    q.insert(
        "false_positive_rate".to_string(),
        if ipctk_none > 0 {
            count(Agreement::Extra) as f64 / ipctk_none as f64
        } else {
            0.0
        },
    );
    q.insert("largest_toi_difference".to_string(), largest_toi);
    q.insert("queries".to_string(), queries.len() as f64);
    q.insert(
        "starting_in_contact".to_string(),
        count(Agreement::StartsInContact) as f64,
    );
    let setup = vec![
        provenance.line(),
        format!(
            "{} queries; ipctk TightInclusionCCD, tolerance {:e}, conservative rescaling 1 (the \
             first time of contact), {:.2} s; ours: vertex_face_ccd with barycentric tolerance {:e}",
            queries.len(),
            spec.ipctk_tolerance,
            answer["seconds"].as_f64().unwrap_or(f64::NAN),
            spec.tolerance
        ),
    ];
    Ok(Outcome {
        quantities: q,
        provenance,
        setup,
        tables: vec![
            agreement_table(&compared),
            disagreement_table(&compared, &queries),
        ],
        plots: vec![toi_plot(&compared)],
        notes: vec![],
    })
}

/// A file of the cross-check that cannot be read or written.
fn file_error(path: &Path, e: std::io::Error) -> CrosscheckError {
    CrosscheckError::File {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksum_is_fnv1a() {
        // FNV-1a 64 of "a" (Fowler, Noll & Vo test vector).
        assert_eq!(checksum(b"a"), "af63dc4c8601ec8c");
    }
}
