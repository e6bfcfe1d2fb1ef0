//! Constitutive models behind one trait, [`Material`].
//!
//! A model maps the deformation gradient of an element (and its own history, when it has one)
//! to the first Piola-Kirchhoff stress `P`, from which the element forces follow as
//! `f_a = V P grad_X N_a`. Elastic models have no state; the microplane concrete model keeps a
//! history per element, which the analysis owns (`model::MaterialHistory`) and advances once per
//! step. A scene names a model with [`MaterialModel`], which the model turns into the `Material`
//! of a body (`model::MaterialSource`); any other `Material` (a model under test, say) can be given to
//! `model::Model::new` directly, and the element loops, the static tangent and the output treat
//! it as they treat the built-in ones (`solver/tests/custom_material.rs` adds a Neo-Hookean body
//! in one file).

mod isotropic;
mod linear_elastic;
pub mod microplane;
mod parameter_file;
mod saint_venant_kirchhoff;
pub mod strength_field;

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

pub use isotropic::{ConstantsError, Elastic, Hooke, IsotropicElastic};
pub use linear_elastic::LinearElastic;
pub use microplane::MicroplaneMaterial;
pub use parameter_file::{read_microplane_file, without_byte_order_mark, MicroplaneFile};
pub use saint_venant_kirchhoff::SaintVenantKirchhoff;
pub use strength_field::{StrengthField, StrengthFieldSpec};

/// The kinematics of one element at one update, as every model receives them (FORMULATION 1).
#[derive(Debug, Clone, Copy)]
pub struct Deformation {
    /// Deformation gradient `F = I + H`.
    pub f: Matrix3<f64>,
    /// Displacement gradient `H = F - I`, passed too so that small strains keep their digits.
    pub h: Matrix3<f64>,
    /// `det F`, the triple product of the columns of `F`.
    pub det: f64,
    /// Rate of the deformation gradient `Fdot = sum_a v_a (x) grad_X N_a` from the nodal
    /// velocities of the half step before (`v_{n-1/2}`), for models that read the strain rate
    /// ([`Material::reads_rate`]); zero otherwise and in statics.
    pub f_dot: Matrix3<f64>,
    /// The time step (0 in statics).
    pub dt: f64,
}

impl Deformation {
    /// The deformation `F = I + H` at zero strain rate (as in statics).
    pub fn at_rest(h: Matrix3<f64>) -> Self {
        let f = Matrix3::identity() + h;
        Self {
            f,
            h,
            det: crate::kinematics::triple_product_determinant(&f),
            f_dot: Matrix3::zeros(),
            dt: 0.0,
        }
    }
}

/// What an update may change of its element besides the stress it returns: the history, and the
/// Cauchy stress the analysis keeps for the output of models with a history.
#[derive(Debug)]
pub struct ElementState<'a> {
    /// The element's history, `history_len` values (empty for a model without one).
    pub history: &'a mut [f32],
    /// Where a model with a history writes the Cauchy stress `[xx, yy, zz, xy, yz, xz]` (Pa) of
    /// the update, when the analysis keeps it.
    pub cauchy: Option<&'a mut [f64; 6]>,
}

impl ElementState<'_> {
    /// The state of an element of a model without history.
    pub fn stateless() -> ElementState<'static> {
        ElementState {
            history: &mut [],
            cauchy: None,
        }
    }
}

/// A constitutive model: the one trait a new model implements, whether it keeps a history or not.
///
/// An update maps an element's [`Deformation`] (and the element's history, when the model keeps
/// one) to the first Piola-Kirchhoff stress `P`. The history is `history_len` `f32` values per
/// element, owned by the analysis (`model::MaterialHistory`): the explicit stepper advances it
/// once per step, the static path updates copies of the committed one, and the remeshing transfer
/// and a distributed partition move it as plain values. A model prepared for a body may keep
/// per-element data of its own (microplane concrete keeps each element's crack band), indexed by
/// the element's id in its body.
///
/// The element loops are generic over the model (`model::BodyMaterial`), so an implementation's
/// methods inline into them: keep them `#[inline]` where they are small.
pub trait Material: std::fmt::Debug + Send + Sync + std::any::Any {
    /// Name in reports and messages (`linear_elastic`, `microplane`, ...).
    fn name(&self) -> &'static str;

    /// The elastic constants at the initial stiffness: the density gives the lumped masses, the
    /// dilatational wave speed the stable time step (FORMULATION 2).
    fn constants(&self) -> IsotropicElastic;

    /// The model as a scene names it, for models built from a [`MaterialModel`].
    fn model(&self) -> Option<MaterialModel> {
        None
    }

    /// `f32` values of history per element; 0 (the default) for a model without history.
    fn history_len(&self) -> usize {
        0
    }

    /// The cost of one element update relative to a linear elastic element's (1, the default),
    /// by which a distributed run divides the elements among its ranks
    /// (`distributed::element_ranges`). An estimate: it moves work, never results.
    fn relative_cost(&self) -> f64 {
        1.0
    }

    /// Writes the history of a virgin element.
    fn initial_history(&self, _history: &mut [f32]) {}

    /// Whether the update reads the strain rate ([`Deformation::f_dot`]); the element loop computes
    /// it only then.
    fn reads_rate(&self) -> bool {
        false
    }

    /// The first Piola-Kirchhoff stress `P` of element `element` (its id in the body) at
    /// `deformation`, advancing its history in `state` (`history_len` values) and writing the
    /// Cauchy stress there where asked. `None` when the model cannot update the element (an
    /// inverted one): its state is then left as it was, its forces are zero and the run stops.
    /// The element forces are `V P grad_X N_a`.
    fn update(
        &self,
        element: usize,
        deformation: &Deformation,
        state: ElementState<'_>,
    ) -> Option<Matrix3<f64>>;

