//! What the restart tests share: byte comparison of two output folders, the bits of a run's
//! final state, and the check that a run stopped.

#![allow(dead_code, clippy::unwrap_used)]

use std::path::Path;

use impact_solver::analysis::Execution;
use impact_solver::restart::RestartError;

/// Every output file of `a` has the bytes of the same file in `b`, and `b` has no other.
pub fn same_files(a: &Path, b: &Path) {
    let names = |d: &Path| -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| !n.ends_with("-checkpoints"))
            .collect();
        n.sort();
        n
    };
    assert_eq!(names(a), names(b));
    for n in names(a) {
        let (x, y) = (
            std::fs::read(a.join(&n)).unwrap(),
            std::fs::read(b.join(&n)).unwrap(),
        );
        assert!(
            x == y,
            "{n} differs ({} against {} bytes)",
            x.len(),
            y.len()
        );
    }
}

pub fn bits(e: &Execution) -> (Vec<u64>, Vec<u32>) {
    let nodal =
        e.u.iter()
            .chain(e.v.as_ref().unwrap())
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect();
    let history = e
        .material_history
        .as_ref()
        .unwrap()
        .bodies
        .iter()
        .flatten()
        .flat_map(|h| h.values.iter().map(|v| v.to_bits()))
        .collect();
    (nodal, history)
}

pub fn stopped(result: Result<Execution, RestartError>) {
    match result {
        Err(RestartError::Run(impact_solver::SolverError::Interrupted { .. })) => {}
        Err(e) => panic!("expected the stop, got {e}"),
        Ok(_) => panic!("expected the stop, the run completed"),
    }
}
