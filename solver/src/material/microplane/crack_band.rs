//! The crack band of the microplane laws (Bazant and Oh 1983): the factors by which
//! an element of size `h` scales the post-peak part of its tension and shear laws so that it
//! dissipates the energy calibrated at `h_ref` per unit crack area, and the sizes at which no
//! factor can. `h` is the element's volume size `(6 V)^(1/3)`, or with `crack_band: across_crack`
//! its length across its crack (`crack_width.rs`), which the same factors scale to.

use super::MicroplaneConcrete;

/// Why an element is too large for the crack band of the microplane laws: its softening laws
/// would have to snap back to dissipate the calibrated energy per unit crack area. Each message
/// gives the sizes (mm) and says to refine the mesh there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrackBandError {
    /// Too large for the calibrated tension boundary.
    #[error(
        "element size h = (6 V)^(1/3) = {h_mm:.1} mm (tensile strength {strength:.3} of the \
         material's) is too large for the tension boundary calibrated at h_ref = {h_ref_mm:.1} \
         mm: its planes would have to snap back to dissipate no more than the fracture energy; \
         refine the mesh there"
    )]
    TensionBoundary {
        /// The element size (mm).
        h_mm: f64,
        /// The element's tensile strength over the material's.
        strength: f64,
        /// The calibration size (mm).
        h_ref_mm: f64,
    },
    /// Too large once a strength field scales its tensile strength.
    #[error(
        "element size h = (6 V)^(1/3) = {h_mm:.1} mm with a tensile strength {strength:.3} times \
         the material's (strength_field) would need a crack band of an element of \
         {equivalent_mm:.1} mm, above the {largest_mm:.1} mm at which the tension law would have \
         to snap back to dissipate no more than the fracture energy; refine the mesh there or \
         lower the strength field's coefficient_of_variation"
    )]
    StrongElement {
        /// The element size (mm).
        h_mm: f64,
        /// The element's tensile strength over the material's.
        strength: f64,
        /// The size of the element whose band it needs, `h s^2` (mm).
        equivalent_mm: f64,
        /// The largest element the tension law admits (mm).
        largest_mm: f64,
    },
    /// Too large for the laws calibrated at `h_ref`.
    #[error(
        "element size h = (6 V)^(1/3) = {h_mm:.1} mm exceeds the {largest_mm:.1} mm above which \
         the microplane laws (calibrated at h_ref = {h_ref_mm:.1} mm) would have to snap back to \
         dissipate no more than the fracture energy; refine the mesh there"
    )]
    TooLarge {
        /// The element size (mm).
        h_mm: f64,
        /// The largest element the laws admit (mm).
        largest_mm: f64,
        /// The calibration size (mm).
        h_ref_mm: f64,
    },
    /// With the band across the crack (`crack_width.rs`): the element's longest edge, the
    /// widest its crack band can be, is too large for the laws.
    #[error(
        "element's longest edge {width_mm:.1} mm (tensile strength {strength:.3} of the \
         material's), the widest crack band across it (crack_band: across_crack), exceeds the \
         {largest_mm:.1} mm above which its softening laws would have to snap back to \
         dissipate no more than the fracture energy; refine the mesh there"
    )]
    TooWide {
        /// The element's longest edge (mm).
        width_mm: f64,
        /// The element's tensile strength over the material's.
        strength: f64,
        /// The largest band the laws admit at that strength (mm).
        largest_mm: f64,
    },
}

/// The crack-band factors of one element (see [`super::laws::ExponentialLaw::band_factor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackBand {
    /// Element size `h = (6 V)^(1/3)` (m).
    pub size: f64,
    /// Crack-band factor of the tension law (exponent `m`): its post-peak area is divided by it
    /// so that `h` times its energy equals that at `h_ref` (dimensionless, 1 at `h = h_ref`).
    pub tension: f64,
    /// The same factor for the shear law (exponent `k`).
    pub shear: f64,
    /// The element's tensile strength over the material's (1 without a strength field,
    /// `strength_field.rs`): the tension law's strain scale `e1` is multiplied by it.
    pub strength: f64,
}

impl MicroplaneConcrete {
    /// Element size of the crack band, `h = (6 V)^(1/3)` (the edge of a cube cut into six
    /// tetrahedra).
    pub fn element_size(volume: f64) -> f64 {
        (6.0 * volume).cbrt()
    }

    /// The crack band of an element of size `h`, or why the element is too large: its softening
    /// laws would have to snap back to dissipate the calibrated energy per unit crack area.
    pub fn crack_band(&self, h: f64) -> Result<CrackBand, CrackBandError> {
        self.crack_band_with_strength(h, 1.0)
    }

    /// The crack band of an element of size `h` whose tensile strength is `strength` times the
    /// material's (a strength field, `strength_field.rs`). Scaling `e1` by `s` scales the tension
    /// law's energy per unit volume by `s^2` (the law is `E e1 x g(x)` in `x = e / e1`), so the
    /// band's factor is the one of an element of size `h s^2`: the element still dissipates the
    /// calibrated fracture energy per unit crack area, and a strong element too large for its
    /// band is refused like a large one.
    pub fn crack_band_with_strength(
        &self,
        h: f64,
        strength: f64,
    ) -> Result<CrackBand, CrackBandError> {
        let h_ref = self.parameters.h_ref;
        let tension = self.tension.band_factor(h * (strength * strength), h_ref);
        let shear = self.shear.band_factor(h, h_ref);
        if let Some(boundary) = &self.parameters.tension_boundary {
            let e = self.parameters.youngs_modulus;
            if boundary.scaled(e, h, h_ref, strength, 1.0).is_none() {
                return Err(CrackBandError::TensionBoundary {
                    h_mm: h * 1e3,
                    strength,
                    h_ref_mm: h_ref * 1e3,
                });
            }
        }
        match (tension, shear) {
            (Some(tension), Some(shear)) => Ok(CrackBand {
                size: h,
                tension,
                shear,
                strength,
            }),
            (None, Some(_)) if strength != 1.0 => Err(CrackBandError::StrongElement {
                h_mm: h * 1e3,
                strength,
                equivalent_mm: h * strength * strength * 1e3,
                largest_mm: self.tension.largest_element(h_ref) * 1e3,
            }),
            _ => Err(CrackBandError::TooLarge {
                h_mm: h * 1e3,
                largest_mm: self.largest_element() * 1e3,
                h_ref_mm: h_ref * 1e3,
            }),
        }
    }

    /// Largest element size the crack band admits.
    pub fn largest_element(&self) -> f64 {
        let h_ref = self.parameters.h_ref;
        self.tension
            .largest_element(h_ref)
            .min(self.shear.largest_element(h_ref))
    }
}
