//! Parameters of the microplane concrete model (MICROPLANE.md "Parameters and calibration").

use serde::{Deserialize, Serialize};

use super::tension_boundary::{TensionBoundary, TensionBoundaryError};
use super::volumetric::VolumetricStrain;

use super::directions::SphereRule;
use crate::material::strength_field::{StrengthFieldError, StrengthFieldSpec};
use crate::material::{ConstantsError, IsotropicElastic};

/// Everything that defines the model. Strains are dimensionless, stresses in Pa, lengths in m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MicroplaneParameters {
    /// Mass density `rho` (kg/m^3).
    pub density: f64,
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio `nu`.
    pub poisson_ratio: f64,
    /// Strain scale of volumetric and deviatoric tension, and of the discontinuity functions
    /// (5.19, 5.91).
    pub e1: f64,
    /// Strain scale of deviatoric compression (5.19).
    pub e2: f64,
    /// Strain scale of shear without volumetric compression (5.20).
    pub e3: f64,
    /// Growth of the shear strain scale with volumetric compression, `e5 = e3 - e4 e_V` (5.20).
    pub e4: f64,
    /// Exponent of volumetric and deviatoric tension (5.19).
    pub m: f64,
    /// Exponent of deviatoric compression (5.19).
    pub n: f64,
    /// Exponent of shear (5.20).
    pub k: f64,
    /// Volumetric compression (5.21): compaction scale `a`, stiffening scale `b`, exponents
    /// `p`, `q`.
    pub a: f64,
    /// Stiffening strain scale `b` of (5.21): the term `|e_V / b|^q` grows with compaction
    /// (dimensionless strain).
    pub b: f64,
    /// Compaction exponent `p` of (5.21): `(1 + |e_V / a|)^-p` softens the volumetric modulus.
    pub p: f64,
    /// Stiffening exponent `q` of (5.21).
    pub q: f64,
    /// Small negative limit of the largest principal stress below which cracks count as closed
    /// (5.96, 5.97), in Pa.
    pub s_i_min: f64,
    /// Unloading modulus weight (5.102): 1 unloads with the initial modulus, 0 with the secant.
    pub alpha: f64,
    /// Growth of the residual strain with post-peak strain (5.103).
    pub beta: f64,
    /// Element size the softening laws were calibrated at (m), for the crack band.
    pub h_ref: f64,
    /// Post-peak shape of the tension law (volumetric and deviatoric, exponent `m`): 0 keeps
    /// `x exp(-x^m)`; a positive value replaces the branch after its peak by Hordijk's (1991)
    /// curve falling to zero over `hordijk_tail` strain scales `e1` at the size `h_ref`. The crack
    /// band shortens it in larger elements, so with `w = h x` inelastic strain the law is a
    /// stress-opening curve of Hordijk's shape whatever the element size (MICROPLANE "Crack band").
    #[serde(default)]
    pub hordijk_tail: f64,
    /// Rate effect (5.110, MICROPLANE "Rate effect"); `~` (null) switches it off.
    #[serde(default = "default_rate_effect")]
    pub rate_effect: Option<RateEffect>,
    /// Quadrature on the sphere.
    #[serde(default)]
    pub rule: SphereRule,
    /// Homogenise the deviatoric stress with `n n - delta/3` (Carol & Bažant 1997) instead of the
    /// thesis' `n n` (5.36). On by default (MICROPLANE.md "Homogenisation"): without it the
    /// deviatoric stresses feed the mean stress and a closed shear-normal strain cycle gives
    /// energy back.
    #[serde(default = "yes")]
    pub deviatoric_trace_term: bool,
    /// The cyclic shear damage of Eligehausen, Popov & Bertero (5.104).
    #[serde(default = "yes")]
    pub shear_cyclic_damage: bool,
    /// Dilatant volumetric strain per unit of inelastic deviatoric compressive strain (MICROPLANE
    /// "Dilatancy"); 0 (the thesis) for none.
    #[serde(default)]
    pub dilatancy: f64,
    /// What drives the softening of volumetric tension (MICROPLANE.md "Tension driver").
    #[serde(default)]
    pub tension_driver: TensionDriver,
    /// What drives the relaxation `psi` of the deviatoric and shear planes (docs/MICROPLANE.md
    /// "Tension under lateral compression").
    #[serde(default, skip_serializing_if = "is_volumetric_relaxation")]
    pub relaxation_driver: RelaxationDriver,
    /// How the volumetric strain is measured at finite strain (`volumetric.rs`): the trace of
    /// the Green-Lagrange strain (MICROPLANE.md, the default) or the volume ratio `J`.
    #[serde(default, skip_serializing_if = "is_trace")]
    pub volumetric_strain: VolumetricStrain,
    /// Coulomb friction on the microplanes once their shear laws have softened (MICROPLANE
    /// "Crack friction", `docs/MICROPLANE.md`): each shear component keeps at least the stress
    /// of a friction slider of stiffness `E_T0` bounded by this coefficient times the plane's
    /// compressive normal stress (the frictional shear boundary of M4, Bažant et al. 2000,
    /// `c10 = 0.73`). `~` (the default, the thesis): none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack_friction: Option<f64>,
    /// A seeded random field of tensile strength over the body (`strength_field.rs`): each
    /// element's tension law is scaled by the field's factor at its centroid, with its crack
    /// band refitted so that the element still dissipates the calibrated fracture energy.
    /// `~` (the default): every element has the material's strength. A scene sets it per body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strength_field: Option<StrengthFieldSpec>,
    /// A tensile boundary on every plane's total normal stress, in M7's form
    /// (`tension_boundary.rs`, docs/MICROPLANE.md "Tensile boundary"): it replaces the tension
    /// laws, the volumetric tension's damage and the relaxation `psi`. `~` (the default, the
    /// thesis): none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tension_boundary: Option<TensionBoundary>,
    /// Which length of an element is its crack band (`crack_band.rs`, MICROPLANE "Crack
    /// band"): `volume` (the default), `h = (6 V)^(1/3)`; `across_crack`, the element's length
    /// across its crack, fixed where its first tension law passes its peak (`crack_width.rs`).
    #[serde(default, skip_serializing_if = "is_volume_band")]
    pub crack_band: CrackBandWidth,
}

