//! An explicit run that remeshes (thesis 9.2, Box 8.1): every `check_every` steps the
//! collapse ratio (8.1) of the remeshed body's elements is checked; where one passes the limit,
//! the run pauses between two steps, the distorted elements grown by `layers` layers are
//! remeshed ([`remesh_problem`]) and the run goes on over the new mesh
//! ([`crate::dynamics::ExplicitSolver::resume`]). One set of observers and one
//! [`OutputSchedule`] span the whole run, so its history, frames and energy check read as one
//! run's.

use std::time::Instant;

use nalgebra::Vector3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::apply::remesh_problem;
use super::record::RemeshRecord;
use super::watch::RemeshWatch;
use crate::dynamics::{
    ExplicitSettings, ExplicitSolver, OutputSchedule, OutputSettings, RunState, RunSummary,
    SegmentEnd,
};
use crate::error::{Result, SolverError};
use crate::mesh::ops::distortion::distortion;
use crate::mesh::ops::mesher::{grow_region, MesherOptions};
use crate::output::{ObserverSet, Recorder, RunObserver};
use crate::problem::Problem;

/// A scene's remeshing settings (`analysis.explicit.remeshing`), the body named; see
/// [`RemeshPolicy`] for what each means.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RemeshSettings {
    /// Name of the body that is remeshed.
    pub body: String,
    /// Steps between two distortion checks.
    #[serde(default = "default_check_every")]
    pub check_every: usize,
    /// Collapse ratio above which an element is distorted.
    #[serde(default = "default_collapse_limit")]
    pub collapse_limit: f64,
    /// Layers of elements around the distorted ones.
    #[serde(default = "default_layers")]
    pub layers: usize,
    /// Smallest element volume refined again (m^3).
    #[serde(default)]
    pub min_volume: f64,
    /// Shortest edge the remesher makes by splitting, and below which it merges edges (m); 0
    /// for no limit. See [`MesherOptions::min_edge`].
    #[serde(default)]
    pub min_edge: f64,
    /// How far an edge collapse may move a curved part of the body's surface (m); 0 keeps
    /// every node there. See [`MesherOptions::surface_deviation`].
    #[serde(default)]
    pub surface_deviation: f64,
    /// Whether the elements the remesher leaves collapsed may be eroded wherever they are,
    /// whatever the surface's shape after (the body's mass kept), not only peeled from the
    /// surface where it stays a manifold; a triggered remeshing then takes every element past
    /// the limit. See
    /// [`MesherOptions::erode`].
    #[serde(default)]
    pub erode: bool,
    /// With `erode`, the largest principal stretch of an element's carried deformation past
    /// which it is failed material: a triggered remeshing takes it, and erodes it whatever its
    /// shape; 0, the default: none. See [`MesherOptions::erode_stretch`].
    #[serde(default)]
    pub erode_stretch: f64,
    /// Largest number of remeshings.
    #[serde(default = "default_max_remeshings")]
    pub max_remeshings: usize,
    /// Growth of the worst collapse ratio past the last remeshing's that triggers the next.
    #[serde(default = "default_regrowth")]
    pub regrowth: f64,
    /// The explicit step (s) below which no element of the remeshed body may bring it after a
    /// remeshing: elements whose stable step would be shorter get the mass that lengthens it
    /// to this over `safety` (selective mass scaling, `mass_scaling.rs`; each remeshing's
    /// `added_mass`); 0, the default, adds no mass.
    #[serde(default)]
    pub mass_scaling_step: f64,
    /// Pictures of the mesh in a plane at the start, after each remeshing and at the end
    /// ([`super::SectionSpec`]); none: no pictures.
    #[serde(default)]
    pub section: Option<super::SectionSpec>,
    /// The stress of the remeshed body near a probe, a few steps before and after each
    /// remeshing ([`super::NearTipSpec`]); none: not recorded.
    #[serde(default)]
    pub near_tip: Option<super::NearTipSpec>,
}

fn default_check_every() -> usize {
    10
}
fn default_collapse_limit() -> f64 {
    crate::mesh::ops::COLLAPSE_RATIO_LIMIT
}
fn default_layers() -> usize {
    1
}
fn default_max_remeshings() -> usize {
    1000
}
fn default_regrowth() -> f64 {
    1.25
}

