//! The files a run that remeshes writes besides its history and fields, with an output folder:
//! the records as `<stem>_remeshing.csv`, the scene's `section` pictures as
//! `<stem>_mesh_<k>.json`, its `near_tip` stresses as `<stem>_near_tip.csv` (module `remesh`,
//! `watch.rs`), and the contact problems its pairs record. The plain run and the run with
//! checkpoints ([`crate::restart`]) build and close them the same way.

use std::path::PathBuf;

use super::ExecuteOptions;
use crate::contact::RecordedProblem;
use crate::dynamics::RunState;
use crate::problem::Problem;
use crate::remesh::{
    NearTipStress, RemeshPolicy, RemeshSettings, RemeshWatch, RemeshingCsv, SectionPictures,
    Watches,
};
use crate::SolverError;

/// The watches of a run that remeshes that write files.
pub struct RemeshOutputs {
    csv: Option<RemeshingCsv>,
    pictures: Option<SectionPictures>,
    near_tip: Option<NearTipStress>,
    recorded: RecordedProblems,
}

/// The contact problems a run that remeshes records, stretch by stretch (pairs with
/// `record_problems_every`).
#[derive(Default)]
struct RecordedProblems(Vec<RecordedProblem>);

impl RemeshWatch for RecordedProblems {
    fn contact_problems(&mut self, problems: &[RecordedProblem]) {
        self.0.extend_from_slice(problems);
    }
}

impl RemeshOutputs {
    /// The files of `remeshing` on `problem` (the problem the run starts from) under
    /// `options.out`, created (empty but for their headers); none without an output folder.
    pub fn new(
        problem: &Problem,
        remeshing: &RemeshSettings,
        policy: &RemeshPolicy,
        options: &ExecuteOptions,
    ) -> Result<Self, SolverError> {
        let stem = options.stem;
        let csv = options
            .out
            .map(|dir| RemeshingCsv::create(&dir.join(format!("{stem}_remeshing.csv"))))
            .transpose()?;
        let pictures = match (options.out, &remeshing.section) {
            (Some(dir), Some(spec)) => {
                Some(SectionPictures::new(spec.clone(), policy.body, dir, stem)?)
            }
            _ => None,
        };
        let near_tip = match (options.out, &remeshing.near_tip) {
            (Some(dir), Some(spec)) => Some(NearTipStress::new(
                spec.clone(),
                problem,
                policy.body,
                &dir.join(format!("{stem}_near_tip.csv")),
            )?),
            _ => None,
        };
        Ok(Self {
            csv,
            pictures,
            near_tip,
            recorded: RecordedProblems::default(),
        })
    }

    /// All of them, as one watch.
    pub fn watches(&mut self) -> Watches<'_> {
        let mut watches: Vec<&mut dyn RemeshWatch> = vec![&mut self.recorded];
        watches.extend(self.csv.as_mut().map(|w| w as &mut dyn RemeshWatch));
        watches.extend(self.pictures.as_mut().map(|w| w as &mut dyn RemeshWatch));
        watches.extend(self.near_tip.as_mut().map(|w| w as &mut dyn RemeshWatch));
        Watches(watches)
    }

    /// Closes the files (the last picture taken at `end`, the run's last problem and state,
    /// or at the last step seen where the run did not complete): the files written, or the
    /// first error; and the contact problems recorded.
    pub fn close(
        self,
        end: Option<(&Problem, &RunState)>,
    ) -> (Result<Vec<PathBuf>, SolverError>, Vec<RecordedProblem>) {
        let mut written = Vec::new();
        let closed = || -> Result<(), SolverError> {
            written.extend(self.csv.map(RemeshingCsv::finish).transpose()?);
            written.extend(self.near_tip.map(NearTipStress::finish).transpose()?);
            if let Some(p) = self.pictures {
                written.extend(p.finish(end)?);
            }
            Ok(())
        };
        let closed = closed();
        (closed.map(|()| written), self.recorded.0)
    }
}
