//! Checkpoint files: the header (magic, format version, the inputs, the payload's length and
//! checksum, the header's own checksum), the atomic write (temporary file, fsync, rename, fsync
//! of the folder) that never leaves a half-written checkpoint under a checkpoint's name, the
//! last two kept, and the search for the newest good one.
//!
//! Layout, little-endian: `IMPACTCK`, version `u32`, the writer's rank `u32` and number of ranks
//! `u32` (0 and 1 on one process), the inputs ([`Inputs::write`]), payload length `u64`, payload
//! FNV-1a 64 `u64`, header FNV-1a 64 `u64` (of every byte before it), then the payload.
//!
//! Each rank of a distributed run writes its own file, `step<step>.rank<r>of<P>.ckpt`, and keeps
//! its own last two; one process writes `step<step>.ckpt`.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::bytes::{fnv1a64, Reader, Writer};
use super::error::CheckpointError;
use super::inputs::Inputs;

/// The first bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = b"IMPACTCK";

/// The version of the layout and payload this binary writes and reads; raised whenever either
/// changes (2: the writer's rank and number of ranks in the header).
pub const FORMAT_VERSION: u32 = 2;

/// How many checkpoints are kept: the newest and the one before it, so that a damaged newest
/// still leaves one to resume from.
pub const KEEP: usize = 2;

/// The folder of a run's checkpoints: `<out>/<stem>-checkpoints`.
pub fn folder(out: &Path, stem: &str) -> PathBuf {
    out.join(format!("{stem}-checkpoints"))
}

/// Which rank of how many ranks wrote a checkpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Part {
    /// The writer's rank, `0..size`.
    pub rank: usize,
    /// The number of ranks of the run.
    pub size: usize,
}

impl Part {
    /// The run of one process.
    pub const ALONE: Part = Part { rank: 0, size: 1 };
}

/// The name of the checkpoint of `part` after `step` steps (zero-padded, so names sort as
/// steps).
fn file_name(step: usize, part: Part) -> String {
    if part == Part::ALONE {
        format!("step{step:012}.ckpt")
    } else {
        format!("step{step:012}.rank{}of{}.ckpt", part.rank, part.size)
    }
}

/// The step and the part a checkpoint's file name gives; `None` for another name.
pub fn parse_name(name: &str) -> Option<(usize, Part)> {
    let rest = name.strip_prefix("step")?.strip_suffix(".ckpt")?;
    let (step, part) = match rest.split_once(".rank") {
        None => (rest, Part::ALONE),
        Some((step, part)) => {
            let (rank, size) = part.split_once("of")?;
            let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
            if !digits(rank) || !digits(size) {
                return None;
            }
            let part = Part {
                rank: rank.parse().ok()?,
                size: size.parse().ok()?,
            };
            (part.rank < part.size && part.size > 1).then_some((step, part))?
        }
    };
    if step.len() != 12 || !step.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some((step.parse().ok()?, part))
}

/// Every checkpoint in `folder` with its step and part, newest (highest step) first; none when
/// the folder is missing.
pub fn list_all(folder: &Path) -> Result<Vec<(PathBuf, usize, Part)>, CheckpointError> {
    let entries = match std::fs::read_dir(folder) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(source) => {
            return Err(CheckpointError::Io {
                path: folder.to_path_buf(),
                action: "listing the checkpoints",
                source,
            })
        }
    };
    let mut files: Vec<(PathBuf, usize, Part)> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| {
            let (step, part) = parse_name(p.file_name()?.to_str()?)?;
            Some((p, step, part))
        })
        .collect();
    files.sort_by(|a, b| b.1.cmp(&a.1).then(a.2.rank.cmp(&b.2.rank)));
    Ok(files)
}

/// The checkpoints of `part` in `folder`, newest first.
pub fn list_part(folder: &Path, part: Part) -> Result<Vec<PathBuf>, CheckpointError> {
    Ok(list_all(folder)?
        .into_iter()
        .filter(|(_, _, p)| *p == part)
        .map(|(path, _, _)| path)
        .collect())
}

/// The checkpoints of a run on one process in `folder`, newest first.
pub fn list(folder: &Path) -> Result<Vec<PathBuf>, CheckpointError> {
    list_part(folder, Part::ALONE)
}

/// Refuses to resume a run on `size` ranks from `folder` when it holds checkpoints of another
/// number of ranks and none of this one: a rank's part fits only its own rank of the same
/// count.
pub fn check_rank_count(folder: &Path, size: usize) -> Result<(), CheckpointError> {
    let all = list_all(folder)?;
    if all.iter().any(|(_, _, p)| p.size == size) {
        return Ok(());
    }
    match all.first() {
        Some((_, _, p)) => Err(CheckpointError::RankCount {
            dir: folder.to_path_buf(),
            found: p.size,
            this: size,
        }),
        None => Ok(()),
    }
}

