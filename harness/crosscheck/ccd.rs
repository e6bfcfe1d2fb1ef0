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

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use super::cache::{cache_path, obtain, Provenance};
use super::ccd_queries::{
    our_time_of_impact, random_queries, read_queries, record_from_case, write_queries, CcdQuery,
    QuerySource,
};
use crate::results::{MaterialPlot, RecordTable};
use crate::results::{PlotData, Series};

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
    pub end_time: f64,
    /// Record every n-th step.
    pub every: usize,
    /// Keep at most this many queries (evenly subsampled).
    pub max: usize,
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
pub fn fresh_queries(spec: &CcdSpec, case_dir: &Path) -> Result<Vec<CcdQuery>, String> {
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
pub fn refresh(spec: &CcdSpec, case_dir: &Path) -> Result<Provenance, String> {
    let queries = fresh_queries(spec, case_dir)?;
    let path = cache_path(&spec.queries);
    write_queries(&path, &queries)?;
    let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let req = request(
        spec,
        &format!("cache/{}", spec.queries),
        &bytes,
        queries.len(),
    );
    super::cache::refresh("ipctk_ccd.py", &req, &cache_path(&spec.cache))
}

/// How one query's answers compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Agreement {
    BothNone,
    BothHit,
    /// ipctk finds an impact in the step, we find none: must not happen.
    Missed,
    /// We find an impact ipctk does not.
    Extra,
    /// The point starts within ipctk's tolerance of the triangle: ipctk answers "in contact at
    /// t = 0" without running its CCD (see `ipctk_ccd.py`), so the query is no test of either;
    /// counted apart, with our answer.
    StartsInContact,
}

/// One query compared.
#[derive(Debug, Clone, Copy)]
pub struct Compared {
    pub source: QuerySource,
    pub agreement: Agreement,
    pub ours: Option<f64>,
    pub theirs: Option<f64>,
    /// Smallest distance between the point and the triangle over the step (m).
    pub min_distance: f64,
}

/// Distance from `p` to the triangle `(a, b, c)` (closest point by regions, Ericson 2005, 5.1.5).
pub fn point_triangle_distance(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.norm();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.norm();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + v * ab)).norm();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.norm();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + w * ac)).norm();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).norm();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).norm()
}

