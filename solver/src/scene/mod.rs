//! The description of a simulation as serde types: what the YAML catalogue writes, what Rust code
//! can build directly. Unknown keys are rejected everywhere.

mod build;
mod explicit;
mod selector;
mod solver_spec;
mod validate;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use crate::material::without_byte_order_mark;
pub use crate::model::Component;
pub use build::{build_problem, build_problem_on_rank};
pub use explicit::ExplicitAnalysis;
pub use selector::Selector;
pub use solver_spec::ContactSolverSpec;
pub use validate::{output_stem_problem, MAX_ELEMENTS};

use crate::error::{Result, SolverError};
use crate::material::microplane::MicroplaneParameters;
use crate::material::{read_microplane_file, IsotropicElastic, MaterialModel};
use crate::mesh::{Axis, BoxSpec};
use crate::model::{CrackIndicator, ProbeQuantity, TimeFunction};
use crate::statics::StaticSettings;

/// A complete simulation: bodies, conditions and the analysis to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name of the scene; the harness's scene runs use it as the stem of their output files.
    pub name: String,
    /// Free text on what the scene models; not used by the solver.
    #[serde(default)]
    pub description: String,
    /// The bodies, each a mesh with a material; names must be unique.
    pub bodies: Vec<BodySpec>,
    /// Prescribed motions (supports, imposed velocities and displacements), applied in order.
    #[serde(default)]
    pub boundary_conditions: Vec<BoundaryCondition>,
    /// Nodal forces, each scaled by a function of time.
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Gravitational acceleration (m/s^2).
    #[serde(default)]
    pub gravity: Option<[f64; 3]>,
    /// Quantities recorded in the history at every output step.
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Pairs of bodies that may touch (thesis chapters 6 and 7).
    #[serde(default)]
    pub contact: Vec<ContactSpec>,
    /// The crack indicator of the field output (FORMULATION 5); defaults: `crack_width: 2.0e-4`
    /// and, without `length`, each element's own size.
    #[serde(default)]
    pub crack_indicator: CrackIndicator,
    /// What to run: explicit dynamics, a static analysis, or a static preload then release.
    pub analysis: Analysis,
}

/// A contact pair as written in a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Name of the pair; labels its history columns and recorded problems.
    pub name: String,
    /// The two bodies by name; the first one's nodes are the slaves of the first pass (thesis
    /// 7.2), the second's faces the masters.
    pub bodies: [String; 2],
    /// Coulomb coefficient; `.inf` sticks.
    #[serde(default)]
    pub friction: f64,
    /// High-frequency damping of the beta-2 corrections (the thesis uses 0.45).
    #[serde(default)]
    pub beta_0: f64,
    /// Detect and resolve a second time with the slave and master roles swapped (thesis 7.2);
    /// default `true`.
    #[serde(default = "default_true")]
    pub two_pass: bool,
    /// `smooth` (default): corner normals averaged over the facets within `crease_angle`
    /// degrees, interpolated at the contact point; `facet`: the master facet's normal (thesis).
    #[serde(default)]
    pub normals: crate::contact::normals::NormalKind,
    /// Angle (degrees) between facet normals above which an edge is a crease that smooth
    /// normals do not average across; default 30.
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
    /// Leave the faces on planes of symmetry out of the pair's surfaces
    /// ([`crate::contact::ContactPair::skip_symmetry_faces`]).
    #[serde(default)]
    pub skip_symmetry_faces: bool,
    /// The largest relative speed (m/s) at which a penetration left from an earlier step is
    /// removed ([`crate::contact::ContactPair::penetration_release_speed`]); none: at once.
    #[serde(default)]
    pub penetration_release_speed: Option<f64>,
}

fn default_crease_angle() -> f64 {
    30.0
}

fn default_true() -> bool {
    true
}

/// A body as written in a scene: a mesh, its material, its placement and initial velocity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name of the body, unique in the scene; conditions, loads, probes and contact pairs refer
    /// to it.
    pub name: String,
    /// Where the body's tetrahedral mesh comes from.
    pub mesh: MeshSource,
    /// The material of every element (but those of `regions`).
    pub material: MaterialSpec,
    /// Velocity field at `t = 0` (m/s); at rest without one.
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
    /// `as_read` (the default): the mesh's own element and node ids; `spatial`: renumbered in
    /// recursive-coordinate-bisection order ([`crate::mesh::Mesh::renumber_spatially`]), so
    /// that the consecutive element ranges of a distributed run are compact parts. It changes
    /// the order of the sums, so the results of the two differ at round-off.
    #[serde(default)]
    pub numbering: Numbering,
}