fn is_volume_band(v: &CrackBandWidth) -> bool {
    *v == CrackBandWidth::Volume
}

/// The length an element's crack band takes (Bažant & Oh 1983: the width of the band of
/// material a crack through the element softens).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrackBandWidth {
    /// `h = (6 V)^(1/3)`, the edge of a cube cut into six tetrahedra of the element's volume,
    /// the same for every crack direction.
    #[default]
    Volume,
    /// The element's length across its crack, Oliver's (1989) `h(n) = 2 / sum_a |grad N_a . n|`,
    /// with `n` the direction of the largest principal stress where the element's first tension
    /// law passes its peak (`crack_width.rs`).
    AcrossCrack,
}

fn is_trace(v: &VolumetricStrain) -> bool {
    *v == VolumetricStrain::GreenLagrangeTrace
}

fn is_volumetric_relaxation(v: &RelaxationDriver) -> bool {
    *v == RelaxationDriver::Volumetric
}

/// The strain whose tension law secant is the relaxation `psi` of the deviatoric and shear
/// planes (5.91, 5.96, 5.99), before the crack closure `f(s_I)` (5.97).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RelaxationDriver {
    /// The thesis: the positive part of `e_V = tr(E) / 3`. Under a lateral compression `e_V`
    /// stays small while the tensile strain grows, nothing relaxes, and the shear planes carry
    /// the tension to their own, far later peak: 1.45 `f_t` beside `sigma_2 = -f_t`, where
    /// concrete gives about 0.95 (Kupfer & Gerstle 1973).
    #[default]
    Volumetric,
    /// The larger of `e_V` and `(1 - 2 nu) / 3 <sigma~_I> / E`, with `sigma~_I` the largest
    /// principal value of the elastic (effective) stress `C : E` (Rankine's equivalent strain,
    /// e.g. Jirásek 2004): in uniaxial stress both equal `e_V`, under a lateral compression the
    /// planes relax as the tensile stress, not the volume, grows, and under compression alone
    /// (`sigma~_I <= 0`) it is the thesis' driver.
    TensileStress,
}