/// The most steps `near_tip` may record about a remeshing: its buffer holds that many stress
/// fields of the region, allocated when the run starts.
pub const MAX_NEAR_TIP_STEPS: usize = 10_000;

impl RemeshSettings {
    /// Checks the ranges of the settings that need no mesh, naming the key: `regrowth` of at
    /// least 1 (below it each remeshing lowers the threshold of the next below the worst element
    /// it leaves, and the mesh grows about eightfold at every check), `check_every` of at least
    /// 1, `min_edge` and `min_volume` zero or positive and finite, `collapse_limit` finite.
    pub fn validate(&self) -> Result<()> {
        let fail = |key: &str, message: String| SolverError::InvalidScene {
            entity: format!("analysis.explicit.remeshing.{key}"),
            message,
        };
        if !(self.regrowth >= 1.0 && self.regrowth.is_finite()) {
            return Err(fail(
                "regrowth",
                format!(
                    "must be at least 1 and finite (default 1.25): below 1 every remeshing \
                     triggers the next at once; got {}",
                    self.regrowth
                ),
            ));
        }
        if self.check_every == 0 {
            return Err(fail("check_every", "counts steps: at least 1".into()));
        }
        for (key, value, unit) in [
            ("min_edge", self.min_edge, "m"),
            ("min_volume", self.min_volume, "m^3"),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(fail(
                    key,
                    format!("must be zero (none) or positive and finite ({unit}), got {value}"),
                ));
            }
        }
        if !(self.collapse_limit > 1.0 && self.collapse_limit.is_finite()) {
            return Err(fail(
                "collapse_limit",
                format!("must exceed 1 and be finite, got {}", self.collapse_limit),
            ));
        }
        if let Some(near_tip) = &self.near_tip {
            if near_tip.steps > MAX_NEAR_TIP_STEPS {
                return Err(fail(
                    "near_tip.steps",
                    format!(
                        "{} is more than the {MAX_NEAR_TIP_STEPS} steps recorded about a \
                         remeshing",
                        near_tip.steps
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The policy for `problem`: an unknown body is an error naming the known ones.
    pub fn policy(&self, problem: &Problem) -> Result<RemeshPolicy> {
        self.validate()?;
        let names: Vec<&str> = problem
            .model
            .bodies
            .iter()
            .map(|b| b.name.as_str())
            .collect();
        let body = names.iter().position(|&n| n == self.body).ok_or_else(|| {
            SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.body".to_string(),
                message: format!(
                    "no body `{}` in the scene (its bodies: {})",
                    self.body,
                    names.join(", ")
                ),
            }
        })?;
        if !(self.surface_deviation >= 0.0) {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.surface_deviation".to_string(),
                message: format!(
                    "must be zero (keep the surface) or positive, got {}",
                    self.surface_deviation
                ),
            });
        }
        if !(self.erode_stretch == 0.0 || (self.erode && self.erode_stretch > 1.0)) {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.erode_stretch".to_string(),
                message: format!(
                    "must be 0 (none) or, with `erode: true`, a stretch above 1, got {}",
                    self.erode_stretch
                ),
            });
        }
        if !(self.mass_scaling_step >= 0.0 && self.mass_scaling_step.is_finite()) {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.mass_scaling_step".to_string(),
                message: format!(
                    "must be zero (no mass scaling) or a positive time step in s, got {}",
                    self.mass_scaling_step
                ),
            });
        }
        Ok(RemeshPolicy {
            body,
            mass_scaling_step: self.mass_scaling_step,
            check_every: self.check_every,
            collapse_limit: self.collapse_limit,
            layers: self.layers,
            min_volume: self.min_volume,
            max_remeshings: self.max_remeshings,
            regrowth: self.regrowth,
            mesher: MesherOptions {
                min_edge: self.min_edge,
                surface_deviation: self.surface_deviation,
                erode: self.erode,
                erode_stretch: self.erode_stretch,
                ..MesherOptions::default()
            },
        })
    }
}

