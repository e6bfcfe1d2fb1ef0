//! Checkpoint and restart of a run over several ranks (`impact_solver::restart::ranks`), the
//! ranks played by threads ([`ThreadGroup`], the collectives the MPI ranks use): each rank
//! writes its own file; a run stopped after a checkpoint and resumed on the same number of
//! ranks ends with the bytes of the distributed run never stopped (history CSV, every rank's
//! frame pieces, the `.pvtu` files and the collection) and the bits of its final state; a
//! resume on another number of ranks is refused naming both; a damaged newest file on one rank
//! sends every rank back to the older checkpoint.
//!
//! The scene is tests/restart/small-drop.yaml (microplane beam, steel hammer, friction,
//! gravity), shortened as in `restart.rs`.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use impact_solver::analysis::{execute, ExecuteOptions, Execution};
use impact_solver::distributed::{Communicator, ThreadGroup};
use impact_solver::dynamics::CheckpointEvery;
use impact_solver::restart::{
    execute_checkpointed, file, CheckpointError, CheckpointPlan, RestartError,
};
use impact_solver::scene::build_problem;

mod restart_common;
use restart_common::{bits, inputs, same_files, scene, stopped, Log, STEM};

/// `run(rank)` on each of `ranks` threads, one rank each; the results in rank order.
fn on_ranks<T: Send>(ranks: usize, run: impl Fn(&dyn Communicator) -> T + Sync) -> Vec<T> {
    let group = ThreadGroup::new(ranks);
    std::thread::scope(|s| {
        let handles: Vec<_> = group
            .iter()
            .map(|comm| {
                let run = &run;
                s.spawn(move || run(comm))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// The run without checkpoints into `out`, as rank `comm.rank()`.
fn plain(out: &Path, comm: &dyn Communicator) -> Execution {
    let scene = scene();
    let mut problem = build_problem(&scene).unwrap();
    let options = ExecuteOptions {
        out: Some(out),
        stem: STEM,
        final_state: true,
        fields: true,
        time_limit_s: None,
        stop: None,
        ranks: Some(comm),
        log: &|_| {},
    };
    execute(&mut problem, &scene.analysis, &options, &mut |_| {}).unwrap()
}

/// A checkpoint every 37 steps.
const EVERY_37: CheckpointEvery = CheckpointEvery {
    every_s: None,
    every_steps: Some(37),
};

/// The run with a checkpoint every 37 steps into `out` as rank `comm.rank()` (on one process
/// without `comm`), stopped (as by a signal) once its progress passes `stop_at` when given,
/// resumed from the newest checkpoint every rank holds good with `resume`.
fn checkpointed(
    out: &Path,
    resume: bool,
    stop_at: Option<f64>,
    log: &Log,
    comm: Option<&dyn Communicator>,
) -> Result<Execution, RestartError> {
    checkpointed_every(out, EVERY_37, resume, stop_at, log, comm)
}

/// [`checkpointed`] with checkpoints `every`.
fn checkpointed_every(
    out: &Path,
    every: CheckpointEvery,
    resume: bool,
    stop_at: Option<f64>,
    log: &Log,
    comm: Option<&dyn Communicator>,
) -> Result<Execution, RestartError> {
    let scene = scene();
    let mut problem = build_problem(&scene).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let sink = log.clone();
    let write = move |line: &str| sink.0.lock().unwrap().push(line.to_string());
    let plan = CheckpointPlan {
        every,
        resume,
        inputs: inputs(),
    };
    let options = ExecuteOptions {
        out: Some(out),
        stem: STEM,
        final_state: true,
        fields: true,
        time_limit_s: None,
        stop: Some(flag.clone()),
        ranks: comm,
        log: &write,
    };
    execute_checkpointed(&mut problem, &scene.analysis, &options, &plan, &mut |x| {
        if stop_at.is_some_and(|at| x >= at) {
            flag.store(true, Ordering::Relaxed);
        }
    })
}

/// The checkpoints each of `ranks` ranks keeps in `out`, newest first.
fn kept(out: &Path, ranks: usize) -> Vec<Vec<PathBuf>> {
    (0..ranks)
        .map(|rank| {
            file::list_part(&file::folder(out, STEM), file::Part { rank, size: ranks }).unwrap()
        })
        .collect()
}

/// A two-rank run into `out` stopped halfway, with two checkpoints kept by each rank.
fn stopped_on_two(out: &Path) -> Vec<Vec<PathBuf>> {
    let results = on_ranks(2, |c| {
        checkpointed(out, false, Some(0.5), &Log::default(), Some(c))
    });
    results.into_iter().for_each(stopped);
    let kept = kept(out, 2);
    assert!(kept.iter().all(|k| k.len() == file::KEEP), "{kept:?}");
    kept
}

#[test]
fn a_run_on_two_ranks_stopped_and_resumed_on_two_is_bitwise_the_run_never_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let reference = on_ranks(2, |c| plain(&a, c));
    let steps = reference[0].summary.as_ref().unwrap().steps;
    assert!(steps > 400, "{steps} steps");
    let force = reference[0]
        .history
        .as_ref()
        .unwrap()
        .column("impact_force_y");
    assert!(
        force.unwrap().iter().any(|&f| f > 1e4),
        "the hammer strikes the beam"
    );
    let pieces = std::fs::read_dir(&a)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with("_1.vtu")
        })
        .count();
    assert!(
        pieces > 3,
        "rank 1 writes its piece of each frame: {pieces}"
    );

    // Checkpoints by wall time change nothing, and every rank writes the same steps though
    // each has its own clock: one rank's clock decides for all.
    let c = dir.path().join("c");
    let every_s = CheckpointEvery {
        every_s: Some(0.02),
        every_steps: None,
    };
    on_ranks(2, |r| {
        checkpointed_every(&c, every_s, false, None, &Log::default(), Some(r))
    })
    .into_iter()
    .for_each(|run| drop(run.unwrap()));
    same_files(&a, &c);
    let by_clock = kept(&c, 2);
    let steps = |files: &[PathBuf]| -> Vec<String> {
        files
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy()[..16].to_string())
            .collect()
    };
    assert!(!by_clock[0].is_empty(), "a checkpoint fell due");
    assert_eq!(steps(&by_clock[0]), steps(&by_clock[1]));

    let kept = stopped_on_two(&b);
    // Each rank's file names its rank and the number of ranks, and so does its header.
    for (rank, files) in kept.iter().enumerate() {
        let name = files[0].file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.ends_with(&format!(".rank{rank}of2.ckpt")), "{name}");
        file::read(&files[0], &inputs()).unwrap();
    }
    let logs = [Log::default(), Log::default()];
    let resumed = on_ranks(2, |c| {
        checkpointed(&b, true, None, &logs[c.rank()], Some(c))
    });
    for (rank, (run, reference)) in resumed.iter().zip(&reference).enumerate() {
        let run = run.as_ref().unwrap();
        assert!(
            run.plan.contains(&*kept[rank][0].to_string_lossy()),
            "rank {rank}: {}",
            run.plan
        );
        assert_eq!(bits(reference), bits(run), "rank {rank}: the final state");
        assert_eq!(
            reference.history.as_ref().unwrap(),
            run.history.as_ref().unwrap(),
            "rank {rank}: the history in memory is the whole run's"
        );
    }
    same_files(&a, &b);
}

