//! The field frames of a run that checkpoints: VTU files and their ParaView collection, as
//! [`crate::output::FieldFrames`] writes them, with the list of frames kept where the
//! checkpoint can read it, and restored from a checkpoint's list on a resume.

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::output::{FieldFrame, PvdWriter, RunObserver};

/// Writes `<stem>_<i:05>.vtu` frames and `<stem>.pvd`, and remembers each frame's time and file.
#[derive(Debug)]
pub struct CheckpointFrames {
    writer: PvdWriter,
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
            writer,
            frames: frames.to_vec(),
        })
    }
}

impl RunObserver for CheckpointFrames {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> Result<Option<PathBuf>> {
        let path = self.writer.write_frame(frame)?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        self.frames.push((frame.time, name));
        Ok(Some(path))
    }
}