/// How a body's elements and nodes are numbered (`numbering:` of a body).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Numbering {
    /// As the mesh generator or file gives them.
    #[default]
    AsRead,
    /// In recursive-coordinate-bisection order of the element centroids.
    Spatial,
}

/// A material region of a body: `{ name, centroid_box: { min, max }, material }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Name of the body the region's elements become; unique among the scene's bodies.
    pub name: String,
    /// Axis-aligned box (m) that the centroid of an element must lie in (closed).
    pub centroid_box: CentroidBox,
    /// The material of the region's elements.
    pub material: MaterialSpec,
}

/// An axis-aligned box `{ min, max }` (m), closed on every side.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentroidBox {
    /// Lower corner, `x, y, z` (m), in the placed (transformed) frame.
    pub min: [f64; 3],
    /// Upper corner, `x, y, z` (m), componentwise at least `min`.
    pub max: [f64; 3],
}

impl MaterialSpec {
    /// The parameter file of a microplane material, to resolve relative paths.
    pub fn file_mut(&mut self) -> Option<&mut PathBuf> {
        match self {
            MaterialSpec::Microplane(spec) => spec.file.as_mut(),
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
    /// Small-strain Hooke's law (density, Young's modulus, Poisson's ratio).
    LinearElastic(IsotropicElastic),
    /// Saint Venant-Kirchhoff hyperelasticity: Hooke's law between the Green-Lagrange strain and
    /// the second Piola-Kirchhoff stress (thesis chapter 3).
    SaintVenantKirchhoff(IsotropicElastic),
    /// Microplane concrete (thesis chapter 5), from a parameter file or inline parameters.
    Microplane(Box<MicroplaneSpec>),
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
    /// The volumetric strain measure, replacing the parameters' (`green_lagrange_trace` or
    /// `volume_ratio`, `material/microplane/volumetric.rs`). A penetration crushes elements to a
    /// fraction of their volume while stretching them, which the trace of the Green-Lagrange
    /// strain reads as volumetric tension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volumetric_strain: Option<crate::material::microplane::VolumetricStrain>,
    /// Coulomb friction on the microplanes once their shear laws have softened, replacing the
    /// parameters' (`MicroplaneParameters::crack_friction`): the residual strength of crushed
    /// concrete under pressure, which a penetrator's nose works against.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack_friction: Option<f64>,
    /// A seeded random field of tensile strength over the body (`material/strength_field.rs`,
    /// docs/materials.md): `{ coefficient_of_variation, correlation_length, seed }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strength_field: Option<crate::material::StrengthFieldSpec>,
    /// Which length of each element is its crack band, replacing the parameters'
    /// (`MicroplaneParameters::crack_band`): `volume`, `(6 V)^(1/3)`, or `across_crack`, the
    /// element's width along its crack's normal (`material/microplane/crack_width.rs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack_band: Option<crate::material::microplane::CrackBandWidth>,
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
                if let Some(measure) = spec.volumetric_strain {
                    parameters.volumetric_strain = measure;
                }
                if let Some(mu) = spec.crack_friction {
                    parameters.crack_friction = Some(mu);
                }
                if let Some(field) = spec.strength_field {
                    parameters.strength_field = Some(field);
                }
                if let Some(band) = spec.crack_band {
                    parameters.crack_band = band;
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
    /// Axis of the rotation through the origin (any length but zero); no rotation without one.
    #[serde(default)]
    pub rotation_axis: Option<[f64; 3]>,
    /// Rotation angle about `rotation_axis` (rad), right-handed.
    #[serde(default)]
    pub rotation_angle: f64,
    /// Translation applied after the rotation (m).
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
    /// Corner of the box with the smallest coordinates (m).
    pub origin: [f64; 3],
    /// Edge lengths along `x, y, z` (m).
    pub size: [f64; 3],
    /// Number of cells along `x, y, z`; each cell is split into six tetrahedra.
    pub divisions: [usize; 3],
    /// Random displacement of the interior nodes; none without it.
    #[serde(default)]
    pub perturb: Option<Perturbation>,
    /// Axes about whose mid-plane the split of the cells into tetrahedra is mirror-symmetric,
    /// as `mirror: [x, z]`, each with an even number of divisions; empty (the default): the
    /// plain Kuhn split, the same in every cell (see [`crate::mesh::box_mesh`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mirror: Vec<Axis>,
}

impl BoxMeshSpec {
    /// The mesh generator's description of the box (without the perturbation).
    pub fn spec(&self) -> BoxSpec {
        BoxSpec {
            origin: self.origin,
            size: self.size,
            divisions: self.divisions,
            mirror: self.mirror.clone(),
        }
    }
}

/// Random displacement of interior nodes by up to `fraction` of the cell size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Perturbation {
    /// Largest displacement as a fraction of the cell size, in `[0, 0.5)`.
    pub fraction: f64,
    /// Seed of the random generator (`crate::rng`), so a perturbed mesh is reproducible.
    pub seed: u64,
}

/// `v(X) = translation + angular_velocity x (X - center) + gradient (X - center)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialVelocity {
    /// Uniform part of the velocity (m/s).
    #[serde(default)]
    pub translation: [f64; 3],
    /// Rigid rotation rate about `center` (rad/s), right-handed.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Velocity gradient `dv/dX` (1/s), row `i` the gradient of component `i`; none without it.
    #[serde(default)]
    pub gradient: Option<[[f64; 3]; 3]>,
    /// Point `X` about which the rotation and the gradient act (m, reference frame).
    #[serde(default)]
    pub center: [f64; 3],
}

/// A condition on the nodes of one body picked by a selector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCondition {
    /// Labels the reaction-force history; defaults to `bc<index>`.
    #[serde(default)]
    pub name: Option<String>,
    /// Name of the body whose nodes are constrained.
    pub body: String,
    /// Which of the body's nodes the condition holds.
    pub nodes: Selector,
    /// The prescribed motion of those nodes.
    pub motion: MotionSpec,
}