    /// The consistent tangent `dP = (dP/dF) : dF` for Newton's method (3.68a), where the model has
    /// one in closed form. `None` (the default) makes the static solver take forward differences
    /// of the element forces instead (`statics::path`).
    fn first_piola_derivative(
        &self,
        _f: &Matrix3<f64>,
        _df: &Matrix3<f64>,
    ) -> Option<Matrix3<f64>> {
        None
    }

    /// Elastic energy stored per unit reference volume at `H`, where the model defines a
    /// potential; `None` (the default) at every strain where it does not (its internal work, from
    /// the forces, is then what it stored and dissipated, and the energy ledger uses that).
    fn strain_energy_density(&self, _h: &Matrix3<f64>) -> Option<f64> {
        None
    }

    /// The rate factor of the last update read from an element's history, for the output (0, the
    /// default, for rate-independent models).
    fn rate_factor(&self, _history: &[f32]) -> f64 {
        0.0
    }

    /// How many updates of an element took a fast path that skips the model's full update
    /// (the microplane model's elastic path), read from its history; `None` (the default) for
    /// models without one.
    fn fast_updates(&self, _history: &[f32]) -> Option<f64> {
        None
    }

    /// What the run's plan says of the model beyond its name (the microplanes and element sizes).
    fn summary(&self) -> Option<String> {
        None
    }

    /// The material for the body's new mesh after a remeshing (`elements`: for each new element
    /// the old one it continues, or its size and centroid where the mesher made it). The
    /// remeshing carries every element's history itself (`remesh`, T1/T2); a model that also
    /// keeps data per element (microplane concrete: each element's crack band) rebuilds that
    /// data here. `Ok(None)`, the default, keeps the material as it is; an error names the new
    /// element (its index in `elements`) and why its data cannot be made.
    fn remeshed(&self, _elements: &RemeshedElements<'_>) -> Result<Option<Self>, (usize, String)>
    where
        Self: Sized,
    {
        Ok(None)
    }

    /// What the model keeps per element besides the histories, as numbers, so that a
    /// checkpoint of a remeshed run can store it and [`Self::with_element_data`] rebuild the
    /// material from it (a remeshed element's data depends on every remeshing before, so it
    /// cannot be made again from the scene). `None`, the default, for a model without data per
    /// element; a model that overrides [`Self::remeshed`] overrides this pair too.
    fn element_data(&self) -> Option<Vec<f64>> {
        None
    }

    /// The material with the data per element that [`Self::element_data`] gave (of a body
    /// with the same elements), or why the numbers do not fit. `Ok(None)`, the default, keeps
    /// the material as it is.
    fn with_element_data(&self, _data: &[f64]) -> Result<Option<Self>, ElementDataError>
    where
        Self: Sized,
    {
        Ok(None)
    }

    /// The tensile strength of an element over the material's where the body has a random
    /// strength field (`strength_field.rs`), for the output; `None` (the default) without one.
    fn strength_factor(&self, _element: usize) -> Option<f64> {
        None
    }
}

/// Data per element that does not fit the material ([`Material::with_element_data`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{numbers} numbers of data per element are not {per_element} per element ({what})")]
pub struct ElementDataError {
    /// How many numbers were given.
    pub numbers: usize,
    /// How many the material keeps per element.
    pub per_element: usize,
    /// What they are.
    pub what: &'static str,
}

/// The elements of a body after a remeshing, as [`Material::remeshed`] sees them.
#[derive(Debug, Clone, Copy)]
pub struct RemeshedElements<'a> {
    /// For each new element, the old element it continues unchanged, or `None` for an element
    /// the mesher made.
    pub origin: &'a [Option<u32>],
    /// Volume of each new element on its new reference (the configuration it is made in).
    pub volumes: &'a [f64],
    /// Centroid of each new element on that reference.
    pub centroids: &'a [nalgebra::Vector3<f64>],
}

/// The material of a body in the model. (A scene names it through `scene::MaterialSpec`, which
/// may point to a parameter file instead.)
// One per body and built once: being `Copy` matters more than the 200 bytes the microplane
// parameters take over the elastic constants.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialModel {
    /// Hooke's law between the back-rotated Cauchy stress and the Green-Lagrange strain
    /// (FORMULATION 1): the elastic limit of the microplane model.
    LinearElastic(IsotropicElastic),
    /// Saint Venant-Kirchhoff: Hooke's law between the second Piola-Kirchhoff stress and the
    /// Green-Lagrange strain (2.123).
    SaintVenantKirchhoff(IsotropicElastic),
    /// The microplane concrete model (thesis chapter 5): it carries a history per element.
    Microplane(microplane::MicroplaneParameters),
}

impl MaterialModel {
    /// The elastic constants: those of the model, or the initial (undamaged) ones of microplane
    /// concrete, which set its wave speed and so the stable time step.
    pub fn constants(&self) -> IsotropicElastic {
        match self {
            MaterialModel::LinearElastic(c) | MaterialModel::SaintVenantKirchhoff(c) => *c,
            MaterialModel::Microplane(p) => p.elastic(),
        }
    }

    /// The model's name as a scene writes it (`linear_elastic`, `saint_venant_kirchhoff`,
    /// `microplane`).
    pub fn name(&self) -> &'static str {
        match self {
            MaterialModel::LinearElastic(_) => "linear_elastic",
            MaterialModel::SaintVenantKirchhoff(_) => "saint_venant_kirchhoff",
            MaterialModel::Microplane(_) => "microplane",
        }
    }
}
