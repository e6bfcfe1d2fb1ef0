//! A tensile boundary on each microplane's total normal stress, in the form of M7 (Caner &
//! Bažant 2013): the volumetric-deviatoric split is kept for compression only, and the plane's
//! total normal stress `sigma_N = s_V + s_D` (in the elastic range exactly the traction
//! `n . sigma . n`, MICROPLANE "Elastic split") is capped, plane by plane, by a softening
//! boundary. A plane that cracks loses its normal stress and, while open, its shear; the planes
//! across it keep theirs, so a cracked point still carries a compression along its crack, which
//! the scalar relaxation `psi` of the thesis cannot do (docs/MICROPLANE.md "Tensile boundary").
//!
//! Per plane, the crack strain `y` along its normal (`crack_strain`): every law of the element
//! sees the strain less the planes' crack strains, and a plane opens where its driver
//! `q = t + theta nu <-s_min>` (the traction across it raised by the larger compression along it;
//! `theta` = `strain_weight`, 0 is Rankine on every plane; `theta = 0.8 f_t / (nu f_c)` gives
//! Kupfer & Gerstle 1973's slope `0.8 f_t / f_c` on the plane normal to `sigma_1`) would pass the
//! boundary `F(y)` (`boundary_shape`: M4 and M7's exponential `f0 exp(-y / eps_f)`, flat part
//! dropped, or MC2010's bilinear); it unloads on the secant to the origin of `F` at its largest
//! crack strain, and closes in compression.
//!
//! The shear boundary (M7's shear boundary: a cohesion that goes as the planes open, friction on
//! the compressed ones): the shear laws' stress of every plane is multiplied by `1 - D`, `D` the
//! largest fall `1 - F(y_max) / f0` of a plane's boundary, and with `crack_friction` each
//! compressed plane's Coulomb slider carries up to `mu <-sigma_N>` once the element has cracked.
//! Without the release of the compressed planes' shear a point under a lateral compression kept
//! hardening after its tensile planes had cracked.
//!
//! Crack band: the plane dissipates `6 w f0 eps_f` per unit volume (`w` its weight); `eps_f` is
//! set per element so that `h` times that is the energy at `h_ref` (Bažant & Oh 1983), with the rate
//! factor and the element's strength scaling `f0` (and the rate factor the energy by `F^2`, as it
//! does for the thesis' tension law).
//! With an onset strain `y0` the boundary is that of `h_ref` up to the crack strain `y0` at every
//! size, and only the tail beyond it is scaled (`h` times the whole area still the same): the
//! planes that soften before the point peaks then do so alike at every size, and so does the peak.

use serde::{Deserialize, Serialize};

use super::boundary_shape::{self, BoundaryShape};
use super::{state, CrackBand, MicroplaneConcrete, MicroplaneParameters};

/// The tensile boundary of every microplane (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TensionBoundary {
    /// `f0`: the largest total normal stress of a plane (Pa).
    pub strength: f64,
    /// `eps_f`: the strain scale of the boundary's softening at `h_ref`.
    pub softening_strain: f64,
    /// `theta` in `[0, 1)`: `theta nu` is the fall of a plane's strength per unit compression
    /// along it (`crack_strain`; the name is that of the former driver
    /// `(1 - theta) sigma_N + theta E eps_N`, which has the same slope in the elastic range).
    #[serde(default)]
    pub strain_weight: f64,
    /// `y0 >= 0`: the crack strain up to which a plane softens on the boundary of `h_ref` at
    /// every element size; the crack band scales only the softening beyond it (0, the default:
    /// all of it).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub onset_strain: f64,
    /// The shape of `F` (`boundary_shape`): exponential (the default) or MC2010's bilinear.
    #[serde(default, skip_serializing_if = "BoundaryShape::is_exponential")]
    pub shape: BoundaryShape,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// What is wrong with a [`TensionBoundary`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TensionBoundaryError {
    /// A non-positive strength or softening strain, or a weight outside `[0, 1)`.
    #[error(
        "tension_boundary needs strength > 0 (Pa), softening_strain > 0, strain_weight in \
         [0, 1) and onset_strain >= 0, got {strength}, {softening_strain}, {strain_weight} and \
         {onset_strain}"
    )]
    OutOfRange {
        /// `f0` (Pa).
        strength: f64,
        /// `eps_f`.
        softening_strain: f64,
        /// `theta`.
        strain_weight: f64,
        /// `y0`.
        onset_strain: f64,
    },
    /// An onset strain with a shape other than the exponential.
    #[error(
        "tension_boundary: onset_strain is defined for the exponential shape only; remove it or \
         use shape: exponential"
    )]
    OnsetNeedsExponential,
}