/// When and where a run remeshes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemeshPolicy {
    /// The body that is remeshed (index in the model).
    pub body: usize,
    /// Steps between two distortion checks.
    pub check_every: usize,
    /// The distortion above which an element is distorted (thesis 8.1: a collapse ratio of
    /// 10; here [`crate::mesh::ops::distortion`], which also catches slivers).
    pub collapse_limit: f64,
    /// Layers of elements added around the distorted ones, so that their nodes can move.
    pub layers: usize,
    /// The smallest element volume that is refined again (m^3; thesis (8.5), `V_min`): a
    /// distorted element of this volume or less is left out of the region, so that repeated
    /// remeshing cannot shrink the elements (and the stable time step) without bound.
    pub min_volume: f64,
    /// The largest number of remeshings; the run stops with an error past it.
    pub max_remeshings: usize,
    /// How much worse than the remeshed body's worst element right after a remeshing an
    /// element must become before the next one (see [`RemeshPolicy::threshold_after`]).
    pub regrowth: f64,
    /// The explicit step (s) selective mass scaling keeps after each remeshing; 0: none
    /// ([`RemeshSettings::mass_scaling_step`]).
    pub mass_scaling_step: f64,
    /// The mesher's settings.
    pub mesher: MesherOptions,
}

impl RemeshPolicy {
    /// The thesis' limit (8.1) on body `body`, checked every 10 steps, one layer around the
    /// distorted elements, no smallest volume and at most 1000 remeshings.
    pub fn new(body: usize) -> Self {
        Self {
            body,
            check_every: 10,
            collapse_limit: crate::mesh::ops::COLLAPSE_RATIO_LIMIT,
            layers: 1,
            min_volume: 0.0,
            max_remeshings: 1000,
            regrowth: 1.25,
            mass_scaling_step: 0.0,
            mesher: MesherOptions::default(),
        }
    }

    /// The distortion that triggers the next remeshing after one that left the body's worst
    /// element at `worst`: the limit, or `regrowth` times `worst` where the remesher could not
    /// bring every element under the limit (an element whose short edges lie on a curved part
    /// of the outer boundary, where nodes do not move, keeps its shape through a refinement):
    /// without this, each remeshing would trigger the next at once, over a region grown by the
    /// previous one's children (an indented block went 74, 84, 1083, 8402, 61193 elements in
    /// five checks).
    pub fn threshold_after(&self, worst: f64) -> f64 {
        self.collapse_limit.max(self.regrowth * worst)
    }

    /// The elements to remesh at the current coordinates `x` of `problem`: the body's elements
    /// whose distortion ([`crate::mesh::ops::distortion`]) passes `threshold` (the limit, or
    /// [`Self::threshold_after`]) and
    /// whose volume exceeds `min_volume`, grown by `layers` within the body; empty when none.
    pub fn region(&self, problem: &Problem, x: &[Vector3<f64>], threshold: f64) -> Vec<usize> {
        let m = &problem.model;
        self.grown_selection(problem, |e| {
            let corners = m.tets[e].map(|n| x[n as usize]);
            distortion(&corners) > threshold
                && crate::kinematics::signed_volume(&corners) > self.min_volume
        })
    }

    /// The body's elements for which `selected` holds, tested in parallel (every element, every
    /// few steps; a collect keeps the order), grown by `layers` layers within the body; empty
    /// when none holds.
    fn grown_selection(
        &self,
        problem: &Problem,
        selected: impl Fn(usize) -> bool + Sync,
    ) -> Vec<usize> {
        let m = &problem.model;
        let Some(body) = m.bodies.get(self.body) else {
            return Vec::new();
        };
        let chosen: Vec<usize> = body
            .elements
            .clone()
            .into_par_iter()
            .filter(|&e| selected(e))
            .collect();
        if chosen.is_empty() {
            return chosen;
        }
        grow_region(&m.tets, &chosen, self.layers)
            .into_iter()
            .filter(|e| body.elements.contains(e))
            .collect()
    }

    /// The body's elements whose carried deformation stretches past
    /// [`MesherOptions::erode_stretch`] (failed material), with `layers` layers around them;
    /// none where it is 0 or erosion is off.
    pub fn torn(&self, problem: &Problem, u: &[Vector3<f64>]) -> Vec<usize> {
        let limit = self.mesher.erode_stretch;
        if !(self.mesher.erode && limit > 0.0) {
            return Vec::new();
        }
        let m = &problem.model;
        self.grown_selection(problem, |e| {
            super::apply::largest_stretch(&m.deformation_gradient(e, u)) > limit
        })
    }
}

