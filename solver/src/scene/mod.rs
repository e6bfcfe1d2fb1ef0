//! The description of a simulation as serde types: what the YAML catalogue writes, what Rust code
//! can build directly. Unknown keys are rejected everywhere.

mod build;
mod selector;
mod solver_spec;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use build::build_problem;
pub use selector::Selector;
pub use solver_spec::ContactSolverSpec;

use crate::dynamics::ExplicitSettings;
use crate::error::{Result, SolverError};
use crate::material::microplane::MicroplaneParameters;
use crate::material::{read_microplane_file, IsotropicElastic, MaterialModel};
use crate::mesh::BoxSpec;
use crate::model::{CrackIndicator, ProbeQuantity, TimeFunction};
use crate::statics::StaticSettings;

/// A complete simulation: bodies, conditions and the analysis to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub bodies: Vec<BodySpec>,
    #[serde(default)]
    pub boundary_conditions: Vec<BoundaryCondition>,
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Gravitational acceleration (m/s^2).
    #[serde(default)]
    pub gravity: Option<[f64; 3]>,
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Pairs of bodies that may touch (thesis chapters 6 and 7).
    #[serde(default)]
    pub contact: Vec<ContactSpec>,
    /// The crack indicator of the field output (FORMULATION 5); defaults: `crack_width: 2.0e-4`
    /// and, without `length`, each element's own size.
    #[serde(default)]
    pub crack_indicator: CrackIndicator,
    pub analysis: Analysis,
}

/// A contact pair as written in a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    pub name: String,
    pub bodies: [String; 2],
    /// Coulomb coefficient; `.inf` sticks.
    #[serde(default)]
    pub friction: f64,
    /// High-frequency damping of the beta-2 corrections (the thesis uses 0.45).
    #[serde(default)]
    pub beta_0: f64,
    #[serde(default = "default_true")]
    pub two_pass: bool,
    /// `smooth` (default): corner normals averaged over the facets within `crease_angle`
    /// degrees, interpolated at the contact point; `facet`: the master facet's normal (thesis).
    #[serde(default)]
    pub normals: crate::contact::normals::NormalKind,
    #[serde(default = "default_crease_angle")]
    pub crease_angle: f64,
    /// A name from `contact::registry` (default `gauss-seidel/thesis`), alone or as
    /// `{ name, tolerance, max_iterations }` (see `solver_spec`).
    #[serde(default)]
    pub solver: ContactSolverSpec,
    /// Record the contact problems of every n-th step as `contact-problem/1` JSON files in the
    /// run's output folder (`<stem>-contact-problems/`).
    #[serde(default)]
    pub record_problems_every: Option<usize>,
    /// Record every vertex-face CCD query of contact detection in every n-th step, for
    /// cross-checks of the CCD (`ExplicitSolver::take_recorded_ccd_queries`).
    #[serde(default)]
    pub record_ccd_every: Option<usize>,
}

fn default_crease_angle() -> f64 {
    30.0
}

fn default_true() -> bool {
    true
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    pub mesh: MeshSource,
    pub material: MaterialSpec,
    #[serde(default)]
    pub initial_velocity: Option<InitialVelocity>,
    /// Rigid placement of the mesh: rotated about an axis through the origin, then translated.
    #[serde(default)]
    pub transform: Option<Transform>,
    /// Parts of the mesh that take another material: the elements whose centroid lies in a
    /// region's box (after `transform`) become a body of their own, named by the region, that
    /// shares the nodes of this body (bonded, one mesh). For a crack band of concrete between
    /// elastic neighbours; an element is in the first region that holds it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<RegionSpec>,
}

/// A material region of a body: `{ name, centroid_box: { min, max }, material }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    pub name: String,
    /// Axis-aligned box (m) that the centroid of an element must lie in (closed).
    pub centroid_box: CentroidBox,
    pub material: MaterialSpec,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentroidBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl MaterialSpec {
    /// The parameter file of a microplane material, to resolve relative paths.
    pub fn file_mut(&mut self) -> Option<&mut PathBuf> {
        match self {
            MaterialSpec::Microplane(MicroplaneSpec { file: Some(p), .. }) => Some(p),
            _ => None,
        }
    }
}

