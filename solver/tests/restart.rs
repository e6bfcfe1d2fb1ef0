//! Checkpoint and restart (`impact_solver::restart`): a run stopped after a checkpoint and
//! resumed in a fresh solver ends with the bytes of the run never stopped (history CSV, field
//! frames, collection) and the bits of its final state; damaged checkpoints are refused with a
//! message and the older one used; changed inputs and another format version are refused.
//!
//! The scene is tests/restart/small-drop.yaml: a microplane-concrete beam struck by a steel
//! hammer, with friction and gravity, so the state carries material histories and contact.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use impact_solver::analysis::{execute, ExecuteOptions, Execution};
use impact_solver::dynamics::CheckpointEvery;
use impact_solver::restart::payload::Payload;
use impact_solver::restart::{
    execute_checkpointed, file, CheckpointError, CheckpointPlan, RestartError,
};
use impact_solver::scene::build_problem;

mod restart_common;
use restart_common::{bits, inputs, scene, stopped, Log, STEM};

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
fn plain(out: &Path) -> Execution {
    let scene = scene();
    let mut problem = build_problem(&scene).unwrap();
    execute(
        &mut problem,
        &scene.analysis,
        &options(out, None, &|_| {}),
        &mut |_| {},
    )
    .unwrap()
}

#[test]
fn a_run_that_asks_for_no_final_state_returns_none_and_writes_the_same_files() {
    let dir = tempfile::tempdir().unwrap();
    let (with, without) = (dir.path().join("with"), dir.path().join("without"));
    let full = plain(&with);
    let scene = scene();
    let mut problem = build_problem(&scene).unwrap();
    let bare = execute(
        &mut problem,
        &scene.analysis,
        &ExecuteOptions {
            final_state: false,
            ..options(&without, None, &|_| {})
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(full.u.len(), problem.model.node_count());
    assert!(full.v.is_some());
    assert!(bare.u.is_empty() && bare.v.is_none());
    same_files(&with, &without);
}

/// The run with a checkpoint every `every` steps into `out`, stopped (as by a signal) once its
/// progress passes `stop_at` when given, resumed from the newest good checkpoint with `resume`.
fn checkpointed(
    out: &Path,
    every: usize,
    resume: bool,
    stop_at: Option<f64>,
    log: &Log,
) -> Result<Execution, RestartError> {
    let scene = scene();
    let mut problem = build_problem(&scene).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let sink = log.clone();
    let write = move |line: &str| sink.0.lock().unwrap().push(line.to_string());
    let plan = CheckpointPlan {
        every: CheckpointEvery {
            every_s: None,
            every_steps: Some(every),
        },
        resume,
        inputs: inputs(),
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

/// Every output file of `a` has the bytes of the same file in `b`, `b` has no other, and there
/// are more than three (a run writes its history, frames and collection).
fn same_files(a: &Path, b: &Path) {
    let count = std::fs::read_dir(a)
        .unwrap()
        .filter(|e| {
            !e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with("-checkpoints")
        })
        .count();
    assert!(count > 3, "{count} files in {}", a.display());
    restart_common::same_files(a, b);
}

#[test]
fn a_run_stopped_and_resumed_is_bitwise_the_run_never_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("c"),
    );
    let reference = plain(&a);
    let steps = reference.summary.as_ref().unwrap().steps;
    assert!(steps > 400, "{steps} steps");
    let (_, history) = bits(&reference);
    assert!(!history.is_empty(), "the beam keeps a material history");
    let force = reference.history.as_ref().unwrap().column("impact_force_y");
    assert!(
        force.unwrap().iter().any(|&f| f > 1e4),
        "the hammer strikes the beam"
    );

    // Checkpoints alone change nothing.
    let log = Log::default();
    let with = checkpointed(&c, 37, false, None, &log).unwrap();
    same_files(&a, &c);
    assert_eq!(bits(&reference), bits(&with));
    assert_eq!(
        file::list(&file::folder(&c, STEM)).unwrap().len(),
        file::KEEP
    );

    // Stopped halfway, then resumed by a fresh solver over a fresh problem.
    stopped(checkpointed(&b, 37, false, Some(0.5), &log));
    let kept = file::list(&file::folder(&b, STEM)).unwrap();
    assert_eq!(kept.len(), 2, "{kept:?}");
    let log = Log::default();
    let resumed = checkpointed(&b, 37, true, None, &log).unwrap();
    assert!(resumed.plan.contains("resumed from"), "{}", resumed.plan);
    same_files(&a, &b);
    assert_eq!(bits(&reference), bits(&resumed));
    assert_eq!(
        reference.history.as_ref().unwrap(),
        resumed.history.as_ref().unwrap(),
        "the history in memory is the whole run's"
    );
}

/// The test above can fail: a checkpoint whose material histories are put back to the virgin
/// state (as a restart that forgot them would) resumes into another run.
#[test]
fn a_resume_that_loses_the_material_histories_is_caught() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    plain(&a);
    stopped(checkpointed(&b, 50, false, Some(0.5), &Log::default()));
    let folder = file::folder(&b, STEM);
    let newest = file::list(&folder).unwrap()[0].clone();
    let mut payload = Payload::decode(&file::read(&newest, &inputs()).unwrap()).unwrap();
    let virgin = build_problem(&scene()).unwrap().model.initial_history();
    for (h, v) in payload.state.history.bodies.iter_mut().zip(virgin.bodies) {
        if let (Some(h), Some(v)) = (h, v) {
            h.values = v.values;
        }
    }
    let step = payload.state.step;
    file::write(&folder, step + 1, &inputs(), &payload.encode()).unwrap();
    checkpointed(&b, 50, true, None, &Log::default()).unwrap();
    let csv = |d: &Path| std::fs::read(d.join(format!("{STEM}_history.csv"))).unwrap();
    assert_ne!(csv(&a), csv(&b), "the lost histories went unnoticed");
}

/// Writes a run's checkpoints into `b` (stopped halfway) and returns the two kept, newest
/// first.
fn two_checkpoints(b: &Path) -> Vec<PathBuf> {
    stopped(checkpointed(b, 50, false, Some(0.5), &Log::default()));
    let kept = file::list(&file::folder(b, STEM)).unwrap();
    assert_eq!(kept.len(), 2);
    kept
}

#[test]
fn a_damaged_newest_checkpoint_is_refused_and_the_older_one_used() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a");
    plain(&a);
    for damage in ["flipped byte", "truncated"] {
        let b = dir.path().join(damage.replace(' ', "-"));
        let kept = two_checkpoints(&b);
        let mut bytes = std::fs::read(&kept[0]).unwrap();
        match damage {
            "flipped byte" => {
                let at = bytes.len() / 2;
                bytes[at] ^= 0x10;
            }
            _ => bytes.truncate(bytes.len() - 1000),
        }
        std::fs::write(&kept[0], &bytes).unwrap();
        let log = Log::default();
        let resumed = checkpointed(&b, 50, true, None, &log).unwrap();
        let lines = log.lines();
        let refusal = lines
            .iter()
            .find(|l| l.contains(&*kept[0].to_string_lossy()))
            .unwrap_or_else(|| panic!("{damage}: no refusal in {lines:?}"));
        let expected = match damage {
            "flipped byte" => "is damaged: its payload checksum",
            _ => "is truncated",
        };
        assert!(refusal.contains(expected), "{damage}: {refusal}");
        assert!(refusal.contains("the older checkpoint used"), "{refusal}");
        assert!(
            resumed.plan.contains(&*kept[1].to_string_lossy()),
            "{}",
            resumed.plan
        );
        same_files(&a, &b);
    }
}