/// A prescribed motion as written in a scene; becomes a [`crate::model::Motion`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionSpec {
    /// The listed displacement components held at zero.
    Fixed(Vec<Component>),
    /// A symmetry plane normal to the component: the nodes picked (all on one plane
    /// `x[component] = const`) are held normal to it, and any other node of the body that
    /// reaches the plane is held on it while it would cross (explicit analyses; a static one
    /// holds the picked nodes only).
    Symmetry(Component),
    /// The listed components move at a velocity (m/s) given as a function of time.
    Velocity {
        /// The constrained components.
        components: Vec<Component>,
        /// Velocity of each listed component (m/s) against time (s).
        value: TimeFunction,
    },
    /// The listed components follow a displacement (m) given as a function of time.
    Displacement {
        /// The constrained components.
        components: Vec<Component>,
        /// Displacement of each listed component (m) against time (s).
        value: TimeFunction,
    },
    /// All three components move at `v(X) = translation + gradient (X - center)`, constant in
    /// time.
    AffineVelocity {
        /// Uniform velocity (m/s).
        #[serde(default)]
        translation: [f64; 3],
        /// Velocity gradient `dv/dX` (1/s), row `i` the gradient of component `i`.
        gradient: [[f64; 3]; 3],
        /// Reference point `X` of the gradient (m).
        #[serde(default)]
        center: [f64; 3],
    },
    /// All three components displaced by `u(X, t) = (translation + gradient (X - center))
    /// scale(t)`.
    AffineDisplacement {
        /// Uniform displacement (m) at scale 1.
        #[serde(default)]
        translation: [f64; 3],
        /// Displacement gradient `du/dX` (dimensionless) at scale 1, row `i` for component `i`.
        gradient: [[f64; 3]; 3],
        /// Reference point `X` of the gradient (m).
        #[serde(default)]
        center: [f64; 3],
        /// Dimensionless factor against time (s); 1 when omitted.
        #[serde(default = "unit_function")]
        scale: TimeFunction,
    },
    /// A rigid rotation of the nodes about an axis through `center`:
    /// `u = R(angle(t)) (X - center) - (X - center)`.
    Rotation {
        /// Rotation axis (any length but zero), right-handed.
        axis: [f64; 3],
        /// A point on the axis (m).
        #[serde(default)]
        center: [f64; 3],
        /// Angle in radians as a function of time.
        angle: TimeFunction,
    },
}