/// Why a segment of the run paused.
enum Pause {
    /// It did not (it finished).
    None,
    /// These elements passed the collapse limit.
    Remesh(Vec<usize>),
    /// The stable limit fell: go on with this step (s).
    TimeStep(f64),
}

/// The largest distortion of the elements of body `body` (on the model's reference, which after
/// a remeshing is the current configuration).
fn worst_distortion(model: &crate::model::Model, body: usize) -> f64 {
    model.bodies[body]
        .elements
        .clone()
        .map(|e| distortion(&model.tets[e].map(|n| model.reference[n as usize])))
        .fold(0.0, f64::max)
}

/// A run with remeshing: its summary (as [`ExplicitSolver::run_with`]'s, over the whole run),
/// the problem and state it ended with, and the record of each remeshing.
#[derive(Debug)]
pub struct RemeshingRun {
    /// The whole run's summary: history, snapshots (displacements from the reference of the
    /// mesh they were taken on), energies, timings.
    pub summary: RunSummary,
    /// The problem over the last mesh; `None` when the run never remeshed (it ended on the
    /// problem it was given).
    pub problem: Option<Problem>,
    /// The state at the end, on the last mesh.
    pub state: RunState,
    /// Every remeshing, in time order.
    pub records: Vec<RemeshRecord>,
}

/// Runs `problem` to the end time of `settings` with `observers`, remeshing as `policy` says;
/// `on_remesh` sees each remeshing's record ([`run_remeshing_watched`] without a watch).
pub fn run_remeshing(
    problem: &Problem,
    settings: &ExplicitSettings,
    output: &OutputSettings,
    policy: &RemeshPolicy,
    observers: &mut [&mut dyn RunObserver],
    on_remesh: &mut dyn FnMut(&RemeshRecord),
) -> Result<RemeshingRun> {
    run_remeshing_watched(
        problem,
        settings,
        output,
        policy,
        observers,
        on_remesh,
        &mut (),
    )
}