/// The test above can fail: a rank that resumes without its part of the material histories
/// (its elements' entries back to the virgin state) resumes into another run.
#[test]
fn a_rank_that_loses_its_histories_is_caught() {
    use impact_solver::restart::ranks::RankPayload;
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    on_ranks(2, |c| plain(&a, c));
    let kept = stopped_on_two(&b);
    let newest = &kept[1][0];
    let mut part = RankPayload::decode(&file::read(newest, &inputs()).unwrap()).unwrap();
    let virgin = build_problem(&scene()).unwrap().model.initial_history();
    let mut changed = false;
    for (h, v) in part
        .payload
        .state
        .history
        .bodies
        .iter_mut()
        .zip(virgin.bodies)
    {
        if let (Some(h), Some(v)) = (h, v) {
            let n = h.values.len();
            changed |= h.values[..] != v.values[v.values.len() - n..];
            h.values.copy_from_slice(&v.values[v.values.len() - n..]);
        }
    }
    assert!(changed, "rank 1's elements have a history to lose");
    let folder = file::folder(&b, STEM);
    let step = part.payload.state.step;
    let part1 = file::Part { rank: 1, size: 2 };
    file::write_part(&folder, step, part1, &inputs(), &part.encode()).unwrap();
    on_ranks(2, |c| {
        checkpointed(&b, true, None, &Log::default(), Some(c)).unwrap()
    });
    let csv = |d: &Path| std::fs::read(d.join(format!("{STEM}_history.csv"))).unwrap();
    assert_ne!(csv(&a), csv(&b), "the lost histories went unnoticed");
}

