//! References named by cases: literal values with their source, or analytic formulas from
//! `references/analytic.rs` (crate `impact-references`) evaluated with the case's own material
//! constants.

use impact_solver::material::IsotropicElastic;
use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};

// The formulas live in the `impact-references` crate (`references/`), which the solver's tests
// use too; re-exported here so that the harness names them `crate::reference::analytic` etc.
pub use impact_references::{analytic, concrete, elastic_refinement, hinge, static_path};

/// Why a metric's reference has no value: the scene lacks what it names, a data file cannot be
/// read, or a structural reference cannot be computed. Each message names the body, file or
/// key and what to change.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceEvalError {
    /// A structural reference (hinge, elastic refinement, static path) cannot be computed.
    #[error(transparent)]
    Structural(#[from] impact_references::error::ReferenceError),
    /// A published curve cannot be read or fitted.
    #[error(transparent)]
    Curve(#[from] crate::curve::CurveError),
    /// The reference names a body the scene does not have.
    #[error("the reference names body `{body}`, which the scene does not have")]
    NoSceneBody {
        /// The body named.
        body: String,
    },
    /// The body's material cannot be read.
    #[error(transparent)]
    Material(#[from] impact_solver::SolverError),
    /// The reference names a body in a case that has no scene.
    #[error(
        "the reference names body `{body}`, but the case has no scene: state the material instead"
    )]
    BodyWithoutScene {
        /// The body named.
        body: String,
    },
    /// A structural reference in a case without a scene.
    #[error("the {reference} reference needs the case's scene")]
    NeedsScene {
        /// The reference (`elastic refinement`, `hinge`, `static path`).
        reference: &'static str,
    },
    /// A published-data file cannot be read.
    #[error("cannot read {path}: {message}")]
    ReadPublished {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// A published-data file is not valid YAML of values.
    #[error("{path}: {message}")]
    ParsePublished {
        /// The file.
        path: String,
        /// The YAML reader's error.
        message: String,
    },
    /// A published-data file lacks the key.
    #[error("{path} has no entry `{key}`; it has {keys:?}")]
    NoEntry {
        /// The file.
        path: String,
        /// The key named.
        key: String,
        /// The keys it has.
        keys: Vec<String>,
    },
}

/// Where a metric's expected value comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Reference {
    /// A published or experimental number, with its source.
    Value {
        /// The value, in the metric's unit.
        value: f64,
        /// Where it comes from (publication, table, figure).
        source: String,
    },
    /// A closed-form solution.
    Analytic(Analytic),
    /// A published or experimental value from a data file in `references/published/`, which
    /// gives each value with its unit and source.
    Published {
        /// The data file's name in `references/published/`.
        file: String,
        /// The entry of the file.
        key: String,
    },
    /// An observed failure mode of a beam (thesis 10.3.2), as the code of the `failure_mode`
    /// measure (`crate::beam::FailureMode::code`): `{ failure_mode: bending }`, or the modes a
    /// bar accepts, `{ failure_mode: [mixed, shear] }`: a measured mode among them is judged
    /// against its own code ([`Reference::judged_value`]).
    FailureMode(crate::beam::ModeSet),
    /// The elastic stiffness of the case's own scene, solved by the implicit static solver on a
    /// refined mesh (see `references/elastic_refinement.rs`).
    ElasticRefinement(elastic_refinement::ElasticStiffnessSpec),
    /// The peak of a cohesive hinge (Olesen 2001) fed with a crack-opening law of the case's own
    /// microplane material (see `references/hinge.rs`).
    Hinge(hinge::HingeSpec),
    /// The peak of the case's own scene solved by the implicit static solver along the same
    /// loading (see `references/static_path.rs`).
    StaticPath(static_path::StaticPathSpec),
    /// The initial stiffness of a measured load-opening curve in a data file of
    /// `references/published/`, by the rule the `rising_branch_slope` measure applies to the
    /// model (`crate::curve::rising_branch_slope`), so that both are measured alike.
    CurveSlope(CurveSlopeSpec),
}

