//! Checkpoint files: the header (magic, format version, the inputs, the payload's length and
//! checksum, the header's own checksum), the atomic write (temporary file, fsync, rename, fsync
//! of the folder) that never leaves a half-written checkpoint under a checkpoint's name, the
//! last two kept, and the search for the newest good one.
//!
//! Layout, little-endian: `IMPACTCK`, version `u32`, the inputs ([`Inputs::write`]), payload
//! length `u64`, payload FNV-1a 64 `u64`, header FNV-1a 64 `u64` (of every byte before it), then
//! the payload.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::bytes::{fnv1a64, Reader, Writer};
use super::error::CheckpointError;
use super::inputs::Inputs;

/// The first bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = b"IMPACTCK";

/// The version of the layout and payload this binary writes and reads; raised whenever either
/// changes.
pub const FORMAT_VERSION: u32 = 1;

/// How many checkpoints are kept: the newest and the one before it, so that a damaged newest
/// still leaves one to resume from.
pub const KEEP: usize = 2;

/// The folder of a run's checkpoints: `<out>/<stem>-checkpoints`.
pub fn folder(out: &Path, stem: &str) -> PathBuf {
    out.join(format!("{stem}-checkpoints"))
}

/// The name of the checkpoint after `step` steps (zero-padded, so names sort as steps).
fn file_name(step: usize) -> String {
    format!("step{step:012}.ckpt")
}

/// The checkpoints in `folder`, newest (highest step) first; none when the folder is missing.
pub fn list(folder: &Path) -> Result<Vec<PathBuf>, CheckpointError> {
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
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("step") && n.ends_with(".ckpt"))
        })
        .collect();
    files.sort();
    files.reverse();
    Ok(files)
}

/// Writes the checkpoint of `step` into `folder` atomically, then removes all but the newest
/// [`KEEP`]. Returns its path.
pub fn write(
    folder: &Path,
    step: usize,
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
    inputs.write(&mut header);
    header.usize(payload.len());
    header.u64(fnv1a64(payload));
    let own = fnv1a64(&header.bytes);
    header.u64(own);

    let path = folder.join(file_name(step));
    let temporary = folder.join(format!("{}.tmp", file_name(step)));
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
    let stale = std::fs::read_dir(folder)
        .map_err(io(folder, "listing the checkpoints"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p != &temporary && p.extension().is_some_and(|x| x == "tmp"));
    for old in stale {
        std::fs::remove_file(&old).map_err(io(&old, "removing a cut-short checkpoint"))?;
    }
    for old in list(folder)?.into_iter().skip(KEEP) {
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
