//! The field frames of a run that checkpoints: VTU files and their ParaView collection, as
//! [`crate::output::FieldFrames`] writes them (or each rank's pieces, as
//! [`crate::output::PieceFrames`] does in a distributed run), with the list of frames kept where
//! the checkpoint can read it, and restored from a checkpoint's list on a resume.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::output::{FieldFrame, PieceFrames, PvdWriter, RunObserver};

/// What writes the frames: whole, or this rank's piece of each.
#[derive(Debug)]
enum Writer {
    Whole(PvdWriter),
    Pieces(PieceFrames),
}

/// Writes `<stem>_<i:05>.vtu` frames and `<stem>.pvd` (or this rank's pieces and, on rank 0,
/// `<stem>_<i:05>.pvtu` and `<stem>.pvd`), and remembers each frame's time and the file the
/// collection lists.
#[derive(Debug)]
pub struct CheckpointFrames {
    writer: Writer,
    /// Time and file name of each frame in the collection, in order.
    pub frames: Vec<(f64, String)>,
}

impl CheckpointFrames {
    /// Frames in `dir`, the collection starting with `frames` (those of the checkpoint a run
    /// resumes from; empty for a run from the start). The next frame is numbered after them,
    /// so a frame written after the checkpoint by the run that was stopped is written again,
    /// the same, by the resumed run.
    pub fn new(dir: &Path, stem: &str, frames: &[(f64, String)]) -> Result<Self> {
        let mut writer = PvdWriter::new(dir, stem)?;
        for (time, file) in frames {
            writer.add_file(*time, file.clone())?;
        }
        Ok(Self {
            writer: Writer::Whole(writer),
            frames: frames.to_vec(),
        })
    }

    /// [`Self::new`] for rank `rank` of `size` of a distributed run, whose elements are `cells`:
    /// it writes its piece of each frame.
    pub fn pieces(
        dir: &Path,
        stem: &str,
        (rank, size): (usize, usize),
        cells: Range<usize>,
        frames: &[(f64, String)],
    ) -> Result<Self> {
        Ok(Self {
            writer: Writer::Pieces(PieceFrames::resumed(dir, stem, rank, size, cells, frames)?),
            frames: frames.to_vec(),
        })
    }
}

impl RunObserver for CheckpointFrames {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> Result<Option<PathBuf>> {
        let (path, name) = match &mut self.writer {
            Writer::Whole(writer) => {
                let path = writer.write_frame(frame)?;
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                (Some(path), name)
            }
            Writer::Pieces(pieces) => {
                let name = pieces.next_name();
                (pieces.field_frame(frame)?, name)
            }
        };
        self.frames.push((frame.time, name));
        Ok(path)
    }
}
