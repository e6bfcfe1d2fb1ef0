//! What a run shows as it goes, and what may halt it, behind one interface: [`RunObserver`].
//!
//! The integrator decides *when* a history row, a field frame or a snapshot is due (the
//! intervals are analysis settings) and hands it to its observers; it writes nothing itself.
//! The observers here stream the history CSV ([`HistoryFile`]), write the VTU frames with their
//! ParaView collection ([`FieldFrames`]), keep the table and snapshots in memory ([`Recorder`]),
//! report progress ([`Progress`]) and halt a run at a wall-time limit ([`Deadline`]) or on a
//! signal ([`StopFlag`]). A caller may add its own (a live plot, a remote sink) through
//! `ExplicitSolver::run_with`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use nalgebra::Vector3;

use super::history::{HistoryStream, HistoryTable};
use super::vtu::{FieldFrame, PvdWriter};
use crate::error::Result;

/// Why an observer halts a run (the run then ends with the matching `SolverError`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Halt {
    /// The wall-time limit of `limit_s` seconds has passed.
    TimeLimit {
        /// The wall-clock limit that passed (s of real time).
        limit_s: f64,
    },
    /// A stop was asked from outside (a signal).
    Interrupted,
}

/// The state a snapshot hands to the observers (borrowed from the run).
#[derive(Debug, Clone, Copy)]
pub struct SnapshotView<'a> {
    /// Simulated time (s).
    pub time: f64,
    /// Displacement of each node (m), in model node order.
    pub u: &'a [Vector3<f64>],
    /// Crack opening of each element (m, [`crate::model::Model::crack_openings`]); empty when no
    /// body keeps a material history.
    pub crack_opening: &'a [f32],
}

/// One observer of a run. Every method has a default that does nothing, so an observer
/// implements what it watches.
pub trait RunObserver {
    /// The history's columns, once, before the first row.
    fn history_columns(&mut self, _columns: &[String]) -> Result<()> {
        Ok(())
    }

    /// A history row (in the order of the columns).
    fn history_row(&mut self, _row: &[f64]) -> Result<()> {
        Ok(())
    }

    /// Whether the observer wants field frames (building one costs a pass over the elements).
    fn wants_fields(&self) -> bool {
        false
    }

    /// A field frame; the path of a file written for it, if any.
    fn field_frame(&mut self, _frame: &FieldFrame) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// The state at a snapshot time: the displacement of every node and the crack opening of
    /// every element.
    fn snapshot(&mut self, _snapshot: &SnapshotView) {}

    /// Called after every step, with the fraction of the run done at about a hundred of them:
    /// a reason to halt the run at the end of this step, if any.
    fn poll(&mut self, _progress: Option<f64>) -> Option<Halt> {
        None
    }

    /// The run has ended (completed, halted or unstable): write out what is buffered. Returns
    /// the files written.
    fn finish(&mut self) -> Result<Vec<PathBuf>> {
        Ok(Vec::new())
    }
}

/// The history as a CSV at `path`, written as the rows come ([`HistoryStream`]): a run that is
/// killed outright leaves every row up to the last flush, one that ends leaves them all.
#[derive(Debug)]
pub struct HistoryFile {
    path: PathBuf,
    stream: Option<HistoryStream>,
}

impl HistoryFile {
    /// An observer that will write the history CSV to `path` (created at the first row's
    /// columns; nothing is opened yet).
    pub fn new(path: PathBuf) -> Self {
        Self { path, stream: None }
    }
}

impl RunObserver for HistoryFile {
    fn history_columns(&mut self, columns: &[String]) -> Result<()> {
        self.stream = Some(HistoryStream::create(&self.path, columns)?);
        Ok(())
    }

    fn history_row(&mut self, row: &[f64]) -> Result<()> {
        match self.stream.as_mut() {
            Some(stream) => stream.append(row),
            None => Ok(()),
        }
    }

    fn finish(&mut self) -> Result<Vec<PathBuf>> {
        match self.stream.take() {
            Some(mut stream) => {
                stream.flush()?;
                Ok(vec![self.path.clone()])
            }
            None => Ok(Vec::new()),
        }
    }
}

/// Field frames as VTU files with a ParaView collection (`<stem>.pvd`) in a folder.
#[derive(Debug)]
pub struct FieldFrames {
    writer: PvdWriter,
}

impl FieldFrames {
    /// Frames written to `dir` as `<stem>_00000.vtu`, ... and collected in `<stem>.pvd`; errors
    /// when the folder cannot be created.
    pub fn new(dir: &Path, stem: &str) -> Result<Self> {
        Ok(Self {
            writer: PvdWriter::new(dir, stem)?,
        })
    }
}

impl RunObserver for FieldFrames {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> Result<Option<PathBuf>> {
        self.writer.write_frame(frame).map(Some)
    }
}

/// The displacement of every node, and the crack opening of every element, at one instant of a
/// run.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Simulated time of the snapshot (s).
    pub time: f64,
    /// Displacement of each node from its reference position (m), in model node order.
    pub u: Vec<Vector3<f64>>,
    /// Crack opening `w` of each element (m, [`crate::model::Model::crack_openings`]), in model
    /// element order; empty when no body keeps a material history (nothing can crack).
    pub crack_opening: Vec<f32>,
}

