//! What the restart tests share: the small drop scene (tests/restart/small-drop.yaml, cut to
//! 1.2 ms) and its inputs, a log that keeps its lines, byte comparison of two output folders,
//! the bits of a run's final state, and the check that a run stopped.

#![allow(dead_code, clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use impact_solver::analysis::Execution;
use impact_solver::restart::{Inputs, RestartError};
use impact_solver::scene::{Analysis, Scene};

/// The file stem of the small drop's outputs.
pub const STEM: &str = "small-drop";

pub fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/restart/small-drop.yaml")
}

/// The small drop test, shortened to 1.2 ms (about 580 steps) with a frame every 0.2 ms.
pub fn scene() -> Scene {
    let mut scene = Scene::from_yaml_file(&scene_path()).unwrap();
    let Analysis::Explicit(a) = &mut scene.analysis else {
        panic!("the small drop is explicit")
    };
    a.settings.end_time = 1.2e-3;
    scene
}

/// The inputs a checkpoint of the small drop records.
pub fn inputs() -> Inputs {
    Inputs::of_scene_file(
        &scene_path(),
        &Scene::from_yaml_file(&scene_path()).unwrap(),
    )
    .unwrap()
}

/// The log lines of a run (or of one rank).
#[derive(Default, Clone)]
pub struct Log(pub Arc<Mutex<Vec<String>>>);

impl Log {
    pub fn lines(&self) -> Vec<String> {
        self.0.lock().unwrap().clone()
    }
}

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