/// Removes the checkpoints of an earlier run from `folder` before a run from the beginning, so
/// that none is resumed by mistake: those of `part`, and on rank 0 those of every other number
/// of ranks (each rank removes its own, so that no two remove the same file).
pub fn remove_earlier(folder: &Path, part: Part) -> Result<(), CheckpointError> {
    for (old, _, p) in list_all(folder)? {
        if p == part || (part.rank == 0 && p.size != part.size) {
            match std::fs::remove_file(&old) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(source) => {
                    return Err(CheckpointError::Io {
                        path: old,
                        action: "removing an earlier run's checkpoint",
                        source,
                    })
                }
            }
        }
    }
    Ok(())
}

/// Writes the checkpoint of a run on one process after `step` steps ([`write_part`]).
pub fn write(
    folder: &Path,
    step: usize,
    inputs: &Inputs,
    payload: &[u8],
) -> Result<PathBuf, CheckpointError> {
    write_part(folder, step, Part::ALONE, inputs, payload)
}

/// Writes the checkpoint of `part` after `step` into `folder` atomically, then removes the
/// temporary files of `part`'s writes that a kill cut short, `part`'s checkpoints of later steps
/// and all but its newest [`KEEP`]. Returns its path.
pub fn write_part(
    folder: &Path,
    step: usize,
    part: Part,
    inputs: &Inputs,
    payload: &[u8],
) -> Result<PathBuf, CheckpointError> {
    let io = |path: &Path, action: &'static str| {
        let path = path.to_path_buf();
        move |source| CheckpointError::Io {
            path,
            action,
            source,
        }
    };
    std::fs::create_dir_all(folder).map_err(io(folder, "creating the folder"))?;
    let mut header = Writer::default();
    header.bytes.extend_from_slice(MAGIC);
    header.u32(FORMAT_VERSION);
    header.u32(part.rank as u32);
    header.u32(part.size as u32);
    inputs.write(&mut header);
    header.usize(payload.len());
    header.u64(fnv1a64(payload));
    let own = fnv1a64(&header.bytes);
    header.u64(own);

    let path = folder.join(file_name(step, part));
    let temporary = folder.join(format!("{}.tmp", file_name(step, part)));
    {
        let mut f =
            std::fs::File::create(&temporary).map_err(io(&temporary, "creating the file"))?;
        f.write_all(&header.bytes)
            .and_then(|()| f.write_all(payload))
            .map_err(io(&temporary, "writing"))?;
        f.sync_all().map_err(io(&temporary, "fsync"))?;
    }
    std::fs::rename(&temporary, &path).map_err(io(&path, "renaming the temporary file"))?;
    sync_folder(folder)?;
    // Temporary files of writes a kill cut short are no checkpoints: removed, not listed.
    // Another rank's temporary file may be a write under way: only this part's are removed.
    let of_part = |p: &Path| {
        p.file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_suffix(".tmp"))
            .and_then(parse_name)
            .is_some_and(|(_, q)| q == part)
    };
    let stale = std::fs::read_dir(folder)
        .map_err(io(folder, "listing the checkpoints"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p != &temporary && of_part(p));
    for old in stale {
        std::fs::remove_file(&old).map_err(io(&old, "removing a cut-short checkpoint"))?;
    }
    // This part's files of later steps were left by a run stopped after them and resumed from an
    // earlier checkpoint (another rank lacked them, or they were damaged): this run writes them
    // again when it gets there, and they must not take the places of the older ones kept.
    let mine = list_all(folder)?.into_iter().filter(|(_, _, p)| *p == part);
    let (later, kept): (Vec<_>, Vec<_>) = mine.partition(|(_, s, _)| *s > step);
    for (old, _, _) in later.into_iter().chain(kept.into_iter().skip(KEEP)) {
        std::fs::remove_file(&old).map_err(io(&old, "removing an old checkpoint"))?;
    }
    Ok(path)
}

/// Makes the rename durable: fsync of the folder that holds the file (POSIX; a no-op where a
/// folder cannot be opened as a file).
fn sync_folder(folder: &Path) -> Result<(), CheckpointError> {
    match std::fs::File::open(folder) {
        Ok(dir) => match dir.sync_all() {
            Ok(()) => Ok(()),
            // Some file systems refuse fsync on a folder; the rename itself is still atomic.
            Err(e) if e.kind() == std::io::ErrorKind::InvalidInput => Ok(()),
            Err(source) => Err(CheckpointError::Io {
                path: folder.to_path_buf(),
                action: "fsync of the folder",
                source,
            }),
        },
        Err(_) => Ok(()),
    }
}

