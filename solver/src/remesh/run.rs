//! When and where an explicit run remeshes (thesis 9.2, Box 8.1): the scene's settings
//! ([`RemeshSettings`]) and the policy they give ([`RemeshPolicy`]): every `check_every` steps
//! the distortion of the remeshed body's elements is checked, and the distorted elements grown
//! by `layers` layers are remeshed. The run itself, paused between two steps for each
//! remeshing, is `driver.rs`.

use nalgebra::Vector3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SolverError};
use crate::mesh::ops::distortion::distortion;
use crate::mesh::ops::mesher::{grow_region, MesherOptions};
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
    /// to this over `safety` (selective mass scaling, `transfer/mass_scaling.rs`; each remeshing's
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
