//! Checkpoint and restart of a run that remeshes: a steel striker at 300 m/s onto a microplane
//! block of 2 x 2 x 2 cells, the block remeshed six times in 102 steps (collapse limit 1.5,
//! regrowth 1), with section pictures and the near-tip stress. A run with checkpoints writes
//! the bytes of the run without; a run stopped twice (after a remeshing, inside a stretch of
//! steps on one mesh) and resumed each time in a fresh solver over the scene's problem ends
//! with the bytes of every output file (history, remeshing and near-tip CSVs, pictures, field
//! frames and collection) and the bits of the final state of the run never stopped. A
//! checkpoint that forgets the threshold of the next remeshing resumes into another run.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use impact_solver::analysis::{execute, ExecuteOptions, Execution};
use impact_solver::dynamics::CheckpointEvery;
use impact_solver::remesh::RemeshCheckpoint;
use impact_solver::restart::remeshing_payload::{decode, encode};
use impact_solver::restart::{execute_checkpointed, file, CheckpointPlan, Inputs, RestartError};
use impact_solver::scene::{build_problem, Scene};

mod restart_common;
use restart_common::{bits, same_files, stopped};

const STEM: &str = "striker";

/// Writes the scene into `dir` and returns its path.
fn scene_file(dir: &Path) -> PathBuf {
    let material = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/materials/thesis-concrete-crack-friction.yaml");
    let text = format!(
        r#"name: {STEM}
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
    end_time: 1.6e-5
    safety: 0.6
    field_interval: 1.0e-6
    remeshing:
      body: block
      check_every: 2
      collapse_limit: 1.5
      regrowth: 1.0
      section: {{ axis: z, value: 0.05 }}
      near_tip: {{ probe: tip, radius: 0.03, steps: 5 }}
"#,
        material.display()
    );
    let path = dir.join("striker.yaml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The log lines of a run.
#[derive(Default, Clone)]
struct Log(Arc<Mutex<Vec<String>>>);

fn options<'a>(
    out: &'a Path,
    stop: Option<Arc<AtomicBool>>,
    log: &'a (dyn Fn(&str) + Sync),
) -> ExecuteOptions<'a> {
    ExecuteOptions {
        out: Some(out),
        stem: STEM,
        final_state: true,
        fields: true,
        time_limit_s: None,
        stop,
        ranks: None,
        log,
    }
}

/// The run without checkpoints, into `out`.
fn plain(scene: &Path, out: &Path) -> Execution {
    let scene = Scene::from_yaml_file(scene).unwrap();
    let mut problem = build_problem(&scene).unwrap();
    execute(
        &mut problem,
        &scene.analysis,
        &options(out, None, &|_| {}),
        &mut |_| {},
    )
    .unwrap()
}

/// The run with a checkpoint every `every` steps into `out`, stopped (as by a signal) once its
/// progress passes `stop_at` when given, resumed from the newest good checkpoint with `resume`.
fn checkpointed(
    scene_path: &Path,
    out: &Path,
    every: usize,
    resume: bool,
    stop_at: Option<f64>,
) -> Result<Execution, RestartError> {
    let scene = Scene::from_yaml_file(scene_path).unwrap();
    let mut problem = build_problem(&scene).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let log = Log::default();
    let write = move |line: &str| log.0.lock().unwrap().push(line.to_string());
    let plan = CheckpointPlan {
        every: CheckpointEvery {
            every_s: None,
            every_steps: Some(every),
        },
        resume,
        inputs: Inputs::of_scene_file(scene_path, &scene).unwrap(),
    };
    let raise = flag.clone();
    execute_checkpointed(
        &mut problem,
        &scene.analysis,
        &options(out, Some(flag), &write),
        &plan,
        &mut |x| {
            if stop_at.is_some_and(|at| x >= at) {
                raise.store(true, Ordering::Relaxed);
            }
        },
    )
}

#[test]
fn a_remeshing_run_stopped_and_resumed_is_bitwise_the_run_never_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path());
    let (a, b, c) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("c"),
    );
    let reference = plain(&scene, &a);
    assert!(
        reference.remeshings.len() >= 4,
        "{} remeshings",
        reference.remeshings.len()
    );
    let names: Vec<String> = std::fs::read_dir(&a)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    for want in ["_remeshing.csv", "_near_tip.csv", "_mesh_1.json", ".pvd"] {
        assert!(names.iter().any(|n| n.ends_with(want)), "{want}: {names:?}");
    }

    // Checkpoints alone change nothing.
    let with = checkpointed(&scene, &c, 7, false, None).unwrap();
    same_files(&a, &c);
    assert_eq!(bits(&reference), bits(&with));
    assert_eq!(reference.remeshings, with.remeshings);

    // Stopped after the first remeshing, resumed and stopped again after the last, resumed
    // to the end: each time a fresh solver over the scene's problem.
    stopped(checkpointed(&scene, &b, 5, false, Some(0.5)));
    stopped(checkpointed(&scene, &b, 5, true, Some(0.85)));
    let resumed = checkpointed(&scene, &b, 5, true, None).unwrap();
    let after: usize = resumed
        .plan
        .split(" after ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("the plan names the resume: {}", resumed.plan));
    assert!(after >= 1, "{}", resumed.plan);
    same_files(&a, &b);
    assert_eq!(bits(&reference), bits(&resumed));
    assert_eq!(reference.remeshings, resumed.remeshings);
    assert_eq!(
        reference.history.as_ref().unwrap(),
        resumed.history.as_ref().unwrap(),
        "the history in memory is the whole run's"
    );
}

/// The test above can fail: a checkpoint that forgets the distortion that triggers the next
/// remeshing (put back to the collapse limit, as a restart that kept no remeshing state would)
/// resumes into another run.
#[test]
fn a_resume_that_forgets_the_remeshing_threshold_is_caught() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_file(dir.path());
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    plain(&scene_path, &a);
    stopped(checkpointed(&scene_path, &b, 5, false, Some(0.85)));
    let scene = Scene::from_yaml_file(&scene_path).unwrap();
    let problem = build_problem(&scene).unwrap();
    let inputs = Inputs::of_scene_file(&scene_path, &scene).unwrap();
    let folder = file::folder(&b, STEM);
    let newest = file::list(&folder).unwrap()[0].clone();
    let (at, frames) = decode(&file::read(&newest, &inputs).unwrap(), &problem).unwrap();
    assert!(!at.records.is_empty(), "stopped after a remeshing");
    assert!(at.threshold > 1.5, "the threshold grew: {}", at.threshold);
    let forgot = encode(
        RemeshCheckpoint {
            problem: at.problem.as_ref(),
            records: &at.records,
            threshold: 1.5,
            step_now: at.step_now,
            state: at.state.clone(),
            columns: &at.columns,
            rows: &at.rows,
            watches: at.watches.clone(),
        },
        frames,
    );
    file::write(&folder, at.state.step + 1, &inputs, &forgot).unwrap();
    checkpointed(&scene_path, &b, 5, true, None).unwrap();
    let csv = |d: &Path| std::fs::read(d.join(format!("{STEM}_remeshing.csv"))).unwrap();
    assert_ne!(csv(&a), csv(&b), "the forgotten threshold went unnoticed");
}
