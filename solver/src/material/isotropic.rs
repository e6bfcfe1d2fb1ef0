//! Isotropic elastic constants and Hooke's law, written once for every model that uses them, and
//! [`Elastic`]: what the elastic models have to say beyond that, from which their [`Material`]
//! implementation follows.

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use super::{Deformation, ElementState, Material, MaterialModel};
use crate::kinematics::green_lagrange_from_h;

/// What is wrong with a set of elastic constants, and the admissible range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConstantsError {
    /// The density (kg/m^3) given, which is not positive, not finite or above
    /// `MAX_DENSITY`.
    #[error("density must be positive and at most {MAX_DENSITY:e} kg/m^3, got {0}")]
    Density(f64),
    /// Young's modulus (Pa) given, which is not positive, not finite or above
    /// `MAX_YOUNGS_MODULUS`.
    #[error("youngs_modulus must be positive and at most {MAX_YOUNGS_MODULUS:e} Pa, got {0}")]
    YoungsModulus(f64),
    /// Poisson's ratio given, outside `(-1, 0.5)` where the elastic energy is positive definite.
    #[error("poisson_ratio must lie in (-1, 0.5), got {0}")]
    PoissonRatio(f64),
}

/// The largest density accepted (kg/m^3): forty times osmium's 22 600. A larger one is a typo
/// or a unit slip (g/m^3), and at `1e300` the wave speed underflows and the stable step
/// overflows.
pub const MAX_DENSITY: f64 = 1.0e6;

/// The largest Young's modulus accepted (Pa): a hundred times diamond's 1.2e12.
pub const MAX_YOUNGS_MODULUS: f64 = 1.0e14;

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
    pub fn validate(&self) -> Result<(), ConstantsError> {
        if !(self.density > 0.0 && self.density <= MAX_DENSITY) {
            return Err(ConstantsError::Density(self.density));
        }
        if !(self.youngs_modulus > 0.0 && self.youngs_modulus <= MAX_YOUNGS_MODULUS) {
            return Err(ConstantsError::YoungsModulus(self.youngs_modulus));
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(ConstantsError::PoissonRatio(self.poisson_ratio));
        }
        Ok(())
    }

    /// Stored energy of Saint-Venant-Kirchhoff form `W = lambda/2 (tr E)^2 + mu tr(E^2)` (2.120).
    #[inline]
    pub fn strain_energy_density(&self, e: &Matrix3<f64>) -> f64 {
        let tr = e.trace();
        0.5 * self.lambda() * tr * tr + self.mu() * e.component_mul(e).sum()
    }

    /// Hooke's law with these constants.
    pub fn hooke(&self) -> Hooke {
        Hooke {
            lambda: self.lambda(),
            two_mu: 2.0 * self.mu(),
        }
    }
}

/// Isotropic Hooke's law `S = lambda tr(E) I + 2 mu E` (2.123), with the Lamé parameters kept so
/// that the hot path does not recompute them. The linear elastic model applies it to the
/// back-rotated strain, Saint-Venant-Kirchhoff to the Green-Lagrange strain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hooke {
    /// Lamé's first parameter `lambda = E nu / ((1 + nu)(1 - 2 nu))` (Pa).
    pub lambda: f64,
    /// Twice the shear modulus, `2 mu = E / (1 + nu)` (Pa).
    pub two_mu: f64,
}

impl Hooke {
    /// `lambda tr(e) I + 2 mu e`.
    #[inline(always)]
    pub fn stress(&self, e: &Matrix3<f64>) -> Matrix3<f64> {
        let mut s = e * self.two_mu;
        let p = self.lambda * e.trace();
        s[(0, 0)] += p;
        s[(1, 1)] += p;
        s[(2, 2)] += p;
        s
    }
}

/// An isotropic elastic model: no history, a stress that depends on `F` alone with a closed-form
/// tangent, and the energy `lambda/2 (tr E)^2 + mu tr E^2` of its constants (exact for
/// Saint-Venant-Kirchhoff (2.120), to second order in the strain for the co-rotated linear
/// model). Every such model is a [`Material`].
pub trait Elastic: std::fmt::Debug + Send + Sync + 'static {
    /// Name in reports and messages.
    const NAME: &'static str;

    /// The elastic constants.
    fn constants(&self) -> IsotropicElastic;

    /// The model as a scene names it.
    fn model(&self) -> MaterialModel;

    /// First Piola-Kirchhoff stress `P` at `F = I + H`.
    fn first_piola(&self, f: &Matrix3<f64>, h: &Matrix3<f64>) -> Matrix3<f64>;

    /// The consistent tangent `dP = (dP/dF) : dF` (3.68a).
    fn first_piola_derivative(&self, f: &Matrix3<f64>, df: &Matrix3<f64>) -> Matrix3<f64>;
}

impl<T: Elastic> Material for T {
    fn name(&self) -> &'static str {
        T::NAME
    }

    fn constants(&self) -> IsotropicElastic {
        Elastic::constants(self)
    }

    fn model(&self) -> Option<MaterialModel> {
        Some(Elastic::model(self))
    }

    #[inline(always)]
    fn update(
        &self,
        _element: usize,
        d: &Deformation,
        _state: ElementState<'_>,
    ) -> Option<Matrix3<f64>> {
        Some(self.first_piola(&d.f, &d.h))
    }

    fn first_piola_derivative(&self, f: &Matrix3<f64>, df: &Matrix3<f64>) -> Option<Matrix3<f64>> {
        Some(Elastic::first_piola_derivative(self, f, df))
    }

    fn strain_energy_density(&self, h: &Matrix3<f64>) -> Option<f64> {
        Some(Elastic::constants(self).strain_energy_density(&green_lagrange_from_h(h)))
    }
}