/// A body's material as written in a scene:
/// `{ linear_elastic: { density, youngs_modulus, poisson_ratio } }`, the same for
/// `saint_venant_kirchhoff`, or microplane concrete (thesis chapter 5) as
/// `{ microplane: { file: ../materials/thesis-concrete.yaml } }` (a parameter file, relative to
/// the scene file) or `{ microplane: { parameters: { density: ..., e1: ..., ... } } }` (inline).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialSpec {
    LinearElastic(IsotropicElastic),
    SaintVenantKirchhoff(IsotropicElastic),
    Microplane(MicroplaneSpec),
}

/// Where the parameters of a microplane body come from: exactly one of `file` and `parameters`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MicroplaneSpec {
    /// A parameter file (`parameters:` and an optional `calibration:` record, see
    /// [`crate::material::MicroplaneFile`]), relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// The parameters written out in the scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameters: Option<MicroplaneParameters>,
    /// `false`: the body responds at static rates (rate factor `F = 1`, thesis (5.110) at
    /// `gamma_dot -> 0`) whatever the parameters say. For quasi-static explicit runs, whose
    /// loading is sped up by orders of magnitude over the laboratory test they stand for: at
    /// 1e-3 to 1e-1 /s the rate law raises the strength by 13 to 25 % (and the elastic waves of
    /// an explicit run alone reach 1e-2 /s), which a static test at about 1e-6 /s does not see.
    #[serde(default = "rate_effect_on", skip_serializing_if = "is_true")]
    pub rate_effect: bool,
}

fn rate_effect_on() -> bool {
    true
}

fn is_true(b: &bool) -> bool {
    *b
}

impl MaterialSpec {
    /// The model of the body named `body`, reading a microplane parameter file where one is
    /// named. Errors name the body and, for a file, the file.
    pub fn model(&self, body: &str) -> Result<MaterialModel> {
        Ok(match self {
            MaterialSpec::LinearElastic(c) => MaterialModel::LinearElastic(*c),
            MaterialSpec::SaintVenantKirchhoff(c) => MaterialModel::SaintVenantKirchhoff(*c),
            MaterialSpec::Microplane(spec) => {
                let parameters = match (&spec.file, &spec.parameters) {
                    (Some(file), None) => read_microplane_file(file).map_err(|e| {
                        let message = match e {
                            SolverError::InvalidScene { entity, message } => {
                                format!("{entity}: {message}")
                            }
                            other => other.to_string(),
                        };
                        SolverError::InvalidScene {
                            entity: format!("body `{body}` material.microplane.file"),
                            message,
                        }
                    })?,
                    (None, Some(p)) => *p,
                    (file, _) => {
                        return Err(SolverError::InvalidScene {
                            entity: format!("body `{body}` material.microplane"),
                            message: format!(
                                "{}; give exactly one: `file: <parameter file relative to the \
                                 scene>` or `parameters: {{ ... }}`",
                                if file.is_some() {
                                    "both `file` and `parameters` are given"
                                } else {
                                    "neither `file` nor `parameters` is given"
                                }
                            ),
                        })
                    }
                };
                let mut parameters = parameters;
                if !spec.rate_effect {
                    parameters.rate_effect = None;
                }
                MaterialModel::Microplane(parameters)
            }
        })
    }
}

/// A rigid transform of a mesh (a rotation keeps every element's orientation; a mirror would
/// turn them inside out, so there is none).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    #[serde(default)]
    pub rotation_axis: Option<[f64; 3]>,
    /// Radians.
    #[serde(default)]
    pub rotation_angle: f64,
    #[serde(default)]
    pub translation: [f64; 3],
}

/// Where a body's mesh comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSource {
    /// The structured generator; optionally with interior nodes moved at random.
    Box(BoxMeshSpec),
    /// A Gmsh 4.1 file, relative to the scene file.
    Gmsh(PathBuf),
}

/// A structured box mesh (six tetrahedra per cell), as written in a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxMeshSpec {
    pub origin: [f64; 3],
    pub size: [f64; 3],
    pub divisions: [usize; 3],
    #[serde(default)]
    pub perturb: Option<Perturbation>,
}