#[test]
fn both_checkpoints_damaged_another_version_or_changed_inputs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let b = dir.path().join("b");
    let kept = two_checkpoints(&b);
    let original: Vec<Vec<u8>> = kept.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let restore = || {
        for (p, bytes) in kept.iter().zip(&original) {
            std::fs::write(p, bytes).unwrap();
        }
    };
    let refusal = || match checkpointed(&b, 50, true, None, &Log::default()) {
        Err(RestartError::Checkpoint(e)) => e,
        Err(e) => panic!("expected a refused checkpoint, the run failed: {e}"),
        Ok(_) => panic!("expected a refused checkpoint, the run resumed"),
    };

    for p in &kept {
        let bytes = std::fs::read(p).unwrap();
        std::fs::write(p, &bytes[..bytes.len() / 3]).unwrap();
    }
    let e = refusal();
    assert!(matches!(e, CheckpointError::NoneUsable { .. }), "{e}");
    assert!(e.to_string().contains("no usable checkpoint"), "{e}");
    restore();

    // The format version is at bytes 8..12, after the magic.
    let mut bytes = original[0].clone();
    bytes[8..12].copy_from_slice(&99u32.to_le_bytes());
    std::fs::write(&kept[0], &bytes).unwrap();
    let e = refusal();
    assert!(
        e.to_string()
            .contains("is of format version 99, this binary reads version 2"),
        "{e}"
    );
    restore();

    // The scene as a checkpoint of another scene file would have it: its hash differs.
    let now = inputs();
    let mut then = now.clone();
    then.0[0].hash ^= 1;
    let payload = file::read(&kept[0], &now).unwrap();
    file::write(&file::folder(&b, STEM), 1_000_000, &then, &payload).unwrap();
    let e = refusal();
    let text = e.to_string();
    assert!(
        text.contains("was written for other inputs: the scene file")
            && text.contains("small-drop.yaml")
            && text.contains("has changed"),
        "{text}"
    );
}

/// A checkpoint whose write a kill cut short is a temporary file: it is not resumed from, and the
/// next checkpoint written removes it.
#[test]
fn a_write_cut_short_leaves_the_last_good_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    plain(&a);
    let kept = two_checkpoints(&b);
    let folder = file::folder(&b, STEM);
    let half = std::fs::read(&kept[0]).unwrap();
    let cut = folder.join("step999999999999.ckpt.tmp");
    std::fs::write(&cut, &half[..half.len() / 2]).unwrap();
    let resumed = checkpointed(&b, 50, true, None, &Log::default()).unwrap();
    assert!(
        resumed.plan.contains(&*kept[0].to_string_lossy()),
        "{}",
        resumed.plan
    );
    assert!(!cut.exists(), "the cut-short write is left");
    same_files(&a, &b);
}