/// A measured curve's initial stiffness: the least-squares slope of `y_scale * y` against
/// `x_scale * x` over the records up to the curve's peak with `y_scale * y` in `[from, to]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSlopeSpec {
    /// The CSV file's name in `references/published/`.
    pub file: String,
    /// Name of the opening column.
    pub x: String,
    /// Name of the load column.
    pub y: String,
    /// Factor on the opening (default 1; 1e3 for um from mm).
    #[serde(default = "one")]
    pub x_scale: f64,
    /// Factor on the load (default 1).
    #[serde(default = "one")]
    pub y_scale: f64,
    /// Lower end of the load window, in the scaled unit.
    pub from: f64,
    /// Upper end of the load window, in the scaled unit.
    pub to: f64,
}

fn one() -> f64 {
    1.0
}

/// The slope of [`CurveSlopeSpec`] and the line saying how it was computed.
fn curve_slope(spec: &CurveSlopeSpec) -> Result<(f64, String), ReferenceEvalError> {
    let path = published_dir().join(&spec.file);
    let columns = crate::curve::read_columns(&path, &[&spec.x, &spec.y])?;
    let w: Vec<f64> = columns[0].iter().map(|x| spec.x_scale * x).collect();
    let f: Vec<f64> = columns[1].iter().map(|y| spec.y_scale * y).collect();
    let (k, n) = crate::curve::rising_branch_slope(&f, &w, spec.from, spec.to)?;
    Ok((
        k,
        format!(
            "least-squares slope of {} against {} of {} over the {n} records before its peak \
             with a load in [{}, {}]",
            spec.y, spec.x, spec.file, spec.from, spec.to
        ),
    ))
}

/// One entry of a published-data file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PublishedValue {
    /// The value, in `unit`.
    pub value: f64,
    /// Its unit as the file states it.
    #[serde(default)]
    pub unit: String,
    /// Where it comes from (publication, table, figure).
    pub source: String,
}

/// Folder of the published-data files: `references/published/` of this repository.
pub fn published_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("references")
        .join("published")
}

fn published(file: &str, key: &str) -> Result<PublishedValue, ReferenceEvalError> {
    let path = published_dir().join(file);
    let text = std::fs::read_to_string(&path).map_err(|e| ReferenceEvalError::ReadPublished {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let values: std::collections::BTreeMap<String, PublishedValue> = serde_norway::from_str(&text)
        .map_err(|e| ReferenceEvalError::ParsePublished {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
    values
        .get(key)
        .cloned()
        .ok_or_else(|| ReferenceEvalError::NoEntry {
            path: path.display().to_string(),
            key: key.into(),
            keys: values.keys().cloned().collect(),
        })
}

/// Quantities of the uniaxial Saint-Venant-Kirchhoff solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SvkQuantity {
    /// Green-Lagrange strain along the stretch (dimensionless).
    E11,
    /// Lateral Green-Lagrange strain (dimensionless).
    E22,
    /// Second Piola-Kirchhoff stress along the stretch (Pa).
    S11,
    /// First Piola-Kirchhoff (nominal) stress along the stretch (Pa).
    P11,
    /// Cauchy stress along the stretch.
    Sigma11,
}

/// The material a formula is evaluated for: stated in the reference itself (the physical
/// problem, independent of the solver input, so a wrong solver setting shows as a failure), or
/// taken from a body of the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialRef {
    /// Elastic constants stated in the reference.
    Material(IsotropicElastic),
    /// The constants of the scene's body of this name.
    Body(String),
}

/// A closed-form reference value (formulas in `impact_references::analytic` and `concrete`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Analytic {
    /// Zero: the reference of error measures (patch-test residuals, drifts).
    Zero,
    /// Dilatational (P-wave) speed `sqrt((lambda + 2 mu) / rho)` (m/s).
    DilatationalWaveSpeed {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
    },
    /// Rayleigh surface-wave speed (m/s).
    RayleighWaveSpeed {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
    },
    /// Stress behind a plane wave driven at `velocity` into `body`: `-rho c_d v`.
    PlaneWaveStress {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
        /// Particle velocity imposed at the driven face (m/s).
        velocity: f64,
    },
    /// Saint-Venant-Kirchhoff in uniaxial stress at an axial stretch: one quantity.
    SvkUniaxial {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
        /// Axial stretch `l` (dimensionless, 1 undeformed).
        stretch: f64,
        /// Which quantity of the solution.
        quantity: SvkQuantity,
    },
    /// Cauchy stress along the stretch of Saint-Venant-Kirchhoff in uniaxial strain (laterally
    /// confined).
    SvkUniaxialStrainStress {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
        /// Axial stretch `l` (dimensionless, 1 undeformed).
        stretch: f64,
    },
    /// First bending frequency of a clamped-free Euler-Bernoulli beam of rectangular section
    /// (Hz).
    CantileverFirstFrequency {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
        /// Free length `L` (m).
        length: f64,
        /// Section depth `h` in the bending plane (m).
        depth: f64,
    },
    /// Head-on impact of two identical spheres (Hertz): one quantity.
    HertzImpact {
        /// The material: stated in the reference or taken from a body of the scene.
        of: MaterialRef,
        /// Radius of each sphere (m); the mass follows from the density.
        radius: f64,
        /// Approach speed of the two spheres (m/s).
        relative_speed: f64,
        /// Which quantity of the solution.
        quantity: HertzQuantity,
    },
    /// Mid-span load at which the extreme fibre of a simply supported beam reaches `f_r`.
    ModulusOfRuptureLoad {
        /// Modulus of rupture (flexural strength) `f_r` (Pa).
        f_r: f64,
        /// Section width `b` (m).
        width: f64,
        /// Section depth `h` (m).
        depth: f64,
        /// Span between the supports `L` (m).
        span: f64,
    },
    /// fib Model Code 2010 dynamic increase factor of strength at a strain rate.
    Mc2010DynamicIncreaseFactor {
        /// Strain rate (1/s).
        rate: f64,
        /// Tensile strength when true, compressive when false.
        tension: bool,
    },
    /// The ratio of the fib Model Code 2010 dynamic increase factors at `rate` and at
    /// `relative_to` (`concrete::mc2010_dif_ratio`).
    Mc2010DifRatio {
        /// Strain rate of the numerator (1/s).
        rate: f64,
        /// Strain rate of the denominator (1/s).
        relative_to: f64,
        /// Tensile strength when true, compressive when false.
        tension: bool,
    },
}

/// Quantities of the Hertz impact solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HertzQuantity {
    /// Largest approach of the centres `delta_max` (m).
    MaxApproach,
    /// Largest contact force `F_max` (N).
    MaxForce,
    /// Contact radius at the largest approach (m).
    ContactRadius,
    /// Duration of the contact (s).
    Duration,
}

