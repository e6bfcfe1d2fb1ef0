//! Recording the CCD queries of contact detection from a run of a catalogue case, without
//! duplicates and evenly subsampled.

use std::collections::HashSet;
use std::path::Path;
use std::time::Instant;

use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::scene::{build_problem, Analysis};

use super::file::problem;
use super::{CcdQuery, QuerySource};
use crate::crosscheck::error::{CrosscheckError, QueryProblem};

/// What [`record_case`] recorded.
#[derive(Debug, Clone)]
pub struct Recording {
    /// The kept queries, in recording order.
    pub queries: Vec<CcdQuery>,
    /// Queries recorded by the run (every CCD call of detection in the recorded steps).
    pub recorded: usize,
    /// Of those, the distinct ones (exact duplicates removed).
    pub distinct: usize,
    /// Of the recorded ones, those our CCD reported a hit for.
    pub recorded_hits: usize,
    /// Steps the run took.
    pub steps: usize,
    /// Wall time of the run (s).
    pub wall_seconds: f64,
}

/// Runs the scene of the catalogue case `case_file` up to `end_time` (the rest of its explicit
/// settings kept), recording every CCD query of contact detection in every `every`-th step on
/// all its contact pairs, and keeps at most `max` distinct ones by even subsampling (see
/// [`record_case`]).
pub fn record_from_case(
    case_file: &Path,
    end_time: f64,
    every: usize,
    max: usize,
    source: QuerySource,
) -> Result<Vec<CcdQuery>, CrosscheckError> {
    record_case(case_file, end_time, every, max, source).map(|r| r.queries)
}

/// [`record_from_case`] with the counts and the run's wall time.
///
/// Exact duplicates (the same 8 points to the bit, as the two passes or consecutive steps can
/// repeat) are removed, first occurrence kept; if more than `max` distinct queries remain, the
/// ones at indices `floor(i n / max)`, `i = 0..max`, are kept (evenly spread over the run, in
/// recording order).
pub fn record_case(
    case_file: &Path,
    end_time: f64,
    every: usize,
    max: usize,
    source: QuerySource,
) -> Result<Recording, CrosscheckError> {
    let fail = |p| problem(case_file, p);
    if every == 0 {
        return Err(fail(QueryProblem::EveryZero));
    }
    if end_time.is_nan() || end_time <= 0.0 {
        return Err(fail(QueryProblem::EndTime(end_time)));
    }
    let spec = crate::case_file::load_spec(case_file)?;
    let mut scene = spec.scene.ok_or_else(|| fail(QueryProblem::NoScene))?;
    let settings = match &mut scene.analysis {
        Analysis::Explicit(a) => {
            a.settings.end_time = end_time;
            a.settings.clone()
        }
        _ => return Err(fail(QueryProblem::NotExplicit)),
    };
    if scene.contact.is_empty() {
        return Err(fail(QueryProblem::NoContact));
    }
    for pair in &mut scene.contact {
        pair.record_ccd_every = Some(every);
    }
    let built = build_problem(&scene).map_err(|e| fail(QueryProblem::Solver(e)))?;
    let mut solver = ExplicitSolver::new(&built, settings, OutputSettings::default())
        .map_err(|e| fail(QueryProblem::Solver(e)))?;
    let started = Instant::now();
    let outcome = solver.run(&mut |_| {});
    let wall_seconds = started.elapsed().as_secs_f64();
    let summary = outcome.map_err(|e| fail(QueryProblem::RunFailed(e.to_string())))?;
    let recorded = solver.take_recorded_ccd_queries();
    let recorded_hits = recorded.iter().filter(|q| q.hit.is_some()).count();
    let mut seen = HashSet::new();
    let distinct: Vec<CcdQuery> = recorded
        .iter()
        .map(|r| CcdQuery::from_trajectories(source, &r.node, &r.face))
        .filter(|q| seen.insert(q.key()))
        .collect();
    Ok(Recording {
        queries: subsample(&distinct, max),
        recorded: recorded.len(),
        distinct: distinct.len(),
        recorded_hits,
        steps: summary.steps,
        wall_seconds,
    })
}

/// At most `max` of `items`, evenly spread, in order: indices `floor(i n / max)`.
fn subsample<T: Clone>(items: &[T], max: usize) -> Vec<T> {
    let n = items.len();
    if n <= max {
        return items.to_vec();
    }
    (0..max).map(|i| items[i * n / max].clone()).collect()
}

#[cfg(test)]
mod tests {
    use super::super::{our_time_of_impact, random_queries, write_queries};
    use super::*;

    #[test]
    fn subsampling_is_even_and_in_order() {
        let items: Vec<usize> = (0..10).collect();
        assert_eq!(subsample(&items, 4), vec![0, 2, 5, 7]);
        assert_eq!(subsample(&items, 20), items);
        assert!(subsample(&items, 0).is_empty());
    }

    /// The recordings of the issue: `cargo test --release --lib crosscheck::ccd_queries --
    /// --ignored --nocapture`; writes `target/ccd-queries/<source>.ccdq`.
    #[test]
    #[ignore = "runs two catalogue cases (the beam one for minutes)"]
    fn record_the_catalogue_cases() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let out = root.join("target/ccd-queries");
        std::fs::create_dir_all(&out).unwrap();
        let runs = [
            (
                "cases/contact/spheres-headon.yaml",
                9e-4,
                QuerySource::Sphere,
            ),
            ("cases/beam/drop-2ms.yaml", 3e-4, QuerySource::Beam),
        ];
        for (file, end, source) in runs {
            let every: usize = std::env::var("CCD_EVERY")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(1);
            let r = record_case(&root.join(file), end, every, 1000, source).unwrap();
            let hits = r
                .queries
                .iter()
                .filter(|q| our_time_of_impact(q, 1e-9).is_some())
                .count();
            eprintln!(
                "{file} to {end:e} s, every {every}: {} steps in {:.1} s; {} queries recorded \
                 ({} hits, {:.3}), {} distinct; kept {} ({} hits, {:.3})",
                r.steps,
                r.wall_seconds,
                r.recorded,
                r.recorded_hits,
                r.recorded_hits as f64 / r.recorded.max(1) as f64,
                r.distinct,
                r.queries.len(),
                hits,
                hits as f64 / r.queries.len().max(1) as f64
            );
            write_queries(&out.join(format!("{}.ccdq", source.name())), &r.queries).unwrap();
        }
        let random = random_queries(1500, 2024);
        write_queries(&out.join("random.ccdq"), &random).unwrap();
    }
}
