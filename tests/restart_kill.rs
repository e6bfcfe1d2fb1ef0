//! `impact-vv scene --checkpoint-every... --resume` against `kill -9`: the small drop test
//! (tests/restart/small-drop.yaml: a microplane-concrete beam struck by a steel hammer, with
//! friction and gravity) is killed at ten seeded random times, resumed after each kill, and run to
//! its end; its history CSV, field frames and collection are then byte for byte those of the run
//! never stopped; so is a run that remeshes, killed five times. Checkpoints by wall time and by
//! the scene's own key change nothing either.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod cli_common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cli_common::*;
use impact_solver::rng::SplitMix64;

const SCENE: &str = "tests/restart/small-drop.yaml";

/// `impact-vv scene SCENE --out out` with `extra` arguments, one rayon thread, from the
/// repository root.
fn scene_command(scene: &str, out: &Path, extra: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_impact-vv"));
    cmd.args(["scene", scene, "--out"])
        .arg(out)
        .args(extra)
        .env("RAYON_NUM_THREADS", "1")
        .current_dir(repo())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    cmd
}

/// Runs to the end; its standard output.
fn run_to_end(scene: &str, out: &Path, extra: &[&str]) -> String {
    let o = scene_command(scene, out, extra).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The output files of `a` (all but the checkpoints) have the bytes of those of `b`.
fn same_output(a: &Path, b: &Path) {
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
    assert!(names(a).iter().any(|n| n.ends_with("_history.csv")));
    assert!(names(a).iter().filter(|n| n.ends_with(".vtu")).count() > 5);
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

#[test]
fn ten_kills_at_random_times_then_resumed_give_the_bytes_of_the_run_never_stopped() {
    let dir = temp_dir("restart-kill");
    let (reference, killed) = (dir.join("reference"), dir.join("killed"));
    let started = Instant::now();
    run_to_end(SCENE, &reference, &[]);
    let full = started.elapsed().as_secs_f64();

    let mut rng = SplitMix64::new(0x6b69_6c6c);
    let mut interrupted = 0;
    for k in 0..10 {
        let mut args = vec!["--checkpoint-every-steps", "25"];
        if k > 0 {
            args.push("--resume");
        }
        let mut child = scene_command(SCENE, &killed, &args).spawn().unwrap();
        // A tenth of the whole run on average: each killed run gets a little further, so the
        // ten kills fall across the run rather than in its first resumes.
        let after = rng.uniform(0.05, 0.15) * full;
        std::thread::sleep(Duration::from_secs_f64(after));
        // SIGKILL on Unix: no handler runs, nothing is flushed.
        let _ = child.kill();
        let status = child.wait().unwrap();
        interrupted += usize::from(!status.success());
        let mut kept: Vec<String> = std::fs::read_dir(killed.join("small-drop-checkpoints"))
            .map(|d| {
                d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        kept.sort();
        eprintln!("kill {k} after {after:.3} s ({status}): checkpoints {kept:?}");
    }
    assert!(
        interrupted >= 5,
        "only {interrupted} of 10 kills stopped a run"
    );
    let last = run_to_end(
        SCENE,
        &killed,
        &["--checkpoint-every-steps", "25", "--resume"],
    );
    assert!(last.contains("resumed from"), "{last}");
    same_output(&reference, &killed);
}

/// A run that remeshes (the striker of `cli_common`, remeshed six times in 102 steps, with
/// section pictures and the near-tip stress) killed at five seeded random times, resumed after
/// each and run to its end: its history, remeshing and near-tip CSVs, pictures, field frames and
/// collection are byte for byte those of the run never stopped.
#[test]
fn five_kills_of_a_remeshing_run_then_resumed_give_the_bytes_of_the_run_never_stopped() {
    let dir = temp_dir("restart-kill-remesh");
    let text = remeshing_striker(
        "      check_every: 2\n      collapse_limit: 1.5\n      regrowth: 1.0\n      \
         section: { axis: z, value: 0.05 }\n      \
         near_tip: { probe: tip, radius: 0.03, steps: 5 }\n",
    )
    .replace(
        "end_time: 4.0e-5",
        "end_time: 1.6e-5\n    field_interval: 1.0e-6",
    );
    assert!(text.contains("field_interval"));
    let scene = dir.join("striker.yaml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_string_lossy().into_owned();
    let (reference, killed) = (dir.join("reference"), dir.join("killed"));
    let started = Instant::now();
    run_to_end(&scene, &reference, &[]);
    let full = started.elapsed().as_secs_f64();
    assert!(reference.join("remesh_mesh_3.json").exists(), "it remeshes");

    let mut rng = SplitMix64::new(0x7265_6d65);
    let mut interrupted = 0;
    for k in 0..5 {
        let mut args = vec!["--checkpoint-every-steps", "3"];
        if k > 0 {
            args.push("--resume");
        }
        let mut child = scene_command(&scene, &killed, &args).spawn().unwrap();
        // A fifth of the uninterrupted run on average: a run with a checkpoint every 3 steps is
        // slower, and each resumed run steps again from its last checkpoint.
        let after = rng.uniform(0.1, 0.3) * full;
        std::thread::sleep(Duration::from_secs_f64(after));
        let _ = child.kill();
        let status = child.wait().unwrap();
        interrupted += usize::from(!status.success());
        eprintln!("kill {k} after {after:.3} s ({status})");
    }
    assert!(
        interrupted >= 3,
        "only {interrupted} of 5 kills stopped a run"
    );
    let last = run_to_end(
        &scene,
        &killed,
        &["--checkpoint-every-steps", "3", "--resume"],
    );
    assert!(last.contains("resumed from"), "{last}");
    same_output(&reference, &killed);
}

#[test]
fn checkpoints_by_wall_time_or_by_the_scene_key_change_nothing() {
    let dir = temp_dir("restart-every");
    let reference = dir.join("reference");
    run_to_end(SCENE, &reference, &[]);

    let timed = dir.join("timed");
    let out = run_to_end(SCENE, &timed, &["--checkpoint-every", "0.05"]);
    assert!(
        out.contains("a checkpoint every 0.05 s of wall time"),
        "{out}"
    );
    same_output(&reference, &timed);

    // The same scene with `checkpoint: { every_steps: 30 }`, its material file by absolute path.
    let text = std::fs::read_to_string(repo().join(SCENE)).unwrap();
    let materials = repo().join("cases/materials/thesis-concrete.yaml");
    let text = text
        .replace(
            "../../cases/materials/thesis-concrete.yaml",
            &materials.to_string_lossy(),
        )
        .replace(
            "explicit: { end_time",
            "explicit: { checkpoint: { every_steps: 30 }, end_time",
        );
    assert!(text.contains("every_steps: 30"));
    let keyed_scene = dir.join("small-drop.yaml");
    std::fs::write(&keyed_scene, text).unwrap();
    let keyed = dir.join("keyed");
    let out = run_to_end(&keyed_scene.to_string_lossy(), &keyed, &[]);
    assert!(out.contains("a checkpoint every 30 steps"), "{out}");
    same_output(&reference, &keyed);
    let folder = keyed.join("small-drop-checkpoints");
    assert_eq!(std::fs::read_dir(folder).unwrap().count(), 2);
}

/// An edited scene is refused on `--resume` with exit status 2 and a message naming the file.
#[test]
fn a_resume_after_the_scene_was_edited_is_refused() {
    let dir = temp_dir("restart-edited");
    let text = std::fs::read_to_string(repo().join(SCENE)).unwrap();
    let materials = repo().join("cases/materials/thesis-concrete.yaml");
    let text = text.replace(
        "../../cases/materials/thesis-concrete.yaml",
        &materials.to_string_lossy(),
    );
    let scene = dir.join("small-drop.yaml");
    std::fs::write(&scene, &text).unwrap();
    let out = dir.join("out");
    let scene = scene.to_string_lossy().into_owned();
    run_to_end(&scene, &out, &["--checkpoint-every-steps", "100"]);
    std::fs::write(&scene, text.replace("friction: 0.5", "friction: 0.4")).unwrap();
    let o = scene_command(&scene, &out, &["--resume"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("was written for other inputs: the scene file")
            && stderr.contains("small-drop.yaml")
            && stderr.contains("has changed"),
        "{stderr}"
    );
}
