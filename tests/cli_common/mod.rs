//! What the command-line tests share: the repository, scratch folders, running `impact-vv`
//! and reading what a run wrote.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch folder removed with everything in it when the value is dropped, so a test run
/// leaves nothing behind in the system's temporary folder (a killed scene alone writes hundreds
/// of megabytes of frames). It reads as the folder's path.
pub struct TestDir(tempfile::TempDir);

impl std::ops::Deref for TestDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

/// An empty scratch folder whose name starts with the test's `name`; it is removed when dropped.
pub fn temp_dir(name: &str) -> TestDir {
    TestDir(
        tempfile::Builder::new()
            .prefix(&format!("impact-vv-cli-{name}-"))
            .tempdir()
            .unwrap(),
    )
}

/// Runs `impact-vv` with `args` and environment `envs` from the repository root.
pub fn impact_vv(args: &[&str], envs: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_impact-vv"));
    cmd.args(args).current_dir(repo());
    for (k, v) in envs {
        cmd.env(k, v);
    }
    cmd.output().expect("impact-vv runs")
}

/// What a run printed, stdout then stderr.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The newest run folder under `reports`.
pub fn only_run_dir(reports: &Path) -> PathBuf {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(reports)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs.pop().expect("a run folder")
}

/// The `results.json` of the newest run under `reports`.
pub fn results(reports: &Path) -> serde_json::Value {
    serde_json::from_str(
        &std::fs::read_to_string(only_run_dir(reports).join("results.json")).unwrap(),
    )
    .unwrap()
}

/// The text of the confined-wave case, a small elastic case to copy into a scratch catalogue.
pub fn confined_wave() -> String {
    std::fs::read_to_string(repo().join("cases/elastic/confined-wave.yaml")).unwrap()
}

/// A steel striker at 300 m/s onto a microplane concrete block of 2 x 2 x 2 cells held at its
/// base, remeshing the block, run for 40 us: a penetration scene of a fraction of a second.
/// `remeshing` holds the lines of the `remeshing:` block after `body: block`, indented six
/// spaces.
pub fn remeshing_striker(remeshing: &str) -> String {
    let material = repo().join("cases/materials/thesis-concrete-crack-friction.yaml");
    format!(
        r#"name: remesh
bodies:
  - name: block
    mesh: {{ box: {{ origin: [0, 0, 0], size: [0.1, 0.1, 0.1], divisions: [2, 2, 2] }} }}
    material: {{ microplane: {{ file: {}, volumetric_strain: volume_ratio, crack_friction: 0.5 }} }}
  - name: striker
    mesh: {{ box: {{ origin: [0.03, 0.101, 0.03], size: [0.04, 0.04, 0.04], divisions: [1, 1, 1] }} }}
    material: {{ linear_elastic: {{ density: 8000, youngs_modulus: 2.0e11, poisson_ratio: 0.3 }} }}
    initial_velocity: {{ translation: [0, -300.0, 0] }}
boundary_conditions:
  - {{ name: bottom, body: block, nodes: {{ plane: {{ point: [0, 0, 0], normal: [0, 1, 0] }} }}, motion: {{ fixed: [y] }} }}
probes:
  - {{ name: tip, body: striker, nodes: all, quantity: displacement }}
contact:
  - {{ name: hit, bodies: [block, striker], friction: 0.5, penetration_release_speed: 20.0 }}
analysis:
  explicit:
    end_time: 4.0e-5
    safety: 0.6
    remeshing:
      body: block
{remeshing}"#,
        material.display()
    )
}