impl TensionBoundary {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), TensionBoundaryError> {
        let ok = self.strength > 0.0
            && self.strength.is_finite()
            && self.softening_strain > 0.0
            && self.softening_strain.is_finite()
            && (0.0..1.0).contains(&self.strain_weight)
            && self.onset_strain >= 0.0
            && self.onset_strain.is_finite();
        if ok && self.onset_strain > 0.0 && !self.shape.is_exponential() {
            return Err(TensionBoundaryError::OnsetNeedsExponential);
        }
        if ok {
            Ok(())
        } else {
            Err(TensionBoundaryError::OutOfRange {
                strength: self.strength,
                softening_strain: self.softening_strain,
                strain_weight: self.strain_weight,
                onset_strain: self.onset_strain,
            })
        }
    }

    /// The boundary of an element of size `h` and strength factor `s` at the rate factor `f`:
    /// its `f0` and `eps_f`, or `None` where `eps_f` would not exceed `f0 / E` (the plane would
    /// snap back: the element is too large for its band).
    pub fn scaled(&self, youngs: f64, h: f64, h_ref: f64, s: f64, f: f64) -> Option<PlaneBoundary> {
        // Dissipated per unit volume: the integral of F over the crack strain, f0 eps_f (the
        // elastic energy stored up to the peak is given back as the stress falls).
        let energy = f * f * (h_ref / h) * self.strength * self.softening_strain;
        let f0 = f * s * self.strength;
        if self.onset_strain > 0.0 {
            // Up to y0 the boundary of h_ref; beyond, the tail that leaves the element the
            // energy of its band.
            let first = f * f * self.strength * self.softening_strain / f0;
            let decayed = (-self.onset_strain / first).exp();
            let tail = (energy - f0 * first * (1.0 - decayed)) / (f0 * decayed);
            return (first > f0 / youngs && tail > f0 * decayed / youngs).then_some(
                PlaneBoundary {
                    f0,
                    softening: tail,
                    youngs,
                    onset: Some((self.onset_strain, first)),
                    shape: BoundaryShape::Exponential,
                },
            );
        }
        // Either shape encloses f0 eps_f (`boundary_shape`).
        let softening = energy / f0;
        (softening > self.shape.steepest_fall() * f0 / youngs).then_some(PlaneBoundary {
            f0,
            softening,
            youngs,
            onset: None,
            shape: self.shape,
        })
    }
}

/// The boundary of one element at one update (see [`TensionBoundary::scaled`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneBoundary {
    /// `f0` (Pa).
    pub f0: f64,
    /// `eps_f` of this element.
    pub softening: f64,
    /// `E` (Pa).
    pub youngs: f64,
    /// With an onset strain `y0`: `(y0, eps_f at h_ref)`, the boundary up to `y0`; `softening`
    /// is then the scale of the tail beyond it.
    pub onset: Option<(f64, f64)>,
    /// The shape of `F` (`boundary_shape`).
    pub shape: BoundaryShape,
}

impl PlaneBoundary {
    /// The boundary `F(y)` at the crack strain `y` (Pa).
    pub(super) fn value(&self, y: f64) -> f64 {
        self.boundary(y).0
    }

    /// The boundary `F(y)` and its slope at the crack strain `y`.
    fn boundary(&self, y: f64) -> (f64, f64) {
        if self.shape == BoundaryShape::Mc2010 {
            return boundary_shape::mc2010(self.f0, self.softening, y);
        }
        match self.onset {
            Some((y0, first)) if y <= y0 => {
                let value = self.f0 * (-y / first).exp();
                (value, -value / first)
            }
            Some((y0, first)) => {
                let value = self.f0 * (-y0 / first).exp() * (-(y - y0) / self.softening).exp();
                (value, -value / self.softening)
            }
            None => {
                let value = self.f0 * (-y / self.softening).exp();
                (value, -value / self.softening)
            }
        }
    }