/// Reads the checkpoint at `path`, checks its magic, version, checksums and inputs against
/// `inputs`, and returns its payload.
pub fn read(path: &Path, inputs: &Inputs) -> Result<Vec<u8>, CheckpointError> {
    let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
        path: path.to_path_buf(),
        action: "reading",
        source,
    })?;
    let truncated = |detail: String| CheckpointError::Truncated {
        path: path.to_path_buf(),
        detail,
    };
    if bytes.len() < MAGIC.len() + 4 {
        return Err(truncated(format!(
            "{} bytes, shorter than a header",
            bytes.len()
        )));
    }
    if &bytes[..MAGIC.len()] != MAGIC {
        return Err(CheckpointError::NotACheckpoint {
            path: path.to_path_buf(),
        });
    }
    let mut r = Reader::new(&bytes[MAGIC.len()..]);
    let short = |e: super::bytes::Short| truncated(e.0);
    let version = r.u32("format version").map_err(short)?;
    if version != FORMAT_VERSION {
        return Err(CheckpointError::Version {
            path: path.to_path_buf(),
            found: version,
            expected: FORMAT_VERSION,
        });
    }
    let rank = r.u32("writer's rank").map_err(short)? as usize;
    let size = r.u32("number of ranks").map_err(short)? as usize;
    let stored_inputs = Inputs::read(&mut r).map_err(short)?;
    let payload_len = r.usize("payload length").map_err(short)?;
    let payload_sum = r.u64("payload checksum").map_err(short)?;
    let header_end = bytes.len() - r.remaining();
    let header_sum = r.u64("header checksum").map_err(short)?;
    let found = fnv1a64(&bytes[..header_end]);
    if found != header_sum {
        return Err(CheckpointError::Checksum {
            path: path.to_path_buf(),
            part: "header",
            found,
            expected: header_sum,
        });
    }
    if r.remaining() != payload_len {
        return Err(truncated(format!(
            "the header announces {payload_len} bytes of payload, the file holds {}",
            r.remaining()
        )));
    }
    let payload = &bytes[bytes.len() - payload_len..];
    let found = fnv1a64(payload);
    if found != payload_sum {
        return Err(CheckpointError::Checksum {
            path: path.to_path_buf(),
            part: "payload",
            found,
            expected: payload_sum,
        });
    }
    let named = path
        .file_name()
        .and_then(|n| n.to_str())
        .and_then(parse_name)
        .map(|(_, part)| part);
    if named.is_some_and(|p| p != Part { rank, size }) {
        return Err(CheckpointError::Mismatch {
            path: path.to_path_buf(),
            detail: format!("it was written by rank {rank} of {size}, its name says otherwise"),
        });
    }
    if let Some(difference) = stored_inputs.difference(inputs) {
        return Err(CheckpointError::InputsChanged {
            path: path.to_path_buf(),
            difference,
        });
    }
    Ok(payload.to_vec())
}

/// The payload of the newest good checkpoint in `folder` and its path, the refusals of damaged
/// newer ones (each message, to be logged) on the way; `None` when the folder holds none. A
/// refusal that is not damage (another format version, changed inputs) stops the search: an
/// older checkpoint of the same run would be refused for the same reason.
#[allow(clippy::type_complexity)]
pub fn newest_good(
    folder: &Path,
    inputs: &Inputs,
) -> Result<(Option<(PathBuf, Vec<u8>)>, Vec<String>), CheckpointError> {
    check_rank_count(folder, 1)?;
    let mut refused = Vec::new();
    let files = list(folder)?;
    for path in &files {
        match read(path, inputs) {
            Ok(payload) => return Ok((Some((path.clone(), payload)), refused)),
            Err(e) if e.is_damage() => refused.push(e.to_string()),
            Err(e) => return Err(e),
        }
    }
    if files.is_empty() {
        Ok((None, refused))
    } else {
        Err(CheckpointError::NoneUsable {
            dir: folder.to_path_buf(),
            reasons: refused.join("; "),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_give_back_their_step_and_part_and_no_other_name_is_a_checkpoint() {
        for (step, part) in [
            (0, Part::ALONE),
            (987_654_321_012, Part::ALONE),
            (40, Part { rank: 0, size: 2 }),
            (40, Part { rank: 11, size: 12 }),
        ] {
            assert_eq!(parse_name(&file_name(step, part)), Some((step, part)));
        }
        assert_eq!(
            file_name(7, Part { rank: 1, size: 3 }),
            "step000000000007.rank1of3.ckpt"
        );
        for name in [
            "step1.ckpt",
            "step00000000000x.ckpt",
            "step000000000007.ckpt.tmp",
            "step000000000007.rank3of3.ckpt",
            "step000000000007.rank0of1.ckpt",
            "step000000000007.rank-1of3.ckpt",
            "step000000000007.rankof3.ckpt",
            "notes.txt",
        ] {
            assert_eq!(parse_name(name), None, "{name}");
        }
    }
}