impl BoxMeshSpec {
    pub fn spec(&self) -> BoxSpec {
        BoxSpec {
            origin: self.origin,
            size: self.size,
            divisions: self.divisions,
        }
    }
}

/// Random displacement of interior nodes by up to `fraction` of the cell size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Perturbation {
    pub fraction: f64,
    pub seed: u64,
}

/// `v(X) = translation + angular_velocity x (X - center) + gradient (X - center)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialVelocity {
    #[serde(default)]
    pub translation: [f64; 3],
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    #[serde(default)]
    pub gradient: Option<[[f64; 3]; 3]>,
    #[serde(default)]
    pub center: [f64; 3],
}

/// Displacement components, named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    X,
    Y,
    Z,
}

/// A condition on the nodes of one body picked by a selector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCondition {
    /// Labels the reaction-force history; defaults to `bc<index>`.
    #[serde(default)]
    pub name: Option<String>,
    pub body: String,
    pub nodes: Selector,
    pub motion: MotionSpec,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionSpec {
    Fixed(Vec<Component>),
    Velocity {
        components: Vec<Component>,
        value: TimeFunction,
    },
    Displacement {
        components: Vec<Component>,
        value: TimeFunction,
    },
    AffineVelocity {
        #[serde(default)]
        translation: [f64; 3],
        gradient: [[f64; 3]; 3],
        #[serde(default)]
        center: [f64; 3],
    },
    AffineDisplacement {
        #[serde(default)]
        translation: [f64; 3],
        gradient: [[f64; 3]; 3],
        #[serde(default)]
        center: [f64; 3],
        #[serde(default = "unit_function")]
        scale: TimeFunction,
    },
    Rotation {
        axis: [f64; 3],
        #[serde(default)]
        center: [f64; 3],
        /// Angle in radians as a function of time.
        angle: TimeFunction,
    },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    #[serde(default)]
    pub name: Option<String>,
    pub body: String,
    pub nodes: Selector,
    /// Force on each selected node (N), scaled by `function`.
    pub force_per_node: [f64; 3],
    #[serde(default = "unit_function")]
    pub function: TimeFunction,
}

fn unit_function() -> TimeFunction {
    TimeFunction::Constant(1.0)
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    pub name: String,
    pub body: String,
    pub nodes: Selector,
    pub quantity: ProbeQuantity,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Analysis {
    Explicit(ExplicitSettings),
    Static(StaticSettings),
    /// Static equilibrium under the loads, then the loads are removed and the body is released
    /// from that deformed state at rest (free vibration).
    Release {
        preload: StaticSettings,
        explicit: ExplicitSettings,
    },
}

impl Scene {
    /// Parses a scene from YAML; `source` names the file in error messages, which carry the line.
    ///
    /// Enums are written as single-key maps (`material: { linear_elastic: {...} }`) rather than
    /// YAML tags, which reads naturally and is what users of other YAML tools expect.
    pub fn from_yaml(text: &str, source: &str) -> Result<Self> {
        let de = serde_norway::Deserializer::from_str(text);
        serde_norway::with::singleton_map_recursive::deserialize(de).map_err(|e| {
            SolverError::InvalidScene {
                entity: source.to_string(),
                message: e.to_string(),
            }
        })
    }

    /// Reads and parses a scene file; relative mesh and material file paths are resolved against
    /// its folder.
    pub fn from_yaml_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| SolverError::InvalidScene {
            entity: path.display().to_string(),
            message: format!("cannot read the scene file: {e}"),
        })?;
        let mut scene = Self::from_yaml(&text, &path.display().to_string())?;
        let base = path.parent().unwrap_or(Path::new("."));
        for body in &mut scene.bodies {
            if let MeshSource::Gmsh(p) = &mut body.mesh {
                if p.is_relative() {
                    *p = base.join(&*p);
                }
            }
            if let MaterialSpec::Microplane(MicroplaneSpec { file: Some(p), .. }) =
                &mut body.material
            {
                if p.is_relative() {
                    *p = base.join(&*p);
                }
            }
            for p in body
                .regions
                .iter_mut()
                .filter_map(|r| r.material.file_mut())
            {
                if p.is_relative() {
                    *p = base.join(&*p);
                }
            }
        }
        Ok(scene)
    }
}
