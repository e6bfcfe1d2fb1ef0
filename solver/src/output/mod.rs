//! What a run leaves on disk: time histories as CSV ([`history`]) and fields as VTK XML files
//! with a ParaView collection ([`vtu`]), written by the run's observers ([`observer`]). Both
//! are plain, documented formats so results can be inspected and post-processed without this
//! crate.

mod fields;
pub mod history;
pub mod observer;
pub mod pieces;
pub mod vtu;

pub use fields::{field_frame, field_frame_with_history};
pub use history::{HistoryStream, HistoryTable};
pub use observer::{
    Deadline, FieldFrames, Halt, HistoryFile, ObserverSet, Progress, Recorder, RunObserver,
    Snapshot, SnapshotView, StopFlag,
};
pub use pieces::PieceFrames;
pub use vtu::{write_vtu, FieldData, FieldFrame, PvdWriter};
