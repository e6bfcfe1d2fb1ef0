//! A kind of case that checks determinism (ARCHITECTURE "Conventions"): the case's scene run
//! on several thread counts must give bitwise the same history and final state.
//!
//! `determinism: { threads: [1, 2] }` beside the case's `scene`; its metrics measure
//! `{ determinism: differing_values }` (how many recorded numbers differ bitwise from the run on
//! the first thread count: 0 when deterministic) or `{ determinism: max_difference }` (the
//! largest absolute difference among them).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use impact_solver::scene::{build_problem, Scene};
use serde::{Deserialize, Serialize};

use crate::case_kind::{
    parse_measures, refuse_parts, unfinished_result, Block, CaseKind, KindParseError, LoadedCase,
    RunOptions,
};
use crate::case_log::CaseLog;
use crate::catalogue::{CaseSpec, Variant};
use crate::judge::judge_metrics;
use crate::results::CaseResult;
use impact_solver::analysis::{execute, ExecuteOptions, Execution};

/// Why a `determinism` case is refused or one of its runs fails.
#[derive(Debug, thiserror::Error)]
pub enum DeterminismError {
    /// The kind's block is missing.
    #[error("a determinism case needs its `determinism` block")]
    NoBlock,
    /// Fewer than two thread counts, or a zero.
    #[error("determinism: give two thread counts or more, each at least 1, got {threads:?}")]
    Threads {
        /// The thread counts given.
        threads: Vec<usize>,
    },
    /// No scene to run.
    #[error("a determinism case runs the case's `scene`: add one")]
    NoScene,
    /// The thread pool cannot be started.
    #[error(transparent)]
    Pool(#[from] rayon::ThreadPoolBuildError),
    /// The scene cannot be built or run.
    #[error(transparent)]
    Solver(#[from] impact_solver::SolverError),
    /// The run panicked.
    #[error("the run on {threads} thread(s) panicked")]
    Panicked {
        /// The thread count of the run.
        threads: usize,
    },
}

/// The `determinism:` block: the thread counts to compare, the first one the reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeterminismSpec {
    /// Thread counts of the runs, each at least 1; the first run is the reference.
    pub threads: Vec<usize>,
}

/// What a determinism case measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Recorded numbers (every history entry, the final displacement and velocity components)
    /// that differ bitwise from the reference run, over all other thread counts; a run whose
    /// history has another shape counts all of its numbers.
    DifferingValues,
    /// The largest absolute difference among them (0 when none differ).
    MaxDifference,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum DeterminismMeasure {
    Determinism(Quantity),
}

/// A case that runs its scene on several thread counts.
#[derive(Debug)]
pub struct DeterminismCase {
    /// The case's `determinism:` block.
    pub spec: DeterminismSpec,
    measures: Vec<Quantity>,
}

/// Reads a `determinism` case: two thread counts or more, each at least 1, a scene, no sweep,
/// variants or plots, and determinism measures.
pub fn parse(
    block: Option<&Block>,
    case: &CaseSpec,
    _base: &Path,
) -> Result<Arc<dyn CaseKind>, KindParseError> {
    let spec: DeterminismSpec = block.ok_or(DeterminismError::NoBlock)?.parse()?;
    if spec.threads.len() < 2 || spec.threads.contains(&0) {
        return Err(DeterminismError::Threads {
            threads: spec.threads.clone(),
        }
        .into());
    }
    if case.scene.is_none() {
        return Err(DeterminismError::NoScene.into());
    }
    refuse_parts(
        case,
        &["sweep", "variants", "plots"],
        "a `determinism` case compares runs of one scene",
    )?;
    let measures: Vec<DeterminismMeasure> = parse_measures(case, "determinism")?;
    Ok(Arc::new(DeterminismCase {
        spec,
        measures: measures
            .into_iter()
            .map(|DeterminismMeasure::Determinism(q)| q)
            .collect(),
    }))
}

impl CaseKind for DeterminismCase {
    fn name(&self) -> &'static str {
        "determinism"
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn run(&self, case: &LoadedCase, _: Option<&Variant>, options: &RunOptions) -> CaseResult {
        let spec = &case.spec;
        let started = Instant::now();
        let mut result = unfinished_result(spec, "default");
        let log = CaseLog::new(options, &spec.id, "default");
        let scene = spec.scene.as_ref().expect("parse checked the scene");
        let time_limit = spec.time_limit_s.unwrap_or(options.time_limit_s);
        let mut runs = Vec::new();
        for &threads in &self.spec.threads {
            match run_on(scene, threads, time_limit, options, &log) {
                Ok(numbers) => runs.push(numbers),
                Err(e) => {
                    result.message = Some(format!("the run on {threads} thread(s) failed: {e}"));
                    result.log_file = log.relative_path();
                    return result;
                }
            }
        }
        result.wall_s = started.elapsed().as_secs_f64();
        let (differing, max_difference) = compare(&runs);
        let judgement = judge_metrics(
            &spec.metrics,
            Some(scene),
            &mut |i, _, _| {
                Ok::<_, DeterminismError>(match self.measures[i] {
                    Quantity::DifferingValues => differing as f64,
                    Quantity::MaxDifference => max_difference,
                })
            },
            &|_| None,
        );
        let note = format!(
            "threads {:?}: {} numbers per run compared, {differing} differ (largest difference \
             {max_difference:e})",
            self.spec.threads,
            runs[0].len()
        );
        let (status, message) = judgement.verdict(&[note]);
        result.status = status;
        result.message = Some(message);
        result.metrics = judgement.metrics;
        result.log_file = log.relative_path();
        result
    }
}

/// The scene run in a pool of `threads` threads: every number it records, in a fixed order
/// (history rows, then the final displacement and velocity); its log lines to the case's log.
fn run_on(
    scene: &Scene,
    threads: usize,
    time_limit_s: f64,
    options: &RunOptions,
    log: &CaseLog,
) -> Result<Vec<f64>, DeterminismError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let run = || {
        pool.install(|| {
            let mut problem = build_problem(scene)?;
            let opts = ExecuteOptions {
                out: None,
                stem: "run",
                final_state: true,
                fields: false,
                time_limit_s: Some(time_limit_s),
                stop: options.stop.clone(),
                ranks: None,
                log: &log.sink(),
            };
            let run = execute(&mut problem, &scene.analysis, &opts, &mut |_| {})?;
            Ok(numbers(&run))
        })
    };
    // From a plain thread: a worker of the catalogue's pool that called `install` itself would
    // run other cases' jobs while it waits, and this case's wall time would count them.
    std::thread::scope(|s| s.spawn(run).join())
        .map_err(|_| DeterminismError::Panicked { threads })?
}

