//! The checkpoints of a run over several ranks (`crate::distributed`): each rank writes its own
//! file holding its part of the state ([`RankPayload`]), and the ranks agree, collectively, on
//! every decision a checkpoint takes, so that none waits in a collective the others left:
//!
//! - which step is checkpointed (a wall-time cadence is one rank's clock made everyone's by
//!   [`crate::dynamics::ExplicitSolver::on_any_rank`], in `run.rs`);
//! - which checkpoint a resume starts from: the newest step for which *every* rank holds a good
//!   file (`agreed_start`); a damaged file on one rank sends all back to the older step;
//! - whether a write or a resume failed: a rank that fails stops, and every other stops with it
//!   (`agree`).

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::bytes::{Read, Reader, Short, Writer};
use super::error::{CheckpointError, RestartError};
use super::file::{self, Part};
use super::inputs::Inputs;
use super::payload::{OutputMarks, Payload};
use super::plan::CheckpointPlan;
use crate::analysis::ExecuteOptions;
use crate::distributed::Communicator;
use crate::dynamics::{ExplicitSettings, ExplicitSolver, OutputSchedule, OutputSettings};
use crate::problem::Problem;

/// A rank's checkpoint: the elements and active nodes it holds (checked on a resume against
/// the rank's own, which the element ranges and node plan give) and its part of the state
/// ([`ExplicitSolver::rank_restart_state`]) with the output marks.
#[derive(Debug, Clone, PartialEq)]
pub struct RankPayload {
    /// The rank's elements.
    pub elements: Range<usize>,
    /// The nodes it integrates, as ascending runs; its nodal values follow this order.
    pub nodes: Vec<Range<usize>>,
    /// Its part of the state and what the output holds.
    pub payload: Payload,
}

impl RankPayload {
    /// The bytes: the element range, the node runs, then [`Payload::encode`].
    pub fn encode(&self) -> Vec<u8> {
        let mut w = Writer::default();
        w.usize(self.elements.start);
        w.usize(self.elements.end);
        w.usize(self.nodes.len());
        for run in &self.nodes {
            w.usize(run.start);
            w.usize(run.end);
        }
        w.bytes.extend(self.payload.encode());
        w.bytes
    }

    /// Reads what [`Self::encode`] wrote; every byte must be used.
    pub fn decode(bytes: &[u8]) -> Read<Self> {
        let mut r = Reader::new(bytes);
        let elements = r.usize("element range")?..r.usize("element range")?;
        let runs = r.usize("node run count")?;
        if runs > r.remaining() / 16 {
            return Err(Short(format!(
                "{runs} node runs in {} bytes",
                r.remaining()
            )));
        }
        let nodes = (0..runs)
            .map(|_| Ok(r.usize("node run")?..r.usize("node run")?))
            .collect::<Read<Vec<_>>>()?;
        let rest = r.part(r.remaining(), "payload")?;
        Ok(Self {
            elements,
            nodes,
            payload: Payload::decode(rest)?,
        })
    }
}

/// `result` on this rank if every rank's is `Ok`; otherwise this rank's own error, or, where
/// only other ranks failed, [`CheckpointError::OtherRanks`] naming them. Collective: every rank
/// learns whether any failed, so that all stop together.
pub(super) fn agree<T, E: Into<RestartError>>(
    comm: &dyn Communicator,
    result: Result<T, E>,
    what: &str,
) -> Result<T, RestartError> {
    let result = result.map_err(Into::into);
    let size = comm.size();
    let mut failed = vec![0.0; size];
    comm.all_gather_f64(
        &[f64::from(u8::from(result.is_err()))],
        &vec![1; size],
        &mut failed,
    );
    let others: Vec<usize> = (0..size)
        .filter(|&r| r != comm.rank() && failed[r] != 0.0)
        .collect();
    match result {
        Ok(_) if !others.is_empty() => Err(CheckpointError::OtherRanks {
            ranks: others,
            size,
            what: what.into(),
        }
        .into()),
        other => other,
    }
}

/// The smallest of every rank's `value` (collective).
fn min_over_ranks(comm: &dyn Communicator, value: u64) -> u64 {
    u64::MAX - comm.max_u64(u64::MAX - value)
}

/// This rank's good checkpoints (step, path, payload), newest first, and the refusals of its
/// damaged ones; an error for a refusal that is not damage (another format version, changed
/// inputs, another number of ranks), which an older checkpoint would meet too.
#[allow(clippy::type_complexity)]
fn good_checkpoints(
    folder: &Path,
    part: Part,
    inputs: &Inputs,
) -> Result<(Vec<(usize, PathBuf, Vec<u8>)>, bool, Vec<String>), CheckpointError> {
    file::check_rank_count(folder, part.size)?;
    let mut good = Vec::new();
    let mut refused = Vec::new();
    let files: Vec<(PathBuf, usize)> = file::list_all(folder)?
        .into_iter()
        .filter(|(_, _, p)| *p == part)
        .map(|(path, step, _)| (path, step))
        .collect();
    for (path, step) in &files {
        match file::read(path, inputs) {
            Ok(payload) => good.push((*step, path.clone(), payload)),
            Err(e) if e.is_damage() => refused.push(e.to_string()),
            Err(e) => return Err(e),
        }
    }
    Ok((good, !files.is_empty(), refused))
}