/// The elastic constants named by a reference.
pub fn body_constants(
    scene: &Scene,
    of: &MaterialRef,
) -> Result<IsotropicElastic, ReferenceEvalError> {
    let body = match of {
        MaterialRef::Material(c) => return Ok(*c),
        MaterialRef::Body(b) => b,
    };
    scene
        .bodies
        .iter()
        .find(|b| &b.name == body)
        .ok_or_else(|| ReferenceEvalError::NoSceneBody { body: body.clone() })
        .and_then(|b| {
            let model = b.material.model(&b.name)?;
            Ok(model.constants())
        })
}

/// The constants of `of` when there may be no scene (cases that run none, such as a contact-problem
/// comparison): a reference naming a body then is an error saying so.
fn constants_of(
    scene: Option<&Scene>,
    of: &MaterialRef,
) -> Result<IsotropicElastic, ReferenceEvalError> {
    match (scene, of) {
        (_, MaterialRef::Material(c)) => Ok(*c),
        (Some(scene), of) => body_constants(scene, of),
        (None, MaterialRef::Body(b)) => {
            Err(ReferenceEvalError::BodyWithoutScene { body: b.clone() })
        }
    }
}

impl Reference {
    /// The value a measured `value` is judged against, given the reference's value `r`: the
    /// measured mode's own code when it is one a failure-mode reference accepts, else `r`.
    pub fn judged_value(&self, r: f64, value: f64) -> f64 {
        match self {
            Reference::FailureMode(modes) if modes.accepts(value) => value,
            _ => r,
        }
    }

    /// The reference value and a line saying where it comes from.
    pub fn evaluate(&self, scene: &Scene) -> Result<(f64, String), ReferenceEvalError> {
        self.evaluate_for(Some(scene))
    }

