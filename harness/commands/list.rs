//! `impact-vv list`: the cases a selection names, one line each.

use std::path::Path;
use std::process::ExitCode;

use crate::catalogue::Tier;

/// Prints id, tier, tags and description of every case of the catalogue in `dir` that
/// `patterns` and `tier` select.
pub fn exec(patterns: &[String], tier: Option<Tier>, dir: &Path) -> ExitCode {
    let cases = match super::catalogue(dir, true) {
        Ok(c) => c,
        Err(code) => return code,
    };
    for c in super::select(&cases, patterns, tier) {
        println!(
            "{:<40} {:<8} {:<30} {}",
            c.spec.id,
            c.spec.tier.name(),
            c.spec.tags.join(","),
            c.spec.description
        );
    }
    ExitCode::SUCCESS
}