/// The checkpoint this rank starts from (collective): with `plan.resume`, its file of the
/// newest step for which every rank holds a good one (refusals of damaged files, and a newer
/// good file set aside because another rank lacks its step, go to the log); `None` to start
/// from the beginning, when no rank has a checkpoint or there is no resume, after removing an
/// earlier run's checkpoints.
pub(super) fn agreed_start(
    folder: &Path,
    plan: &CheckpointPlan,
    options: &ExecuteOptions,
    comm: &dyn Communicator,
) -> Result<Option<(PathBuf, Vec<u8>)>, RestartError> {
    let part = Part {
        rank: comm.rank(),
        size: comm.size(),
    };
    if !plan.resume {
        let removed = file::remove_earlier(folder, part);
        agree(comm, removed, "removing an earlier run's checkpoints")?;
        return Ok(None);
    }
    let read = good_checkpoints(folder, part, &plan.inputs);
    let (mut good, any_file, refused) = agree(comm, read, "reading their checkpoints")?;
    refused.iter().for_each(|line| (options.log)(line));
    if comm.max_u64(u64::from(any_file)) == 0 {
        if part.rank == 0 {
            (options.log)(&format!(
                "no checkpoint in `{}`: the run starts from the beginning",
                folder.display()
            ));
        }
        return Ok(None);
    }
    // Steps as `step + 1`, so that 0 is "none": each round every rank proposes its newest good
    // step below the bound, the smallest proposal is the candidate, and it is taken when every
    // rank holds it; otherwise the next round looks below it.
    let mut bound = u64::MAX;
    let agreed = loop {
        let proposal = good
            .iter()
            .map(|(step, _, _)| *step as u64 + 1)
            .filter(|&s| s < bound)
            .max()
            .unwrap_or(0);
        let candidate = min_over_ranks(comm, proposal);
        if candidate == 0 {
            break None;
        }
        let held = good
            .iter()
            .any(|(step, _, _)| *step as u64 + 1 == candidate);
        if comm.max_u64(u64::from(!held)) == 0 {
            break Some((candidate - 1) as usize);
        }
        bound = candidate;
    };
    let Some(step) = agreed else {
        let mut reasons = refused;
        reasons.push(format!(
            "no step for which every one of the {} ranks holds a good checkpoint",
            part.size
        ));
        return Err(CheckpointError::NoneUsable {
            dir: folder.to_path_buf(),
            reasons: reasons.join("; "),
        }
        .into());
    };
    for (newer, path, _) in good.iter().filter(|(s, _, _)| *s > step) {
        (options.log)(&format!(
            "checkpoint `{}` of step {newer} is good, but not every rank holds a good one of \
             that step: the ranks resume from step {step}",
            path.display()
        ));
    }
    let at = good.iter().position(|(s, _, _)| *s == step);
    Ok(at.map(|i| {
        let (_, path, payload) = good.swap_remove(i);
        (path, payload)
    }))
}

/// The solver a run starts with, its output schedule, the output marks a checkpoint stored
/// (none for a run from the beginning) and the plan's line about where it starts.
pub(super) type StartingSolver<'a> = (
    ExplicitSolver<'a>,
    OutputSchedule,
    Option<OutputMarks>,
    String,
);

/// A distributed solver for this rank (over `problem`, rank `comm.rank()`), new or restored from
/// its checkpoint `start`, with the output schedule, the output marks the checkpoint stored and
/// a line for the plan. Not collective by itself: the caller [`agree`]s on the result.
pub(super) fn rank_solver<'a>(
    problem: &'a Problem,
    settings: &ExplicitSettings,
    output: OutputSettings,
    comm: &'a dyn Communicator,
    start: Option<(PathBuf, Vec<u8>)>,
) -> Result<StartingSolver<'a>, RestartError> {
    let mut solver = ExplicitSolver::new_rank(problem, settings.clone(), output, comm)?;
    let Some((path, bytes)) = start else {
        return Ok((solver, OutputSchedule::default(), None, String::new()));
    };
    let mismatch = |detail: String| CheckpointError::Mismatch {
        path: path.clone(),
        detail,
    };
    let part = RankPayload::decode(&bytes)
        .map_err(|e| mismatch(format!("its payload does not read back: {}", e.0)))?;
    let elements = solver.rank_elements().unwrap_or_default();
    if part.elements != elements || part.nodes != solver.active_nodes() {
        return Err(mismatch(format!(
            "it holds elements {:?} and {} runs of nodes, this run gives rank {} elements {:?} \
             and {} runs",
            part.elements,
            part.nodes.len(),
            comm.rank(),
            elements,
            solver.active_nodes().len()
        ))
        .into());
    }
    let step = part.payload.state.step;
    let schedule = solver
        .restore_rank(part.payload.state)
        .map_err(|e| mismatch(e.to_string()))?;
    if part.payload.marks.columns != solver.history_columns() {
        return Err(mismatch("its history columns differ from this scene's".into()).into());
    }
    let line = format!(
        "; resumed from `{}` (rank {} of {}) at step {step}",
        path.display(),
        comm.rank(),
        comm.size()
    );
    Ok((solver, schedule, Some(part.payload.marks), line))
}