/// The distance below which the point counts as touching the triangle: the rounding level of
/// the query's coordinates, `1e-12` times the largest.
pub fn touch_level(q: &CcdQuery) -> f64 {
    1e-12
        * q.points
            .iter()
            .flatten()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Distance between the point and the triangle of `q` at step fraction `t`.
pub fn distance_at(q: &CcdQuery, t: f64) -> f64 {
    let at = |k: usize| {
        let (x0, x1) = (Vector3::from(q.points[k]), Vector3::from(q.points[k + 4]));
        x0 + t * (x1 - x0)
    };
    point_triangle_distance(&at(0), &at(1), &at(2), &at(3))
}

/// Smallest distance over the step: 2001 samples, then golden-section search around the best.
/// Independent of both CCD algorithms (it never solves for coplanarity).
pub fn min_distance(q: &CcdQuery) -> f64 {
    const N: usize = 2000;
    let (mut best, mut at) = (f64::INFINITY, 0);
    for i in 0..=N {
        let d = distance_at(q, i as f64 / N as f64);
        if d < best {
            (best, at) = (d, i);
        }
    }
    let (mut lo, mut hi) = (
        (at.max(1) - 1) as f64 / N as f64,
        (at + 1).min(N) as f64 / N as f64,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if distance_at(q, m1) < distance_at(q, m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    best.min(distance_at(q, 0.5 * (lo + hi)))
}

/// Compares our answers with ipctk's (`hit`, `toi` arrays of its answer).
pub fn compare(
    queries: &[CcdQuery],
    answer: &Value,
    tolerance: f64,
) -> Result<Vec<Compared>, String> {
    let hits = answer["hit"]
        .as_array()
        .ok_or("ipctk's answer has no `hit`")?;
    let tois = answer["toi"]
        .as_array()
        .ok_or("ipctk's answer has no `toi`")?;
    let initial = answer["initial"]
        .as_array()
        .ok_or("ipctk's answer has no `initial`")?;
    if [hits.len(), tois.len(), initial.len()]
        .iter()
        .any(|&n| n != queries.len())
    {
        return Err(format!(
            "ipctk answered {} queries, there are {}",
            hits.len(),
            queries.len()
        ));
    }
    Ok(queries
        .iter()
        .zip(hits.iter().zip(tois).zip(initial))
        .map(|(q, ((h, t), i))| {
            let theirs = (h.as_u64() == Some(1)).then(|| t.as_f64().unwrap_or(f64::NAN));
            let ours = our_time_of_impact(q, tolerance);
            let agreement = match (ours.is_some(), theirs.is_some()) {
                _ if i.as_u64() == Some(1) => Agreement::StartsInContact,
                (false, false) => Agreement::BothNone,
                (true, true) => Agreement::BothHit,
                (false, true) => Agreement::Missed,
                (true, false) => Agreement::Extra,
            };
            Compared {
                source: q.source,
                agreement,
                ours,
                theirs,
                min_distance: min_distance(q),
            }
        })
        .collect())
}

/// The measured quantities (metric `measure: { crosscheck: <name> }`).
pub const QUANTITIES: [&str; 9] = [
    "missed_impacts_raw",
    "missed_within_ipctk_tolerance",
    "missed_beyond_ipctk_tolerance",
    "starting_in_contact",
    "missed_impacts",
    "extra_impacts",
    "extra_impacts_beyond_ipctk_tolerance",
    "largest_toi_difference",
    "queries",
];

/// Everything the case measured.
pub struct Outcome {
    pub quantities: std::collections::BTreeMap<String, f64>,
    pub provenance: Provenance,
    pub setup: Vec<String>,
    pub tables: Vec<RecordTable>,
    pub plots: Vec<MaterialPlot>,
    pub notes: Vec<String>,
}

/// Runs the cross-check: queries and ipctk's answers (fresh with Python, else cached), our CCD
/// on every query, the comparison.
pub fn run(spec: &CcdSpec, case_dir: &Path, scratch: &Path) -> Result<Outcome, String> {
    let (queries, answer, provenance) = if super::python::ENABLED {
        let queries = fresh_queries(spec, case_dir)?;
        std::fs::create_dir_all(scratch).map_err(|e| format!("{}: {e}", scratch.display()))?;
        let file = scratch.join("ccd-queries.bin");
        write_queries(&file, &queries)?;
        let bytes = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        let req = request(spec, &file.display().to_string(), &bytes, queries.len());
        let (answer, p) = obtain("ipctk_ccd.py", &req, &cache_path(&spec.cache))?;
        (queries, answer, p)
    } else {
        let path = cache_path(&spec.queries);
        let queries = read_queries(&path)?;
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
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

const SOURCES: [QuerySource; 3] = [QuerySource::Sphere, QuerySource::Beam, QuerySource::Random];

fn agreement_table(compared: &[Compared]) -> RecordTable {
    let rows = SOURCES
        .iter()
        .map(|s| {
            let of: Vec<&Compared> = compared.iter().filter(|c| c.source == *s).collect();
            let n = |a: Agreement| of.iter().filter(|c| c.agreement == a).count();
            let dt: Vec<f64> = of
                .iter()
                .filter(|c| c.agreement == Agreement::BothHit)
                .filter_map(|c| Some((c.ours? - c.theirs?).abs()))
                .collect();
            let starting: Vec<&&Compared> = of
                .iter()
                .filter(|c| c.agreement == Agreement::StartsInContact)
                .collect();
            let median = median(&dt);
            vec![
                s.name().to_string(),
                of.len().to_string(),
                n(Agreement::BothNone).to_string(),
                n(Agreement::BothHit).to_string(),
                n(Agreement::Missed).to_string(),
                n(Agreement::Extra).to_string(),
                format!(
                    "{} ({} found by us at t = 0)",
                    starting.len(),
                    starting.iter().filter(|c| c.ours == Some(0.0)).count()
                ),
                format!("{median:.2e}"),
                format!("{:.2e}", dt.iter().cloned().fold(0.0, f64::max)),
            ]
        })
        .collect();
    RecordTable {
        title: "Vertex-face CCD: ours against ipctk".into(),
        head: [
            "queries from",
            "queries",
            "no impact (both)",
            "impact (both)",
            "ipctk only (missed by us)",
            "ours only",
            "starting within ipctk's tolerance",
            "median |toi difference|",
            "largest |toi difference|",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
        note: "Times of impact are step fractions in [0, 1]. ipctk's Tight-Inclusion is \
               conservative: a query it answers without impact has none, and its impact time is \
               a lower bound within its distance tolerance."
            .into(),
    }
}

fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// Every query the two answer differently, and the 10 largest time differences.
fn disagreement_table(compared: &[Compared], queries: &[CcdQuery]) -> RecordTable {
    let mut idx: Vec<usize> = (0..compared.len())
        .filter(|&i| matches!(compared[i].agreement, Agreement::Missed | Agreement::Extra))
        .collect();
    let mut by_dt: Vec<usize> = (0..compared.len())
        .filter(|&i| compared[i].agreement == Agreement::BothHit)
        .collect();
    let dt = |i: usize| (compared[i].ours.unwrap() - compared[i].theirs.unwrap()).abs();
    by_dt.sort_by(|&a, &b| dt(b).total_cmp(&dt(a)));
    idx.extend(by_dt.into_iter().take(10));
    let t = |x: Option<f64>| x.map_or("none".to_string(), |t| format!("{t:.9}"));
    let rows = idx
        .iter()
        .map(|&i| {
            let c = &compared[i];
            let size = queries[i]
                .points
                .iter()
                .flatten()
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            vec![
                i.to_string(),
                c.source.name().to_string(),
                format!("{:?}", c.agreement).to_lowercase(),
                t(c.ours),
                t(c.theirs),
                format!("{:.3e}", c.min_distance),
                format!("{size:.3e}"),
            ]
        })
        .collect();
    RecordTable {
        title: "Queries answered differently, and the largest time differences".into(),
        head: [
            "query",
            "from",
            "kind",
            "ours",
            "ipctk",
            "smallest distance in the step (m)",
            "largest coordinate (m)",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
        note: "The smallest distance is computed here by sampling and golden-section search on \
               the exact point-triangle distance, independently of both CCD algorithms: a query \
               with an impact reaches 0 (to the sampling's accuracy)."
            .into(),
    }
}

/// Sorted |toi difference| of the queries both find an impact in, per source.
fn toi_plot(compared: &[Compared]) -> MaterialPlot {
    let series = SOURCES
        .iter()
        .filter_map(|s| {
            let mut dt: Vec<f64> = compared
                .iter()
                .filter(|c| c.source == *s && c.agreement == Agreement::BothHit)
                .filter_map(|c| Some((c.ours? - c.theirs?).abs().max(1e-17)))
                .collect();
            if dt.is_empty() {
                return None;
            }
            dt.sort_by(f64::total_cmp);
            let n = dt.len() as f64;
            Some(Series {
                name: s.name().to_string(),
                x: (0..dt.len()).map(|i| (i as f64 + 1.0) / n).collect(),
                y: dt,
            })
        })
        .collect();
    MaterialPlot {
        plot: PlotData {
            title: "Time-of-impact differences, ours against ipctk (sorted)".into(),
            x_label: "fraction of the queries with an impact in both".into(),
            y_label: "|toi ours - toi ipctk| (step fractions; 1e-17 = equal)".into(),
            series,
            reference_lines: vec![],
            log_log: false,
        },
        log_x: false,
        log_y: true,
        boxes: vec![],
        dashed: vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_triangle_distance_in_each_region() {
        let (a, b, c) = (
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        );
        let d = |p: [f64; 3]| point_triangle_distance(&Vector3::from(p), &a, &b, &c);
        assert_eq!(d([0.25, 0.25, 2.0]), 2.0); // face
        assert_eq!(d([-3.0, -4.0, 0.0]), 5.0); // vertex a
        assert_eq!(d([0.5, -2.0, 0.0]), 2.0); // edge ab
        assert!((d([1.0, 1.0, 0.0]) - 0.5f64.sqrt()).abs() < 1e-15); // edge bc
        assert_eq!(d([2.0, 0.0, 0.0]), 1.0); // vertex b
    }

    #[test]
    fn the_smallest_distance_over_a_step_finds_a_crossing_and_a_near_miss() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let query = |p0: [f64; 3], p1: [f64; 3]| CcdQuery {
            source: QuerySource::Random,
            points: [p0, tri[0], tri[1], tri[2], p1, tri[0], tri[1], tri[2]],
        };
        assert!(min_distance(&query([0.2, 0.2, 1.0], [0.2, 0.2, -1.0])) < 1e-12);
        // Passes beside the edge bc (x + y = 1) at 5e-5 outside along x and y: sqrt(2) 5e-5 away.
        let miss = min_distance(&query(
            [0.5 + 5e-5, 0.5 + 5e-5, 1.0],
            [0.5 + 5e-5, 0.5 + 5e-5, -1.0],
        ));
        assert!((miss - 2f64.sqrt() * 5e-5).abs() < 1e-12, "{miss}");
    }

    #[test]
    fn answers_are_compared_one_sidedly() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let q = |p0: [f64; 3], p1: [f64; 3]| CcdQuery {
            source: QuerySource::Random,
            points: [p0, tri[0], tri[1], tri[2], p1, tri[0], tri[1], tri[2]],
        };
        let queries = [
            q([0.2, 0.2, 1.0], [0.2, 0.2, -1.0]),
            q([2.0, 2.0, 1.0], [2.0, 2.0, -1.0]),
        ];
        let answer = json!({"hit": [1, 1], "toi": [0.4999995, 0.3], "initial": [0, 0]});
        let c = compare(&queries, &answer, 1e-9).unwrap();
        assert_eq!(c[0].agreement, Agreement::BothHit);
        assert!((c[0].ours.unwrap() - 0.5).abs() < 1e-15);
        assert_eq!(c[1].agreement, Agreement::Missed);
        let starting = json!({"hit": [1, 1], "toi": [0.0, 0.0], "initial": [1, 0]});
        let c = compare(&queries, &starting, 1e-9).unwrap();
        assert_eq!(c[0].agreement, Agreement::StartsInContact);
        assert_eq!(c[1].agreement, Agreement::Missed);
        let short = json!({"hit": [1], "toi": [0.5], "initial": [0]});
        assert!(compare(&queries, &short, 1e-9)
            .unwrap_err()
            .contains("answered 1"));
    }

    #[test]
    fn checksum_is_fnv1a() {
        // FNV-1a 64 of "a" (Fowler, Noll & Vo test vector).
        assert_eq!(checksum(b"a"), "af63dc4c8601ec8c");
    }
}
