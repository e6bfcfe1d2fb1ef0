//! What a run that remeshes shows besides its history and fields, for the report's penetration
//! section (issue 21): each remeshing's record as a row of `<stem>_remeshing.csv`, written as
//! the remeshing is made ([`RemeshingCsv`]) so that a run that fails or is stopped keeps the
//! rows it computed; pictures of the mesh in a plane ([`super::SectionPictures`]); the stress
//! near a probe around each remeshing ([`super::NearTipStress`]).
//!
//! [`super::run_remeshing_watched`] shows a [`RemeshWatch`] the start of the run, every step
//! and every remeshing; what a watch writes is its own business.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::record::RemeshRecord;
use crate::contact::RecordedProblem;
use crate::dynamics::{ExplicitSolver, RunState};
use crate::error::{Result, SolverError};
use crate::problem::Problem;

/// An observer of a run that remeshes (see the module's documentation). Every method does
/// nothing by default.
pub trait RemeshWatch {
    /// Before the first step, with the problem the run starts from (displacements zero).
    fn start(&mut self, _problem: &Problem) {}

    /// After every step but the run's last, with the problem of the current mesh and the solver
    /// over it (its displacements, time and material histories after the step).
    fn step(&mut self, _problem: &Problem, _solver: &ExplicitSolver<'_>) {}

    /// After a remeshing: its record, and the problem and state the run goes on with (the new
    /// reference is the current configuration: displacements zero).
    fn remeshed(&mut self, _record: &RemeshRecord, _problem: &Problem, _state: &RunState) {}

    /// At the end of each stretch of steps on one mesh (before a remeshing, a change of time
    /// step or the run's end, and when the stretch fails), the contact problems its pairs with
    /// `record_every` recorded, in step order: they are results too, written whether or not the
    /// run completes.
    fn contact_problems(&mut self, _problems: &[RecordedProblem]) {}

    /// Adds to `marks` what the watch needs to go on from a checkpoint taken now (between two
    /// steps, after [`Self::step`] saw the last).
    fn marks(&self, _marks: &mut WatchMarks) {}

    /// Instead of [`Self::start`], for a run resumed from a checkpoint: the problem of the
    /// current mesh and the solver restored over it, the remeshings made before the checkpoint
    /// and what [`Self::marks`] gave then. The watch rewrites its files to where they stood.
    fn resumed(
        &mut self,
        _problem: &Problem,
        _solver: &ExplicitSolver<'_>,
        _records: &[RemeshRecord],
        _marks: &WatchMarks,
    ) {
    }
}

/// What the watches of a run that remeshes hold at a checkpoint, besides what the run's
/// problem and records give back.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WatchMarks {
    /// The near-tip stress's ([`super::NearTipStress`]); `None` without one.
    pub near_tip: Option<NearTipMarks>,
}

/// What [`super::NearTipStress`] holds at a checkpoint.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NearTipMarks {
    /// Every line written after the header, in order.
    pub lines: Vec<String>,
    /// The rows of the last steps, oldest first (the window before the next remeshing).
    pub recent: Vec<super::NearTipRow>,
    /// Steps of the window after the last remeshing still to write.
    pub after: usize,
}

/// No watch.
impl RemeshWatch for () {}

/// Several watches, each shown everything in the order given.
pub struct Watches<'a>(pub Vec<&'a mut dyn RemeshWatch>);

impl RemeshWatch for Watches<'_> {
    fn start(&mut self, problem: &Problem) {
        self.0.iter_mut().for_each(|w| w.start(problem));
    }

    fn step(&mut self, problem: &Problem, solver: &ExplicitSolver<'_>) {
        self.0.iter_mut().for_each(|w| w.step(problem, solver));
    }

    fn remeshed(&mut self, record: &RemeshRecord, problem: &Problem, state: &RunState) {
        self.0
            .iter_mut()
            .for_each(|w| w.remeshed(record, problem, state));
    }

    fn contact_problems(&mut self, problems: &[RecordedProblem]) {
        self.0.iter_mut().for_each(|w| w.contact_problems(problems));
    }

    fn marks(&self, marks: &mut WatchMarks) {
        self.0.iter().for_each(|w| w.marks(marks));
    }

    fn resumed(
        &mut self,
        problem: &Problem,
        solver: &ExplicitSolver<'_>,
        records: &[RemeshRecord],
        marks: &WatchMarks,
    ) {
        self.0
            .iter_mut()
            .for_each(|w| w.resumed(problem, solver, records, marks));
    }
}

