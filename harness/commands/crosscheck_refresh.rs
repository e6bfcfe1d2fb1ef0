//! `impact-vv crosscheck-refresh`: recomputes the cached independent answers of the cases
//! that keep them (needs the `python` feature).

use std::path::Path;
use std::process::ExitCode;

use crate::case_file::matches;
use crate::case_kind::LoadedCase;

/// Refreshes the caches of the cases of `dir` that `patterns` select (all when empty).
pub fn exec(patterns: &[String], dir: &Path) -> ExitCode {
    let cases = match super::catalogue(dir, true) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let chosen: Vec<&LoadedCase> = cases
        .iter()
        .filter(|c| patterns.is_empty() || patterns.iter().any(|p| matches(c, p)))
        .collect();
    let mut refreshed = 0;
    let mut code = ExitCode::SUCCESS;
    for case in chosen {
        let Some(outcome) = case.kind.refresh(case) else {
            continue;
        };
        refreshed += 1;
        match outcome {
            Ok(line) => println!(
                "{}: {}",
                case.spec.id,
                line.replace("fresh answer", "cached answer")
            ),
            Err(e) => {
                eprintln!("error: {}: {e}", case.spec.id);
                code = ExitCode::from(2);
            }
        }
    }
    if refreshed == 0 {
        eprintln!("error: no case with a cache of independent answers matches {patterns:?}");
        return ExitCode::from(2);
    }
    code
}