/// The strain that drives volumetric tensile softening (the relaxation `psi` follows `e_V` with
/// either).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TensionDriver {
    /// The thesis: `e_V = tr(E) / 3` (5.19). A crack between elastic neighbours opens with
    /// its lateral strains held, `e_V = e_x / 3`, where the uniaxial test that calibrates the law
    /// has `e_V ~ 0.2 e_x`: the crack then dissipates about a third of GF.
    #[default]
    Volumetric,
    /// `(1 - 2 nu) / 3 * sqrt(sum <e_i>^2)` over the principal strains (Mazars 1986): the
    /// volumetric strain of uniaxial stress with the same tensile strain, whatever the lateral
    /// constraint. The volumetric stress is `E_V0 e_V` times the secant factor of the tension law
    /// at the largest value reached (a scalar damage, no residual strain).
    Equivalent,
}

fn yes() -> bool {
    true
}

fn default_rate_effect() -> Option<RateEffect> {
    Some(RateEffect::default())
}

/// `F = 1 + c2 asinh(gamma_dot / c1)` (Bažant et al. 2000; the thesis' `1 + c2 ln(2 gamma_dot/c1)`
/// (5.110) for large rates, but 1 at rest instead of minus infinity).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateEffect {
    /// Reference rate (1/s).
    pub c1: f64,
    /// Strength gain per unit of `asinh`.
    pub c2: f64,
}

impl Default for RateEffect {
    /// The public M7 code's constants (research notes section 2), within about 1 % of the fib
    /// MC2010 tensile dynamic increase factor from 1e-5 to 10 /s.
    fn default() -> Self {
        Self {
            c1: 4e-6,
            c2: 0.022,
        }
    }
}

impl RateEffect {
    /// The factor on the strain scales for the equivalent rate `gamma_dot` (5.111).
    ///
    /// `asinh x = ln(x + sqrt(x^2 + 1))` for `x >= 0`: one logarithm and one root, where the
    /// library's `asinh` adds `hypot` and `log1p` for relative accuracy near 0 that the factor
    /// does not need (its error is `c2` times the absolute error of `asinh`, below 1e-17).
    #[inline(always)]
    pub fn factor(&self, gamma_dot: f64) -> f64 {
        let x = (gamma_dot / self.c1).abs();
        1.0 + self.c2 * (x + (x * x + 1.0).sqrt()).ln().copysign(gamma_dot)
    }
}

impl MicroplaneParameters {
    /// The initial (undamaged) elastic constants: density, Young's modulus, Poisson's ratio.
    pub fn elastic(&self) -> IsotropicElastic {
        IsotropicElastic {
            density: self.density,
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
        }
    }

    /// Checks every parameter, naming the offending one and its admissible range.
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.elastic().validate()?;
        let positive = [
            ("e1", self.e1),
            ("e2", self.e2),
            ("e3", self.e3),
            ("m", self.m),
            ("n", self.n),
            ("k", self.k),
            ("a", self.a),
            ("b", self.b),
            ("q", self.q),
            ("h_ref", self.h_ref),
        ];
        for (name, value) in positive {
            if !(value > 0.0 && value.is_finite()) {
                return Err(ParameterError::NotPositive { name, value });
            }
        }
        if !(self.hordijk_tail >= 0.0 && self.hordijk_tail.is_finite()) {
            return Err(ParameterError::HordijkTail(self.hordijk_tail));
        }
        if !(self.dilatancy >= 0.0 && self.dilatancy.is_finite()) {
            return Err(ParameterError::Dilatancy(self.dilatancy));
        }
        for (name, value) in [("e4", self.e4), ("p", self.p)] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(ParameterError::Negative { name, value });
            }
        }
        if !(self.s_i_min < 0.0 && self.s_i_min.is_finite()) {
            return Err(ParameterError::PrincipalStressFloor(self.s_i_min));
        }
        for (name, value) in [("alpha", self.alpha), ("beta", self.beta)] {
            if !(value > 0.0 && value <= 1.0) {
                return Err(ParameterError::UnloadingFraction { name, value });
            }
        }
        if let Some(mu) = self.crack_friction {
            if !(mu > 0.0 && mu.is_finite()) {
                return Err(ParameterError::CrackFriction(mu));
            }
        }
        if let Some(field) = &self.strength_field {
            field.validate()?;
        }
        if let Some(boundary) = &self.tension_boundary {
            boundary.validate()?;
            if self.crack_band == CrackBandWidth::AcrossCrack {
                return Err(ParameterError::AcrossCrackWithBoundary);
            }
        }
        if let Some(rate) = self.rate_effect {
            if !(rate.c1 > 0.0 && rate.c1.is_finite() && rate.c2 >= 0.0 && rate.c2.is_finite()) {
                return Err(ParameterError::RateEffect {
                    c1: rate.c1,
                    c2: rate.c2,
                });
            }
        }
        Ok(())
    }
}

