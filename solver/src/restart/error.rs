//! Why a checkpoint could not be written or was refused. Each message names the file and what
//! to do about it.

use std::path::PathBuf;

/// A checkpoint that could not be written, read or used.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file could not be written, synced, renamed or read.
    #[error("checkpoint `{path}`: {action} failed: {source}; check the folder's free space and permissions")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What was being done (`write`, `rename`, ...).
        action: &'static str,
        /// The system's error.
        source: std::io::Error,
    },
    /// The file does not start with the checkpoint's magic bytes.
    #[error("`{path}` is not a checkpoint (its first bytes are not `IMPACTCK`); remove it from the checkpoint folder")]
    NotACheckpoint {
        /// The file.
        path: PathBuf,
    },
    /// The file was written by another version of the format.
    #[error("checkpoint `{path}` is of format version {found}, this binary reads version {expected}; resume with the binary that wrote it, or run again from the start without --resume")]
    Version {
        /// The file.
        path: PathBuf,
        /// The file's version.
        found: u32,
        /// This binary's version.
        expected: u32,
    },
    /// The file ends before its header or payload does (a write cut short, a truncated copy).
    #[error(
        "checkpoint `{path}` is truncated ({detail}); it is skipped and the older checkpoint used"
    )]
    Truncated {
        /// The file.
        path: PathBuf,
        /// What was missing.
        detail: String,
    },
    /// The payload's checksum does not match (a flipped byte, a damaged disk).
    #[error("checkpoint `{path}` is damaged: its {part} checksum is {found:#018x}, the file says {expected:#018x} (FNV-1a 64); it is skipped and the older checkpoint used")]
    Checksum {
        /// The file.
        path: PathBuf,
        /// `header` or `payload`.
        part: &'static str,
        /// The checksum computed now.
        found: u64,
        /// The checksum stored in the file.
        expected: u64,
    },
    /// An input of the run has changed since the checkpoint was written.
    #[error("checkpoint `{path}` was written for other inputs: {difference}; restore the input as it was, or run again from the start without --resume")]
    InputsChanged {
        /// The file.
        path: PathBuf,
        /// Which input differs and how.
        difference: String,
    },
    /// The payload does not fit this run (another scene's state, another mesh).
    #[error("checkpoint `{path}` does not fit this run: {detail}; run again from the start without --resume")]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        detail: String,
    },
    /// Every checkpoint in the folder was refused.
    #[error(
        "no usable checkpoint in `{dir}`: {reasons}; run again from the start without --resume"
    )]
    NoneUsable {
        /// The folder.
        dir: PathBuf,
        /// Why each was refused.
        reasons: String,
    },
    /// The checkpoints were written by a run over another number of ranks: a rank's part fits
    /// only its own rank of the same count.
    #[error("the checkpoints in `{dir}` were written by a run over {found} ranks, this run has {this}; resume it on {found} ranks, or run again from the start without --resume")]
    RankCount {
        /// The folder.
        dir: PathBuf,
        /// The number of ranks of the run that wrote them.
        found: usize,
        /// The number of ranks of this run.
        this: usize,
    },
    /// Other ranks of a distributed run refused their checkpoints or could not write them; each
    /// says why in its own message.
    #[error("rank(s) {ranks:?} of {size} stopped {what}; their own messages say why")]
    OtherRanks {
        /// The ranks that failed.
        ranks: Vec<usize>,
        /// The number of ranks.
        size: usize,
        /// When (`while writing the checkpoint of step 40`, ...).
        what: String,
    },
    /// The run is of a kind that does not checkpoint yet.
    #[error("{what} cannot be checkpointed or resumed yet; run it without --checkpoint-every, --resume and `analysis.explicit.checkpoint`")]
    Unsupported {
        /// The kind of run.
        what: String,
    },
}

impl CheckpointError {
    /// Whether the file is damaged (truncated, failed checksum, not a checkpoint), so that an
    /// older checkpoint may be used instead; other refusals stop the run.
    pub fn is_damage(&self) -> bool {
        matches!(
            self,
            CheckpointError::Truncated { .. }
                | CheckpointError::Checksum { .. }
                | CheckpointError::NotACheckpoint { .. }
        )
    }
}

/// Why a run with checkpoints stopped: the run's own error, or its checkpoint's.
#[derive(Debug, thiserror::Error)]
pub enum RestartError {
    /// The run failed as it would without checkpoints.
    #[error(transparent)]
    Run(#[from] crate::SolverError),
    /// A checkpoint could not be written, or none could be resumed from.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
}