    /// [`PlaneBoundary::damage`] with an onset strain: the root of `kappa - E y - F(y)`, which
    /// falls from `kappa - f0 > 0` at `y = 0` to `-F <= 0` at `kappa / E`, by Newton's method
    /// kept inside that bracket (bisection where a step leaves it: `F` has a kink at `y0`).
    fn damage_with_onset(&self, kappa: f64) -> f64 {
        let e = self.youngs;
        let (mut low, mut high) = (0.0, kappa / e);
        let mut y = 0.0;
        for _ in 0..100 {
            let (value, slope) = self.boundary(y);
            let g = kappa - e * y - value;
            if g > 0.0 {
                low = y;
            } else {
                high = y;
            }
            let mut next = y - g / (-e - slope);
            if !(next > low && next < high) {
                next = 0.5 * (low + high);
            }
            if (next - y).abs() <= 1e-13 * kappa / e {
                y = next;
                break;
            }
            y = next;
        }
        (e * y / kappa).clamp(0.0, 1.0)
    }

    /// Damage `d` at the largest driver `kappa` (Pa): 0 up to `f0`, else the root of
    /// `kappa - E y - f0 exp(-y / eps_f) = 0` in the crack strain `y`, `d = E y / kappa`. The
    /// function is concave and falls from `kappa - f0 > 0` (no snap-back), so Newton's method
    /// from `y = 0` overshoots once and then converges from above.
    pub fn damage(&self, kappa: f64) -> f64 {
        if kappa <= self.f0 {
            return 0.0;
        }
        if self.onset.is_some() {
            return self.damage_with_onset(kappa);
        }
        if self.shape == BoundaryShape::Mc2010 {
            let y =
                boundary_shape::mc2010_crack_strain(kappa, self.youngs, self.f0, self.softening);
            return (self.youngs * y / kappa).clamp(0.0, 1.0);
        }
        let (e, f0, ef) = (self.youngs, self.f0, self.softening);
        let mut y = 0.0;
        for _ in 0..30 {
            let decay = f0 * (-y / ef).exp();
            let g = kappa - e * y - decay;
            let slope = -e + decay / ef;
            let step = g / slope;
            y -= step;
            if step.abs() <= 1e-12 * y.abs() {
                break;
            }
        }
        (e * y / kappa).clamp(0.0, 1.0)
    }
}

/// The boundary of one element at one update: its planes' boundary and the element's shear
/// release `D`, the largest fall `1 - F(y_max) / f0` of a plane's boundary at the largest crack
/// strain it reached (`crack_strain`), which releases the shear of every plane (M7's cohesion that
/// vanishes as the planes open).
#[derive(Debug, Clone, Copy)]
pub(super) struct ElementBoundary {
    element_damage: f64,
}

impl ElementBoundary {
    /// The boundary of an element with crack band `band` at the rate factor `f`, its plane
    /// histories `planes` ([`state::PER_PLANE`] values per plane, the crack strains of this
    /// update already solved).
    pub(super) fn new(
        boundary: &TensionBoundary,
        parameters: &MicroplaneParameters,
        band: &CrackBand,
        f: f64,
        planes: &[f32],
    ) -> Self {
        let plane = Self::plane_boundary(boundary, parameters, band, f);
        let largest = planes
            .chunks_exact(state::PER_PLANE)
            .map(|h| h[state::D_POSITIVE])
            .fold(0.0f32, f32::max) as f64;
        let element_damage = if largest > 0.0 {
            (1.0 - plane.value(largest) / plane.f0).clamp(0.0, 1.0)
        } else {
            0.0
        };
        Self { element_damage }
    }