/// Nodal forces on the nodes of one body picked by a selector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Labels the load in error messages; defaults to `load<index>`.
    #[serde(default)]
    pub name: Option<String>,
    /// Name of the loaded body.
    pub body: String,
    /// Which of the body's nodes carry the force.
    pub nodes: Selector,
    /// Force on each selected node (N), scaled by `function`.
    pub force_per_node: [f64; 3],
    /// Dimensionless factor on the force against time (s); 1 when omitted.
    #[serde(default = "unit_function")]
    pub function: TimeFunction,
}

fn unit_function() -> TimeFunction {
    TimeFunction::Constant(1.0)
}

/// A quantity over some nodes of a body, recorded as a history column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Name of the probe; its history column.
    pub name: String,
    /// Name of the probed body.
    pub body: String,
    /// Which of the body's nodes the quantity is taken over.
    pub nodes: Selector,
    /// What is recorded, three components: the mean displacement or velocity of the nodes, or
    /// the sum of their reactions.
    pub quantity: ProbeQuantity,
}

/// The analysis a scene runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Analysis {
    /// Explicit central-difference dynamics (thesis chapter 4), remeshing one body or not.
    Explicit(ExplicitAnalysis),
    /// Static equilibrium by Newton's method in load steps.
    Static(StaticSettings),
    /// Static equilibrium under the loads, then the loads are removed and the body is released
    /// from that deformed state at rest (free vibration).
    Release {
        /// The static analysis that finds the preloaded state.
        preload: StaticSettings,
        /// The explicit run from the released state (its `remeshing`, read and checked as in
        /// an explicit analysis, is not used).
        explicit: ExplicitAnalysis,
    },
}

impl Scene {
    /// Parses a scene from YAML; `source` names the file in error messages, which carry the line.
    ///
    /// Enums are written as single-key maps (`material: { linear_elastic: {...} }`) rather than
    /// YAML tags, which reads naturally and is what users of other YAML tools expect.
    pub fn from_yaml(text: &str, source: &str) -> Result<Self> {
        let de = serde_norway::Deserializer::from_str(without_byte_order_mark(text));
        let scene: Self =
            serde_norway::with::singleton_map_recursive::deserialize(de).map_err(|e| {
                SolverError::InvalidScene {
                    entity: source.to_string(),
                    message: e.to_string(),
                }
            })?;
        scene.validate().map_err(|e| match e {
            SolverError::InvalidScene { entity, message } => SolverError::InvalidScene {
                entity: format!("{source}: {entity}"),
                message,
            },
            other => other,
        })?;
        Ok(scene)
    }

    /// Reads and parses a scene file; relative mesh and material file paths are resolved against
    /// its folder.
    pub fn from_yaml_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| SolverError::InvalidScene {
            entity: path.display().to_string(),
            message: format!("cannot read the scene file: {e}"),
        })?;
        let mut scene = Self::from_yaml(&text, &path.display().to_string())?;
        scene.resolve_paths(path.parent().unwrap_or(Path::new(".")));
        Ok(scene)
    }

    /// Reads the scene held under `key` of a YAML file (a case file keeps its scene under
    /// `scene`), relative paths resolved against the file's folder: a case's scene for a
    /// benchmark, an example or a test without the harness.
    pub fn from_yaml_file_entry(path: &Path, key: &str) -> Result<Self> {
        let source = path.display().to_string();
        let invalid = |message: String| SolverError::InvalidScene {
            entity: format!("{source} `{key}`"),
            message,
        };
        let text = std::fs::read_to_string(path)
            .map_err(|e| invalid(format!("cannot read the file: {e}")))?;
        let document: serde_norway::Value = serde_norway::from_str(without_byte_order_mark(&text))
            .map_err(|e| invalid(e.to_string()))?;
        let entry = document
            .get(key)
            .ok_or_else(|| invalid(format!("the file has no `{key}` entry")))?;
        let entry_text = serde_norway::to_string(entry).map_err(|e| invalid(e.to_string()))?;
        let mut scene = Self::from_yaml(&entry_text, &format!("{source} `{key}`"))?;
        scene.resolve_paths(path.parent().unwrap_or(Path::new(".")));
        Ok(scene)
    }

    /// Resolves the relative mesh and material file paths of the scene against `base` (the
    /// folder of the file it was read from).
    pub fn resolve_paths(&mut self, base: &Path) {
        for body in &mut self.bodies {
            if let MeshSource::Gmsh(p) = &mut body.mesh {
                if p.is_relative() {
                    *p = base.join(&*p);
                }
            }
            if let Some(p) = body.material.file_mut() {
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
    }
}