#[test]
fn a_resume_on_another_number_of_ranks_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let b = dir.path().join("b");
    stopped_on_two(&b);
    let refused = |e: Result<Execution, RestartError>, this: usize| match e {
        Err(RestartError::Checkpoint(e @ CheckpointError::RankCount { .. })) => {
            let text = e.to_string();
            assert!(
                text.contains("written by a run over 2 ranks, this run has")
                    && text.contains(&format!("has {this};")),
                "{text}"
            );
        }
        Err(e) => panic!("expected the refusal of another rank count, got {e}"),
        Ok(_) => panic!("expected the refusal of another rank count, the run resumed"),
    };
    for e in on_ranks(3, |c| {
        checkpointed(&b, true, None, &Log::default(), Some(c))
    }) {
        refused(e, 3);
    }
    refused(checkpointed(&b, true, None, &Log::default(), None), 1);
    // Nothing was lost: both ranks' checkpoints are there.
    let kept = kept(&b, 2);
    assert_eq!(kept.iter().map(Vec::len).sum::<usize>(), 4);

    // A refusal on one rank alone stops both: rank 1's newest written for another scene file.
    let now = inputs();
    let mut then = now.clone();
    then.0[0].hash ^= 1;
    let payload = file::read(&kept[1][0], &now).unwrap();
    let step = step_of(&kept[1][0]);
    let part1 = file::Part { rank: 1, size: 2 };
    file::write_part(&file::folder(&b, STEM), step, part1, &then, &payload).unwrap();
    let results = on_ranks(2, |c| {
        checkpointed(&b, true, None, &Log::default(), Some(c))
    });
    let texts: Vec<String> = results
        .into_iter()
        .map(|r| match r {
            Err(RestartError::Checkpoint(e)) => e.to_string(),
            Err(e) => panic!("expected a refused checkpoint, the run failed: {e}"),
            Ok(_) => panic!("expected a refused checkpoint, the run resumed"),
        })
        .collect();
    assert!(
        texts[1].contains("was written for other inputs"),
        "{}",
        texts[1]
    );
    assert!(
        texts[0].contains("rank(s) [1] of 2 stopped"),
        "{}",
        texts[0]
    );
}

#[test]
fn a_flipped_byte_in_one_ranks_newest_checkpoint_sends_every_rank_to_the_older_one() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    on_ranks(2, |c| plain(&a, c));
    let kept = stopped_on_two(&b);
    let mut bytes = std::fs::read(&kept[1][0]).unwrap();
    let at = bytes.len() / 2;
    bytes[at] ^= 0x10;
    std::fs::write(&kept[1][0], &bytes).unwrap();
    let logs = [Log::default(), Log::default()];
    let resumed = on_ranks(2, |c| {
        checkpointed(&b, true, None, &logs[c.rank()], Some(c))
    });
    let refusal = logs[1]
        .lines()
        .into_iter()
        .find(|l| l.contains(&*kept[1][0].to_string_lossy()))
        .unwrap_or_else(|| panic!("no refusal in {:?}", logs[1].lines()));
    assert!(
        refusal.contains("is damaged: its payload checksum"),
        "{refusal}"
    );
    let set_aside = logs[0].lines();
    assert!(
        set_aside
            .iter()
            .any(|l| l.contains(&*kept[0][0].to_string_lossy())
                && l.contains("not every rank holds a good one")),
        "rank 0 sets its newest aside: {set_aside:?}"
    );
    for (rank, run) in resumed.iter().enumerate() {
        let plan = &run.as_ref().unwrap().plan;
        assert!(
            plan.contains(&*kept[rank][1].to_string_lossy()),
            "rank {rank} resumes from its older checkpoint: {plan}"
        );
    }
    same_files(&a, &b);
}

/// The step of a checkpoint, from its name.
fn step_of(path: &Path) -> usize {
    path.file_name().unwrap().to_string_lossy()[4..16]
        .parse()
        .unwrap()
}

/// A newer checkpoint only one rank holds (the other was killed while writing its own) is not
/// resumed from, and the next checkpoint written removes it, so that it does not take the
/// place of an older one both ranks hold.
#[test]
fn a_newer_checkpoint_that_only_one_rank_holds_is_removed_at_the_next_write() {
    let dir = tempfile::tempdir().unwrap();
    let b = dir.path().join("b");
    let before = stopped_on_two(&b);
    let (older, newer) = (step_of(&before[0][1]), step_of(&before[0][0]));
    std::fs::remove_file(&before[0][0]).unwrap();
    // Resumed from the older step with a checkpoint every 5 steps, stopped before the newer.
    let every_5 = CheckpointEvery {
        every_s: None,
        every_steps: Some(5),
    };
    let results = on_ranks(2, |c| {
        checkpointed_every(&b, every_5, true, Some(0.47), &Log::default(), Some(c))
    });
    results.into_iter().for_each(stopped);
    let now = kept(&b, 2);
    let steps = |files: &[PathBuf]| files.iter().map(|p| step_of(p)).collect::<Vec<_>>();
    assert!(
        steps(&now[0])[0] > older && steps(&now[0])[0] < newer,
        "checkpoints between {older} and {newer}: {now:?}"
    );
    assert_eq!(steps(&now[0]), steps(&now[1]), "{now:?}");
}