    /// The planes' boundary of an element with crack band `band` at the rate factor `f`.
    pub(super) fn plane_boundary(
        boundary: &TensionBoundary,
        parameters: &MicroplaneParameters,
        band: &CrackBand,
        f: f64,
    ) -> PlaneBoundary {
        let (e, h_ref, s) = (parameters.youngs_modulus, parameters.h_ref, band.strength);
        boundary
            .scaled(e, band.size, h_ref, s, f)
            .unwrap_or_else(|| PlaneBoundary {
                // Refused when the body was built; kept finite if a remeshed element is not.
                f0: f * s * boundary.strength,
                softening: 1.000001 * f * s * boundary.strength / e,
                youngs: e,
                onset: None,
                shape: BoundaryShape::Exponential,
            })
    }

    /// Whether the element has a cracked plane (its shear laws are then being released and a
    /// crack friction's sliders take over on the compressed planes).
    #[inline(always)]
    pub(super) fn cracked(&self) -> bool {
        self.element_damage > 0.0
    }

    /// One plane's deviatoric, `m` and `k` stresses under the shear boundary, and its total
    /// normal stress, from the laws' `s_d`, `s_m`, `s_k` and the volumetric stress `s_v`, the
    /// laws having seen the strain less the element's crack strain (`crack_strain`), so that the
    /// normal stress is already the plane's traction under its boundary.
    ///
    /// The shear boundary (M7's cohesion that vanishes as the planes open, Caner & Bažant
    /// 2013): the shear laws' stress of every plane is multiplied by `1 - D`. On a compressed
    /// plane the crack friction's slider, bounded by `mu <-sigma_N>`, then carries what friction
    /// can (`MicroplaneConcrete::crack_friction`).
    #[inline(always)]
    pub(super) fn cap_plane(&self, s_v: f64, s_d: f64, s_m: f64, s_k: f64) -> (f64, f64, f64, f64) {
        let kept = 1.0 - self.element_damage;
        (s_d, kept * s_m, kept * s_k, s_v + s_d)
    }