fn numbers(run: &Execution) -> Vec<f64> {
    let history = run.history.iter().flat_map(|h| h.rows().iter().flatten());
    let state = run.u.iter().chain(run.v.iter().flatten());
    history
        .copied()
        .chain(state.flat_map(|x| [x.x, x.y, x.z]))
        .collect()
}

/// How many numbers of the other runs differ bitwise from the first run's, and the largest
/// absolute difference among them.
fn compare(runs: &[Vec<f64>]) -> (usize, f64) {
    let reference = &runs[0];
    let mut differing = 0;
    let mut largest = 0.0f64;
    for other in &runs[1..] {
        if other.len() != reference.len() {
            differing += other.len().max(reference.len());
            largest = f64::INFINITY;
            continue;
        }
        for (a, b) in reference.iter().zip(other) {
            if a.to_bits() != b.to_bits() {
                differing += 1;
                largest = largest.max((a - b).abs());
            }
        }
    }
    (differing, largest)
}

#[cfg(test)]
mod tests {
    use super::compare;

    /// Equal runs have no differing number; one changed bit is counted with its size, and a
    /// history of another length counts all of its numbers.
    #[test]
    fn runs_are_compared_bit_for_bit() {
        let a = vec![1.0, 2.0, 3.0];
        assert_eq!(compare(&[a.clone(), a.clone()]), (0, 0.0));
        let nudged = f64::from_bits(2.0f64.to_bits() + 1);
        let (n, d) = compare(&[a.clone(), vec![1.0, nudged, 3.0]]);
        assert_eq!(n, 1);
        assert!(d > 0.0 && d < 1e-15);
        assert_eq!(compare(&[a, vec![1.0, 2.0]]), (3, f64::INFINITY));
    }
}
