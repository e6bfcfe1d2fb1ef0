//! Constitutive models behind one trait.
//!
//! A model maps the deformation gradient of an element (and its own history, when it has one)
//! to the first Piola-Kirchhoff stress `P`, from which the element forces follow as
//! `f_a = V P grad_X N_a`. Elastic models have no state and need no per-step storage; the
//! microplane concrete model keeps a history per element, which the analysis owns
//! (`model::MaterialHistory`) and advances once per step.

mod linear_elastic;
pub mod microplane;
mod parameter_file;
mod saint_venant_kirchhoff;

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

pub use linear_elastic::LinearElastic;
pub use parameter_file::{read_microplane_file, MicroplaneFile};
pub use saint_venant_kirchhoff::SaintVenantKirchhoff;

/// Isotropic elastic constants, with the Lamé parameters of (2.121).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IsotropicElastic {
    /// Mass density `rho` (kg/m^3).
    pub density: f64,
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio `nu`.
    pub poisson_ratio: f64,
}

impl IsotropicElastic {
    /// `lambda = E nu / ((1 + nu)(1 - 2 nu))` (2.121).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// `mu = E / (2 (1 + nu))` (2.121).
    pub fn mu(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Dilatational (P-wave) speed `c_d = sqrt((lambda + 2 mu) / rho)`.
    pub fn dilatational_wave_speed(&self) -> f64 {
        ((self.lambda() + 2.0 * self.mu()) / self.density).sqrt()
    }

    /// Checks the constants, naming the offending one and its admissible range.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.density > 0.0 && self.density.is_finite()) {
            return Err(format!("density must be positive, got {}", self.density));
        }
        if !(self.youngs_modulus > 0.0 && self.youngs_modulus.is_finite()) {
            return Err(format!(
                "youngs_modulus must be positive, got {}",
                self.youngs_modulus
            ));
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(format!(
                "poisson_ratio must lie in (-1, 0.5), got {}",
                self.poisson_ratio
            ));
        }
        Ok(())
    }

    /// Stored energy of Saint-Venant-Kirchhoff form `W = lambda/2 (tr E)^2 + mu tr(E^2)` (2.120).
    pub fn strain_energy_density(&self, e: &Matrix3<f64>) -> f64 {
        let tr = e.trace();
        0.5 * self.lambda() * tr * tr + self.mu() * e.component_mul(e).sum()
    }
}

/// A constitutive model. Implementations are small `Copy` structs; the element loop is
/// monomorphised per model so the stress update inlines into it.
pub trait Material: Sync + Send {
    /// First Piola-Kirchhoff stress `P` for the deformation gradient `F` (with `H = F - I`,
    /// passed too so that small strains keep their digits).
    fn first_piola(&self, f: &Matrix3<f64>, h: &Matrix3<f64>) -> Matrix3<f64>;

    /// Directional derivative `dP = (dP/dF) : dF`, the consistent tangent for Newton's method.
    fn first_piola_derivative(&self, f: &Matrix3<f64>, df: &Matrix3<f64>) -> Matrix3<f64>;

    /// Cauchy stress `sigma = P F^T / det F`.
    fn cauchy(&self, f: &Matrix3<f64>, h: &Matrix3<f64>) -> Matrix3<f64> {
        let p = self.first_piola(f, h);
        let s = p * f.transpose() / f.determinant();
        0.5 * (s + s.transpose())
    }

    /// Elastic energy stored per unit reference volume, where the model defines one.
    fn strain_energy_density(&self, h: &Matrix3<f64>) -> f64;

    /// Mass density in the reference configuration (kg/m^3).
    fn density(&self) -> f64;

    /// Dilatational wave speed at the initial stiffness, for the stable time step (FORMULATION 2).
    fn dilatational_wave_speed(&self) -> f64;
}

/// The material of a body in the model. (A scene names it through `scene::MaterialSpec`, which
/// may point to a parameter file instead.)
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialModel {
    LinearElastic(IsotropicElastic),
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

    pub fn name(&self) -> &'static str {
        match self {
            MaterialModel::LinearElastic(_) => "linear_elastic",
            MaterialModel::SaintVenantKirchhoff(_) => "saint_venant_kirchhoff",
            MaterialModel::Microplane(_) => "microplane",
        }
    }

    /// Whether the model keeps a history per element (its forces then advance that history, so
    /// they are computed once per step by the analysis that owns it).
    pub fn has_history(&self) -> bool {
        matches!(self, MaterialModel::Microplane(_))
    }

    pub fn density(&self) -> f64 {
        self.constants().density
    }

    pub fn dilatational_wave_speed(&self) -> f64 {
        self.constants().dilatational_wave_speed()
    }
}

/// Calls `$body` with `$m` bound to the stateless (elastic) model behind a [`MaterialModel`], so
/// generic element loops are instantiated once per model (static dispatch in the hot path).
/// Models with a history are no [`Material`]: every caller says what it does for them, with `$p`
/// bound to their parameters.
#[macro_export]
macro_rules! with_material {
    ($model:expr, |$m:ident| $body:expr, microplane($p:pat) => $stateful:expr) => {
        match $model {
            $crate::material::MaterialModel::LinearElastic(c) => {
                let $m = $crate::material::LinearElastic::new(*c);
                $body
            }
            $crate::material::MaterialModel::SaintVenantKirchhoff(c) => {
                let $m = $crate::material::SaintVenantKirchhoff::new(*c);
                $body
            }
            $crate::material::MaterialModel::Microplane($p) => $stateful,
        }
    };
}