/// A microplane parameter outside its admissible range: which, its value and the range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParameterError {
    /// The elastic constants (density, E, nu).
    #[error(transparent)]
    Elastic(#[from] ConstantsError),
    /// A parameter that must be positive and finite (`e1`-`e3`, `m`, `n`, `k`, `a`, `b`, `q`,
    /// `h_ref`).
    #[error("{name} must be positive and finite, got {value}")]
    NotPositive {
        /// The parameter's name as the parameter file writes it.
        name: &'static str,
        /// The value given, in the parameter's unit.
        value: f64,
    },
    /// A negative `hordijk_tail` (the tail length in units of the strain scale); holds it.
    #[error("hordijk_tail must be >= 0 (0: exponential softening), got {0}")]
    HordijkTail(f64),
    /// A negative `dilatancy` (dilatant volumetric per inelastic deviatoric strain); holds it.
    #[error("dilatancy must be >= 0 (0: none), got {0}")]
    Dilatancy(f64),
    /// A `crack_friction` coefficient that is not positive and finite; holds it.
    #[error("crack_friction must be positive and finite (leave it out for none), got {0}")]
    CrackFriction(f64),
    /// `e4` or `p`, which must not be negative.
    #[error("{name} must be >= 0, got {value}")]
    Negative {
        /// The parameter's name as the parameter file writes it.
        name: &'static str,
        /// The value given, in the parameter's unit.
        value: f64,
    },
    /// `s_i_min` (Pa), which must be a small negative stress.
    #[error("s_i_min must be a small negative stress (Pa), got {0}")]
    PrincipalStressFloor(f64),
    /// `alpha` or `beta` of the unloading rules, in (0, 1].
    #[error("{name} must lie in (0, 1], got {value}")]
    UnloadingFraction {
        /// The parameter's name as the parameter file writes it.
        name: &'static str,
        /// The value given, in the parameter's unit.
        value: f64,
    },
    /// The tensile boundary's constants.
    #[error(transparent)]
    TensionBoundary(#[from] TensionBoundaryError),
    /// The strength field's coefficient of variation or correlation length.
    #[error(transparent)]
    StrengthField(#[from] StrengthFieldError),
    /// `crack_band: across_crack` with the tensile boundary, whose planes crack through their
    /// own crack strains: the onset that fixes the band is read from the tension laws' history,
    /// which the boundary replaces.
    #[error(
        "crack_band: across_crack is not available with tension_boundary (the band is fixed \
         where a tension law passes its peak, and the boundary replaces the tension laws); use \
         crack_band: volume"
    )]
    AcrossCrackWithBoundary,
    /// Constants of the rate law (5.110) out of range.
    #[error("rate_effect needs c1 > 0 and c2 >= 0, got c1 = {c1}, c2 = {c2}")]
    RateEffect {
        /// The reference strain rate `c1` (1/s), which must be positive.
        c1: f64,
        /// The strength gain per unit of `asinh` `c2` (dimensionless), which must not be negative.
        c2: f64,
    },
}

#[cfg(test)]
mod tests {
    #[test]
    fn rate_factor_is_one_plus_c2_asinh() {
        let rate = super::RateEffect {
            c1: 4e-6,
            c2: 0.022,
        };
        for gamma_dot in [0.0, 1e-12, 1e-6, 4e-6, 1e-3, 1.0, 1e3, 1e6] {
            let exact = 1.0 + 0.022 * (gamma_dot / 4e-6f64).asinh();
            let f = rate.factor(gamma_dot);
            assert!(
                (f - exact).abs() < 1e-15,
                "{gamma_dot}: {f} against {exact}"
            );
        }
    }
}