    /// As [`Reference::evaluate`], for a case that may have no scene.
    pub fn evaluate_for(&self, scene: Option<&Scene>) -> Result<(f64, String), ReferenceEvalError> {
        let needs = |reference| ReferenceEvalError::NeedsScene { reference };
        use analytic::*;
        Ok(match self {
            Reference::Value { value, source } => (*value, source.clone()),
            Reference::FailureMode(modes) => (
                modes.first_code(),
                format!(
                    "failure mode {} (thesis 10.3.2; code 0 none, 1 bending, 2 mixed, 3 shear, 4 bending_inclined)",
                    modes.name()
                ),
            ),
            Reference::Published { file, key } => {
                let p = published(file, key)?;
                (p.value, format!("{} ({file}: {key})", p.source))
            }
            Reference::ElasticRefinement(spec) => elastic_refinement::elastic_stiffness(
                scene.ok_or_else(|| needs("elastic refinement"))?,
                spec,
            )?,
            Reference::Hinge(spec) => hinge::hinge_reference(
                scene.ok_or_else(|| needs("hinge"))?,
                spec,
            )?,
            Reference::StaticPath(spec) => static_path::static_path_peak(
                scene.ok_or_else(|| needs("static path"))?,
                spec,
            )?,
            Reference::CurveSlope(spec) => curve_slope(spec)?,
            Reference::Analytic(a) => {
                match a {
                    Analytic::Zero => (0.0, "exact solution: zero".into()),
                    Analytic::DilatationalWaveSpeed { of } => (
                        dilatational_wave_speed(&constants_of(scene, of)?),
                        "c_d = sqrt((lambda + 2 mu)/rho)".into(),
                    ),
                    Analytic::RayleighWaveSpeed { of } => (
                        rayleigh_wave_speed(&constants_of(scene, of)?),
                        "root of Rayleigh's equation (Rayleigh 1885)".into(),
                    ),
                    Analytic::PlaneWaveStress { of, velocity } => (
                        plane_wave_stress(&constants_of(scene, of)?, *velocity),
                        "sigma = -rho c_d v0 (1-D wave theory)".into(),
                    ),
                    Analytic::SvkUniaxial {
                        of,
                        stretch,
                        quantity,
                    } => {
                        let s = svk_uniaxial(&constants_of(scene, of)?, *stretch);
                        let v = match quantity {
                            SvkQuantity::E11 => s.e11,
                            SvkQuantity::E22 => s.e22,
                            SvkQuantity::S11 => s.s11,
                            SvkQuantity::P11 => s.p11,
                            SvkQuantity::Sigma11 => s.sigma11,
                        };
                        (v, format!("Saint-Venant-Kirchhoff uniaxial stress at stretch {stretch} (2.123)"))
                    }
                    Analytic::SvkUniaxialStrainStress { of, stretch } => (
                        svk_uniaxial_strain_stress(&constants_of(scene, of)?, *stretch),
                        format!(
                            "Saint-Venant-Kirchhoff uniaxial strain at stretch {stretch} (2.123)"
                        ),
                    ),
                    Analytic::CantileverFirstFrequency { of, length, depth } => (
                        cantilever_first_frequency(&constants_of(scene, of)?, *length, *depth),
                        "Euler-Bernoulli cantilever, beta L = 1.8751".into(),
                    ),
                    Analytic::HertzImpact {
                        of,
                        radius,
                        relative_speed,
                        quantity,
                    } => {
                        let c = constants_of(scene, of)?;
                        let mass = c.density * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
                        let h = hertz_impact(&c, *radius, mass, *relative_speed);
                        let v = match quantity {
                            HertzQuantity::MaxApproach => h.max_approach,
                            HertzQuantity::MaxForce => h.max_force,
                            HertzQuantity::ContactRadius => h.contact_radius,
                            HertzQuantity::Duration => h.duration,
                        };
                        (
                            v,
                            "Hertz impact of identical spheres (Hertz 1882; Johnson 1985, 11.4)"
                                .into(),
                        )
                    }
                    Analytic::ModulusOfRuptureLoad {
                        f_r,
                        width,
                        depth,
                        span,
                    } => (
                        modulus_of_rupture_load(*f_r, *width, *depth, *span),
                        "P = 2 f_r b h^2 / (3 S) (beam theory)".into(),
                    ),
                    Analytic::Mc2010DynamicIncreaseFactor { rate, tension } => (
                        mc2010_dynamic_increase_factor(*rate, *tension),
                        "fib Model Code 2010, 5.1.11.1".into(),
                    ),
                    Analytic::Mc2010DifRatio {
                        rate,
                        relative_to,
                        tension,
                    } => (
                        concrete::mc2010_dif_ratio(*rate, *relative_to, *tension),
                        format!(
                            "fib Model Code 2010, 5.1.11.1: {} DIF at {rate:e} /s over that at \
                             {relative_to:e} /s",
                            if *tension { "tensile" } else { "compressive" }
                        ),
                    ),
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hinge::{HingeLaw, HingeQuantity};

    /// The measured initial CMOD stiffness of the Gregoire beams, recomputed from the committed
    /// mean curves: 73.0 N/um (D50 half-notched, 150-450 N) and 383.0 N/um (D50 unnotched,
    /// 1-3 kN), the values references/published/gregoire-2013.yaml records.
    #[test]
    fn the_measured_cmod_stiffness_of_the_gregoire_beams() {
        for (file, from, to, expected) in [
            ("gregoire-2013-d50-half-notched.csv", 150.0, 450.0, 73.0),
            ("gregoire-2013-d50-unnotched.csv", 1000.0, 3000.0, 383.0),
        ] {
            let yaml = format!(
                "curve_slope: {{ file: {file}, x: cmod, y: load_mean, x_scale: 1.0e3, from: {from}, to: {to} }}"
            );
            // As the catalogue reads a case: externally tagged enums as single-key maps.
            let reference: Reference = serde_norway::with::singleton_map_recursive::deserialize(
                serde_norway::Deserializer::from_str(&yaml),
            )
            .expect("parses");
            let (k, source) = reference.evaluate_for(None).expect("evaluates");
            assert!((k - expected).abs() < 0.05, "{file}: {k} N/um");
            assert!(source.contains(file), "{source}");
        }
    }

    /// The thesis beam (chapter 10): 600 x 300 mm, span 2.8 m; concrete f_t 2.7 MPa
    /// (cases/materials/thesis-concrete.yaml), as in the hinge's own tests.
    const H: f64 = 0.6;
    const B: f64 = 0.3;
    const L: f64 = 2.8;
    const FT: f64 = 2.7e6;

    /// The harness side of the hinge reference: a case's YAML parses into it and it evaluates on
    /// a scene (moved here from `references/hinge/tests.rs`, which cannot see the harness).
    #[test]
    fn hinge_reference_parses_and_evaluates_on_a_scene() {
        // As the catalogue reads a case: externally tagged enums as single-key maps.
        #[derive(Deserialize)]
        struct Metric {
            reference: Reference,
        }
        let parse = |text: &str| {
            serde_norway::with::singleton_map_recursive::deserialize::<Metric, _>(
                serde_norway::Deserializer::from_str(text),
            )
            .map(|m| m.reference)
        };
        let reference = parse(
            "reference: { hinge: { depth: 0.6, width: 0.3, span: 2.8, law: own, element_size: 0.05, \
             quantity: peak_bending_moment } }",
        )
        .expect("a hinge reference");
        let Reference::Hinge(spec) = &reference else {
            panic!("{reference:?}");
        };
        assert_eq!(spec.law, HingeLaw::Own);
        assert_eq!(spec.quantity, HingeQuantity::PeakBendingMoment);
        assert!(parse(
            "reference: { hinge: { depth: 0.6, width: 0.3, span: 2.8, law: linear, \
             element_size: 0.05, quantity: peak_load } }"
        )
        .is_err());
        let material = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases/materials/thesis-concrete.yaml");
        let scene = Scene::from_yaml(
            &format!(
                "name: hinge-test\n\
                 bodies:\n  - name: beam\n    \
                 mesh: {{ box: {{ origin: [0, 0, 0], size: [3.0, 0.6, 0.3], divisions: [2, 1, 1] }} }}\n    \
                 material: {{ microplane: {{ file: {} }} }}\n\
                 analysis:\n  explicit: {{ end_time: 1.0e-3 }}\n",
                material.display()
            ),
            "test",
        )
        .expect("scene");
        let (moment, source) = reference.evaluate(&scene).expect("evaluates");
        println!("{moment} N m: {source}");
        // Between the elastic cracking moment and the rigid-plastic one at f_t = 2.7 MPa.
        let (elastic, plastic) = (FT * B * H * H / 6.0, FT * B * H * H / 2.0);
        assert!(moment > elastic && moment < plastic, "{moment}");
        let mut load = spec.clone();
        load.quantity = HingeQuantity::PeakLoad;
        load.law = HingeLaw::Hordijk;
        let (p, _) = Reference::Hinge(load).evaluate(&scene).expect("evaluates");
        println!("Hordijk at the material's f_t and G_F: {p} N");
        assert!(p > 4.0 * elastic / L && p < 4.0 * plastic / L, "{p}");
    }
}
