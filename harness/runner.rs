//! The runner: one job per case and variant, run by the case's kind (several at once when
//! cores allow), each result handed on as it finishes.
//!
//! Parallel runs give each case a lane: a thread pool of its own, of the global pool's threads
//! divided among the lanes (one each on two cores). A case run as a task of one shared pool can
//! be taken up by a worker waiting inside another case's parallel loop, and the waiting case
//! stays frozen under it until the whole taken case ends; cases run on threads of their own but
//! one shared pool contend three threads to two cores, and a case's parallel loops queue behind
//! the other's. Either way the nail run took about three times its time alone. A lane's pool
//! serves its own case only. The longest cases start first, so the last to finish is a short
//! one.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use crate::case_kind::{unfinished_result, LoadedCase, RunOptions};
use crate::catalogue::Variant;
use crate::results::{CaseResult, Status};

type Job<'a> = (&'a LoadedCase, Option<&'a Variant>);

/// Runs the cases and returns their results in the order given. `on_done` is called as each
/// case finishes (for progress display).
pub fn run_cases(
    cases: &[LoadedCase],
    options: &RunOptions,
    on_done: &(dyn Fn(&CaseResult) + Sync),
) -> Vec<CaseResult> {
    run_jobs(cases, &|_, _| true, options, on_done)
}

/// The jobs of `cases`, one per case and variant (`"default"` for a case without variants), in
/// catalogue order, as `(case id, variant name)`.
pub fn job_names(cases: &[LoadedCase]) -> Vec<(String, String)> {
    jobs_of(cases)
        .iter()
        .map(|(c, v)| {
            (
                c.spec.id.clone(),
                v.map_or("default", |v| &v.name).to_string(),
            )
        })
        .collect()
}

fn jobs_of(cases: &[LoadedCase]) -> Vec<Job<'_>> {
    cases
        .iter()
        .flat_map(|c| {
            if c.spec.variants.is_empty() {
                vec![(c, None)]
            } else {
                c.spec.variants.iter().map(|v| (c, Some(v))).collect()
            }
        })
        .collect()
}

/// [`run_cases`] for the jobs for which `wanted(case id, variant name)` holds (a run resumed:
/// those that did not finish), their results in catalogue order.
pub fn run_jobs(
    cases: &[LoadedCase],
    wanted: &(dyn Fn(&str, &str) -> bool + Sync),
    options: &RunOptions,
    on_done: &(dyn Fn(&CaseResult) + Sync),
) -> Vec<CaseResult> {
    // One job per case and variant, in catalogue order.
    let jobs: Vec<Job> = jobs_of(cases)
        .into_iter()
        .filter(|(c, v)| wanted(&c.spec.id, v.map_or("default", |v| &v.name)))
        .collect();
    let run_one = |(case, variant): &Job| {
        let stopped = options
            .stop
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed));
        let result = if stopped {
            let mut r = unfinished_result(&case.spec, variant.map_or("default", |v| &v.name));
            r.status = Status::Interrupted;
            r.message = Some("interrupted before it started".into());
            r
        } else {
            case.kind.run(case, *variant, options)
        };
        let result = CaseResult {
            known_failure: case.spec.known_failure.clone(),
            ..result
        };
        on_done(&result);
        result
    };
    let lanes = rayon::current_num_threads().min(jobs.len());
    if !options.parallel || lanes <= 1 {
        return jobs.iter().map(run_one).collect();
    }

    let threads_per_lane = (rayon::current_num_threads() / lanes).max(1);
    let order = longest_first(&jobs);
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<CaseResult>>> = jobs.iter().map(|_| Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..lanes {
            scope.spawn(|| {
                let lane = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads_per_lane)
                    .build()
                    .expect("a thread pool for a lane of cases");
                while let Some(&job) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let result = lane.install(|| run_one(&jobs[job]));
                    *slots[job].lock().unwrap_or_else(|e| e.into_inner()) = Some(result);
                }
            });
        }
    });
    slots
        .into_iter()
        .map(|slot| {
            slot.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every job ran on a lane")
        })
        .collect()
}

/// The jobs' indices, longest expected first: by the case's wall-time guard `time_limit_s`
/// (each long case's guard is set from its measured length; a case without one is short), in
/// catalogue order among equals.
fn longest_first(jobs: &[Job]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| {
        let limit = |j: usize| jobs[j].0.spec.time_limit_s.unwrap_or(0.0);
        limit(b).total_cmp(&limit(a))
    });
    order
}