/// The header of `<stem>_remeshing.csv`: time (s); elements of the whole model before and
/// after; the largest collapse ratio (8.1) before and after; kinetic and stored energy (J)
/// before and after; the jump in total energy (J); the norm of the momentum jump (kg m/s) and
/// of the uniform velocity shift that restored it (m/s); the new surface nodes moved out of a
/// contact partner and the largest move (m); the largest distortion the run watches before and
/// after and its element in each mesh; the mass selective mass scaling added (kg); the volume
/// peeled (m^3); the elements of the old mesh remeshed; the kinetic energy the transfer lost
/// and the region's nodes were given back (J) and the factor on their velocity fluctuations.
pub const REMESHING_CSV_HEADER: &str = "time,elements_before,elements_after,\
worst_collapse_before,worst_collapse_after,kinetic_before,kinetic_after,stored_before,\
stored_after,total_energy_jump,momentum_jump,velocity_shift,surface_nodes_moved,\
largest_surface_move,worst_distortion_before,worst_distortion_after,\
worst_distortion_element_before,worst_distortion_element_after,added_mass,peeled_volume,\
region_elements,kinetic_restored,fluctuation_scale";

/// One row of `<stem>_remeshing.csv` (the columns of [`REMESHING_CSV_HEADER`]), without the
/// line end; floats in Rust's shortest round-trip exponent form.
pub fn remeshing_csv_row(r: &RemeshRecord) -> String {
    format!(
        "{:e},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e},{},{},{:e},{:e},{},{:e},{:e}",
        r.time,
        r.before.elements,
        r.after.elements,
        r.before.worst_collapse_ratio,
        r.after.worst_collapse_ratio,
        r.before.kinetic,
        r.after.kinetic,
        r.before.stored,
        r.after.stored,
        r.total_energy_jump(),
        r.momentum_jump().norm(),
        r.velocity_shift.norm(),
        r.separation.moved,
        r.separation.largest_depth,
        r.before.worst_distortion,
        r.after.worst_distortion,
        r.before.worst_distortion_element,
        r.after.worst_distortion_element,
        r.added_mass,
        r.peeled_volume,
        r.region_elements,
        r.kinetic_restored,
        r.fluctuation_scale,
    )
}

/// A text file written line by line and flushed after each write, that keeps the first error
/// to return at the end (a watch cannot stop the run from inside a step).
pub(super) struct LineFile {
    path: PathBuf,
    out: Option<BufWriter<File>>,
    error: Option<std::io::Error>,
}

impl LineFile {
    /// Creates `path` (and its folder) with the line `header`.
    pub(super) fn create(path: &Path, header: &str) -> Result<Self> {
        let mut file = Self {
            path: path.to_path_buf(),
            out: None,
            error: None,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| file.failed(source))?;
        }
        let out = File::create(path).map_err(|source| file.failed(source))?;
        file.out = Some(BufWriter::new(out));
        file.write_lines(std::iter::once(header.to_string()));
        match file.error.take() {
            Some(source) => Err(file.failed(source)),
            None => Ok(file),
        }
    }

    fn failed(&self, source: std::io::Error) -> SolverError {
        SolverError::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Appends `lines` and flushes; after a first error, nothing more is written.
    pub(super) fn write_lines(&mut self, lines: impl IntoIterator<Item = String>) {
        let Some(out) = self.out.as_mut() else {
            return;
        };
        let result = lines
            .into_iter()
            .try_for_each(|l| writeln!(out, "{l}"))
            .and_then(|()| out.flush());
        if let Err(e) = result {
            self.error = Some(e);
            self.out = None;
        }
    }

    /// The file's path, or the first error met writing it.
    pub(super) fn finish(mut self) -> Result<PathBuf> {
        if let Some(out) = self.out.as_mut() {
            if let Err(e) = out.flush() {
                self.error.get_or_insert(e);
            }
        }
        match self.error.take() {
            Some(source) => Err(self.failed(source)),
            None => Ok(self.path),
        }
    }
}

/// `<stem>_remeshing.csv`, one row per remeshing written (and flushed) as the remeshing is
/// made: a run that fails, is stopped or is killed leaves the rows of the remeshings it made.
pub struct RemeshingCsv {
    file: LineFile,
}

impl RemeshingCsv {
    /// Creates the file at `path` with its header ([`REMESHING_CSV_HEADER`]).
    pub fn create(path: &Path) -> Result<Self> {
        Ok(Self {
            file: LineFile::create(path, REMESHING_CSV_HEADER)?,
        })
    }

    /// The file's path, or the first error met writing it.
    pub fn finish(self) -> Result<PathBuf> {
        self.file.finish()
    }
}

impl RemeshWatch for RemeshingCsv {
    fn remeshed(&mut self, record: &RemeshRecord, _problem: &Problem, _state: &RunState) {
        self.file
            .write_lines(std::iter::once(remeshing_csv_row(record)));
    }

    /// The rows of the remeshings before the checkpoint, from their records.
    fn resumed(
        &mut self,
        _problem: &Problem,
        _solver: &ExplicitSolver<'_>,
        records: &[RemeshRecord],
        _marks: &WatchMarks,
    ) {
        self.file.write_lines(records.iter().map(remeshing_csv_row));
    }
}