    /// One plane's deviatoric, `m` and `k` stresses under the tensile and shear boundaries:
    /// [`ElementBoundary::cap_plane`], then, with crack friction, the Coulomb slider of the plane
    /// (`slip`, present with crack friction; the plane's shear strains in `shear.2`) bounded by
    /// `mu <-sigma_N>` on the plane's capped normal stress, engaged once the element has cracked
    /// or a shear law of the plane has passed its peak strain `shear_peak` (M7's frictional
    /// shear boundary on compressed planes; on an open plane the bound is 0 and the released
    /// laws' stress stays).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn plane_stresses(
        &self,
        model: &MicroplaneConcrete,
        history: &mut [f32],
        slip: Option<&mut [f32]>,
        s_v: f64,
        s_d: f64,
        shear: (f64, f64, [f64; 2]),
        shear_peak: f64,
    ) -> (f64, f64, f64) {
        let (s_m, s_k, strain) = shear;
        let (s_d, s_m, s_k, total) = self.cap_plane(s_v, s_d, s_m, s_k);
        match (model.parameters.crack_friction, slip) {
            (Some(mu), Some(slip)) => {
                let reached = [state::M, state::M + 2, state::K, state::K + 2];
                let cracked =
                    self.cracked() || reached.iter().any(|&i| history[i] as f64 > shear_peak);
                let bound = mu * (-total).max(0.0);
                let (s_m, s_k) = model.crack_friction([s_m, s_k], strain, slip, bound, cracked);
                (s_d, s_m, s_k)
            }
            _ => (s_d, s_m, s_k),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boundary() -> PlaneBoundary {
        TensionBoundary {
            strength: 3.0e6,
            softening_strain: 1.0e-3,
            strain_weight: 0.0,
            onset_strain: 0.0,
            shape: BoundaryShape::Exponential,
        }
        .scaled(30e9, 0.05, 0.05, 1.0, 1.0)
        .unwrap()
    }

    #[test]
    fn damage_puts_the_plane_on_its_boundary() {
        let b = boundary();
        assert_eq!(b.damage(2.0e6), 0.0);
        for kappa in [3.1e6, 5e6, 3e7, 3e8] {
            let d = b.damage(kappa);
            let y = d * kappa / b.youngs;
            let on_boundary = b.f0 * (-y / b.softening).exp();
            assert!(
                ((1.0 - d) * kappa - on_boundary).abs() < 1e-6 * b.f0,
                "kappa {kappa}: {} against {on_boundary}",
                (1.0 - d) * kappa
            );
        }
    }

    #[test]
    fn with_an_onset_the_damage_puts_the_plane_on_its_boundary() {
        let spec = TensionBoundary {
            strength: 3.0e6,
            softening_strain: 4.0e-4,
            strain_weight: 0.0,
            onset_strain: 5.0e-5,
            shape: BoundaryShape::Exponential,
        };
        for h in [0.025, 0.05, 0.1] {
            let b = spec.scaled(30e9, h, 0.05, 1.0, 1.0).unwrap();
            for kappa in [3.05e6, 4e6, 5e6, 3e7, 3e8] {
                let d = b.damage(kappa);
                let y = d * kappa / b.youngs;
                let on_boundary = b.boundary(y).0;
                assert!(
                    ((1.0 - d) * kappa - on_boundary).abs() < 1e-6 * b.f0,
                    "h {h}, kappa {kappa}: {} against {on_boundary}",
                    (1.0 - d) * kappa
                );
            }
            // Up to the onset the boundary is that of h_ref at every size.
            let reference = spec.scaled(30e9, 0.05, 0.05, 1.0, 1.0).unwrap();
            assert_eq!(b.boundary(4e-5).0, reference.boundary(4e-5).0);
        }
    }

    #[test]
    fn energy_per_crack_area_does_not_depend_on_the_element() {
        for onset_strain in [0.0, 5.0e-5] {
            energy_per_crack_area_for(onset_strain, BoundaryShape::Exponential);
        }
        energy_per_crack_area_for(0.0, BoundaryShape::Mc2010);
    }

    fn energy_per_crack_area_for(onset_strain: f64, shape: BoundaryShape) {
        // h times the area under the plane's uniaxial curve, integrated along the strain.
        let spec = TensionBoundary {
            strength: 3.0e6,
            softening_strain: 4.0e-4,
            strain_weight: 0.0,
            onset_strain,
            shape,
        };
        let energy = |h: f64, s: f64| {
            let b = spec.scaled(30e9, h, 0.05, s, 1.0).unwrap();
            let (mut work, mut last, mut kappa) = (0.0, 0.0f64, 0.0f64);
            let n = 400_000;
            for i in 1..=n {
                let eps = 0.02 * i as f64 / n as f64;
                let sigma_el = b.youngs * eps;
                kappa = kappa.max(sigma_el);
                let sigma = (1.0 - b.damage(kappa)) * sigma_el;
                work += 0.5 * (sigma + last) * 0.02 / n as f64;
                last = sigma;
            }
            h * work
        };
        let reference = energy(0.05, 1.0);
        for (h, s) in [(0.025, 1.0), (0.1, 1.0), (0.05, 0.8), (0.05, 1.2)] {
            let ratio = energy(h, s) / reference;
            assert!(
                (ratio - 1.0).abs() < 1e-3,
                "onset {onset_strain}, h {h}, s {s}: {ratio}"
            );
        }
    }

    #[test]
    fn a_cracked_element_releases_the_shear_of_its_planes() {
        let element = ElementBoundary {
            element_damage: 0.75,
        };
        // A compressed plane keeps its normal stress; its shear laws' stress goes with 1 - D.
        let (s_d, s_m, s_k, total) = element.cap_plane(-4e6, 1e6, 2e6, -1e6);
        assert_eq!((s_d, total), (1e6, -3e6));
        assert_eq!((s_m, s_k), (0.25 * 2e6, 0.25 * -1e6));
        assert!(element.cracked());
        assert!(!ElementBoundary {
            element_damage: 0.0
        }
        .cracked());
    }

    #[test]
    fn a_band_that_would_snap_back_is_refused() {
        let spec = TensionBoundary {
            strength: 3.0e6,
            softening_strain: 2.0e-4,
            strain_weight: 0.0,
            onset_strain: 0.0,
            shape: BoundaryShape::Exponential,
        };
        // f0 / E = 1e-4: the band snaps back beyond h = 0.1 m.
        assert!(spec.scaled(30e9, 0.05, 0.05, 1.0, 1.0).is_some());
        assert!(spec.scaled(30e9, 0.5, 0.05, 1.0, 1.0).is_none());
    }
}
