//! The runner: one job per case and variant, run by the case's kind (several at once when
//! cores allow), each result handed on as it finishes.

use rayon::prelude::*;

use crate::case_kind::{unfinished_result, LoadedCase, RunOptions};
use crate::catalogue::Variant;
use crate::results::{CaseResult, Status};

/// Runs the cases and returns their results in the order given. `on_done` is called as each
/// case finishes (for progress display).
pub fn run_cases(
    cases: &[LoadedCase],
    options: &RunOptions,
    on_done: &(dyn Fn(&CaseResult) + Sync),
) -> Vec<CaseResult> {
    // One job per case and variant, in catalogue order.
    let jobs: Vec<(&LoadedCase, Option<&Variant>)> = cases
        .iter()
        .flat_map(|c| {
            if c.spec.variants.is_empty() {
                vec![(c, None)]
            } else {
                c.spec.variants.iter().map(|v| (c, Some(v))).collect()
            }
        })
        .collect();
    let run_one = |(case, variant): &(&LoadedCase, Option<&Variant>)| {
        let stopped = options
            .stop
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed));
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
    if options.parallel {
        jobs.par_iter().map(run_one).collect()
    } else {
        jobs.iter().map(run_one).collect()
    }
}