/// The history table and the snapshots, kept in memory for the run's summary.
#[derive(Debug, Default)]
pub struct Recorder {
    /// Every history row, with its columns; `None` until the run announced the columns.
    pub history: Option<HistoryTable>,
    /// The displacement snapshots in time order.
    pub snapshots: Vec<Snapshot>,
}

impl RunObserver for Recorder {
    fn history_columns(&mut self, columns: &[String]) -> Result<()> {
        self.history = Some(HistoryTable::new(columns.to_vec()));
        Ok(())
    }

    fn history_row(&mut self, row: &[f64]) -> Result<()> {
        if let Some(table) = self.history.as_mut() {
            table.push(row.to_vec());
        }
        Ok(())
    }

    fn snapshot(&mut self, snapshot: &SnapshotView) {
        self.snapshots.push(Snapshot {
            time: snapshot.time,
            u: snapshot.u.to_vec(),
            crack_opening: snapshot.crack_opening.to_vec(),
        });
    }
}

/// Reports the fraction of the run done to a callback (a progress bar).
pub struct Progress<'a>(pub &'a mut dyn FnMut(f64));

impl RunObserver for Progress<'_> {
    fn poll(&mut self, progress: Option<f64>) -> Option<Halt> {
        if let Some(fraction) = progress {
            (self.0)(fraction);
        }
        None
    }

    fn finish(&mut self) -> Result<Vec<PathBuf>> {
        (self.0)(1.0);
        Ok(Vec::new())
    }
}

/// Halts a run once a wall-time limit has passed (checked at the progress points).
#[derive(Debug, Clone, Copy)]
pub struct Deadline {
    at: Instant,
    limit_s: f64,
}

impl Deadline {
    /// `limit_s` seconds from now. The readers refuse a limit that is not positive and finite;
    /// one that gets here all the same is no limit when it is too large for a `Duration` or for
    /// the clock, and is up at once when it is not positive.
    pub fn after(limit_s: f64) -> Self {
        let now = Instant::now();
        let at = Duration::try_from_secs_f64(limit_s.max(0.0))
            .ok()
            .and_then(|d| now.checked_add(d));
        Self {
            // `None`: beyond what the clock can count, so never reached.
            at: at.unwrap_or(now + Duration::from_secs(100 * 365 * 86_400)),
            limit_s,
        }
    }
}

impl RunObserver for Deadline {
    fn poll(&mut self, progress: Option<f64>) -> Option<Halt> {
        (progress.is_some() && Instant::now() > self.at).then_some(Halt::TimeLimit {
            limit_s: self.limit_s,
        })
    }
}

/// Halts a run at the end of the step during which a flag becomes true (set by a signal
/// handler).
#[derive(Debug, Clone)]
pub struct StopFlag(pub Arc<AtomicBool>);

impl RunObserver for StopFlag {
    fn poll(&mut self, _progress: Option<f64>) -> Option<Halt> {
        self.0.load(Ordering::Relaxed).then_some(Halt::Interrupted)
    }
}

/// The observers of one run, called in order; the files they wrote, in the order written.
pub struct ObserverSet<'a, 'b> {
    observers: Vec<&'a mut (dyn RunObserver + 'b)>,
    /// Files the observers wrote so far, in the order written.
    pub written: Vec<PathBuf>,
}

impl<'a, 'b> ObserverSet<'a, 'b> {
    /// The set of `observers`, called in the order given; nothing written yet.
    pub fn new(observers: Vec<&'a mut (dyn RunObserver + 'b)>) -> Self {
        Self {
            observers,
            written: Vec::new(),
        }
    }

    /// Announces the history's columns to every observer; stops at the first error.
    pub fn history_columns(&mut self, columns: &[String]) -> Result<()> {
        self.observers
            .iter_mut()
            .try_for_each(|o| o.history_columns(columns))
    }

    /// Hands a history row to every observer; stops at the first error.
    pub fn history_row(&mut self, row: &[f64]) -> Result<()> {
        self.observers
            .iter_mut()
            .try_for_each(|o| o.history_row(row))
    }

    /// Whether any observer wants field frames, so that the run builds them.
    pub fn wants_fields(&self) -> bool {
        self.observers.iter().any(|o| o.wants_fields())
    }

    /// Hands a field frame to the observers that want one and records the files they wrote.
    pub fn field_frame(&mut self, frame: &FieldFrame) -> Result<()> {
        for o in self.observers.iter_mut().filter(|o| o.wants_fields()) {
            if let Some(path) = o.field_frame(frame)? {
                self.written.push(path);
            }
        }
        Ok(())
    }

    /// Hands a snapshot to every observer.
    pub fn snapshot(&mut self, snapshot: &SnapshotView) {
        self.observers.iter_mut().for_each(|o| o.snapshot(snapshot));
    }

    /// Polls every observer (each sees the progress); the first halt asked for, if any.
    pub fn poll(&mut self, progress: Option<f64>) -> Option<Halt> {
        self.observers
            .iter_mut()
            .fold(None, |halt, o| o.poll(progress).or(halt))
    }

    /// Finishes every observer, even after one fails; the first error, if any.
    pub fn finish(&mut self) -> Result<()> {
        let mut first_error = None;
        for o in self.observers.iter_mut() {
            match o.finish() {
                Ok(mut paths) => self.written.append(&mut paths),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        first_error.map_or(Ok(()), Err)
    }
}