/// Runs `problem` to the end time of `settings` with `observers`, remeshing as `policy` says:
/// `on_remesh` sees each remeshing's record, and `watch` the start, every step and every
/// remeshing with the problem and state it made ([`RemeshWatch`]).
/// An instability or a halt writes what the observers hold and returns the error; a remeshing
/// that fails returns its error after the observers have written what they hold.
pub fn run_remeshing_watched(
    problem: &Problem,
    settings: &ExplicitSettings,
    output: &OutputSettings,
    policy: &RemeshPolicy,
    observers: &mut [&mut dyn RunObserver],
    on_remesh: &mut dyn FnMut(&RemeshRecord),
    watch: &mut dyn RemeshWatch,
) -> Result<RemeshingRun> {
    let started = Instant::now();
    let mut recorder = Recorder::default();
    let mut all: Vec<&mut dyn RunObserver> = observers.iter_mut().map(|o| &mut **o).collect();
    all.push(&mut recorder);
    let mut set = ObserverSet::new(all);
    let mut schedule = OutputSchedule::default();
    let mut owned: Option<Problem> = None;
    let mut state: Option<RunState> = None;
    let mut records: Vec<RemeshRecord> = Vec::new();
    let every = policy.check_every.max(1);
    let mut threshold = policy.collapse_limit;
    // The time step: the settings' own, or `safety` times the stable limit, shrunk where the
    // current limit falls (elements flattened under a penetrator): when the step passes
    // halfway from `safety` to 1 times the current limit, the run pauses and goes on with
    // `safety` times it (without remeshing; thesis 10.4.1.1 on the falling limit).
    let adapt = settings.time_step.is_none();
    let trigger = 0.5 * (settings.safety + 1.0);
    let mut step_now: Option<f64> = None;
    watch.start(problem);
    let (summary, last_state) = loop {
        let current = owned.as_ref().unwrap_or(problem);
        let mut resumed = settings.clone();
        resumed.time_step = resumed.time_step.or(step_now);
        let (end, now, pause, summary) = {
            let problem = current;
            let mut solver = match state.take() {
                Some(s) => ExplicitSolver::resume(problem, resumed, output.clone(), s)?,
                None => {
                    let solver = ExplicitSolver::new(problem, resumed, output.clone())?;
                    set.history_columns(&solver.history_columns())?;
                    solver
                }
            };
            let mut pause = Pause::None;
            let end = solver.run_segment(&mut set, &mut schedule, &mut |s| {
                watch.step(problem, s);
                if s.step % every != 0 {
                    return false;
                }
                let m = &problem.model;
                let x: Vec<Vector3<f64>> =
                    m.reference.iter().zip(&s.u).map(|(x, u)| x + u).collect();
                let region = policy.region(problem, &x, threshold);
                if !region.is_empty() {
                    // With erosion, every element past the limit is offered to the remesher
                    // (the regrowth threshold only decides when): one the last remeshing left
                    // collapsed, below the threshold, would otherwise stay outside the region
                    // and never be reshaped or eroded.
                    pause = Pause::Remesh(if policy.mesher.erode {
                        let mut offered = policy.region(problem, &x, policy.collapse_limit);
                        offered.extend(policy.torn(problem, &s.u));
                        offered.sort_unstable();
                        offered.dedup();
                        offered
                    } else {
                        region
                    });
                    return true;
                }
                if adapt {
                    let (limit, _) = m.current_critical_time_step(&s.u);
                    // An element turned inside out since the last step has a negative
                    // altitude: the next step's forces stop the run on it, naming the element
                    // (a step from it would be negative, and the error would blame the step).
                    if limit > 0.0 && s.time_step() > trigger * limit {
                        pause = Pause::TimeStep(settings.safety * limit);
                        return true;
                    }
                }
                false
            });
            watch.contact_problems(&solver.take_recorded_problems());
            let end = end?;
            let summary = (end == SegmentEnd::Finished)
                .then(|| solver.summary(&schedule, started, Recorder::default(), Vec::new()));
            (end, solver.into_state(), pause, summary)
        };
        if let (SegmentEnd::Finished, Some(summary)) = (end, summary) {
            break (summary, now);
        }
        let region = match pause {
            Pause::TimeStep(dt) => {
                step_now = Some(dt);
                state = Some(now);
                continue;
            }
            Pause::Remesh(region) => region,
            Pause::None => Vec::new(),
        };
        // A signal that came during the last steps stops the run here rather than after a
        // remeshing that may take seconds.
        if let Some(crate::output::Halt::Interrupted) = set.poll(None) {
            set.finish()?;
            return Err(SolverError::Interrupted {
                step: now.step,
                time: now.time,
            });
        }
        if records.len() >= policy.max_remeshings {
            let _ = set.finish();
            return Err(too_many_remeshings(policy, now.time));
        }
        // The stable limit that gives the step `mass_scaling_step` at the run's safety.
        let critical_step = policy.mass_scaling_step / settings.safety;
        let remeshed = match remesh_problem(current, &now, &region, &policy.mesher, critical_step) {
            Ok(r) => r,
            Err(e) => {
                let _ = set.finish();
                return Err(e);
            }
        };
        threshold = policy.threshold_after(worst_distortion(&remeshed.problem.model, policy.body));
        on_remesh(&remeshed.record);
        records.push(remeshed.record);
        owned = Some(remeshed.problem);
        state = Some(remeshed.state);
        // The new mesh's reference is the current configuration: its own limit applies.
        step_now = None;
        if let (Some(record), Some(p), Some(s)) = (records.last(), &owned, &state) {
            watch.remeshed(record, p, s);
        }
    };
    set.finish()?;
    let written = std::mem::take(&mut set.written);
    drop(set);
    let mut summary = summary;
    summary.history = recorder
        .history
        .unwrap_or_else(|| crate::output::HistoryTable::new(Vec::new()));
    summary.snapshots = recorder.snapshots;
    summary.written = written;
    summary.wall_seconds = started.elapsed().as_secs_f64();
    Ok(RemeshingRun {
        summary,
        problem: owned,
        state: last_state,
        records,
    })
}

/// The error of a run that needs more remeshings than `policy` allows, at time `time` (s).
fn too_many_remeshings(policy: &RemeshPolicy, time: f64) -> SolverError {
    SolverError::Remesh {
        entity: "run".to_string(),
        message: format!(
            "needs more than the {} remeshings allowed (at t = {time:.6e} s)",
            policy.max_remeshings
        ),
    }
}
