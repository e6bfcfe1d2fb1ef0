//! Element and nodal fields of a state, packaged as a frame for the VTU writer.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::{MaterialHistory, Model};
use crate::kinematics::{green_lagrange_from_h, principal_values, voigt};
use crate::material::{Deformation, ElementState};

/// The crack indicator `eps_1 / eps_r` of every element (FORMULATION 5, thesis 5.1): an element
/// counts as cracked when its largest principal Green-Lagrange strain `eps_1` reaches
/// `eps_r = w_cr / L`. Written in a scene as `crack_indicator: { crack_width: 2.0e-4, length:
/// 0.05 }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackIndicator {
    /// Critical crack opening `w_cr` (m); 0.2 mm by default.
    #[serde(default = "default_crack_width")]
    pub crack_width: f64,
    /// Characteristic length `L` (m) for all elements (the thesis uses its average element size,
    /// 50 mm); by default each element's own size `(6 V)^(1/3)`.
    #[serde(default)]
    pub length: Option<f64>,
}

fn default_crack_width() -> f64 {
    2.0e-4
}

impl Default for CrackIndicator {
    fn default() -> Self {
        Self {
            crack_width: default_crack_width(),
            length: None,
        }
    }
}

/// Why a crack indicator's settings are refused (the caller names `crack_indicator`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrackIndicatorError {
    /// A crack width that is not a positive opening.
    #[error("crack_width must be a positive opening in m (default 2.0e-4), got {0}")]
    Width(f64),
    /// A length that is not positive.
    #[error(
        "length must be a positive length in m, or left out for each element's own size (6 \
         V)^(1/3), got {0}"
    )]
    Length(f64),
}

impl CrackIndicator {
    /// Checks that the width and the length are positive.
    pub fn validate(&self) -> Result<(), CrackIndicatorError> {
        if !(self.crack_width > 0.0 && self.crack_width.is_finite()) {
            return Err(CrackIndicatorError::Width(self.crack_width));
        }
        if let Some(l) = self.length {
            if !(l > 0.0 && l.is_finite()) {
                return Err(CrackIndicatorError::Length(l));
            }
        }
        Ok(())
    }

    /// `eps_r = w_cr / L` for an element of size `element_size`.
    pub fn cracking_strain(&self, element_size: f64) -> f64 {
        self.crack_width / self.length.unwrap_or(element_size)
    }
}

/// Cauchy stress, Green-Lagrange strain and its largest principal value per element, with the
/// crack indicator and the microplane rate factor.
pub struct ElementFields {
    /// `[xx, yy, zz, xy, yz, xz]` (Pa). For microplane bodies, the stress of the history's last
    /// update (NaN when no history is given: it cannot be computed from `u` alone).
    pub cauchy: Vec<[f64; 6]>,
    /// Green-Lagrange strain `E = (F^T F - I) / 2` in Voigt order `[xx, yy, zz, xy, yz, xz]`,
    /// tensor shears (dimensionless).
    pub green_lagrange: Vec<[f64; 6]>,
    /// Largest principal value `eps_1` of the Green-Lagrange strain (dimensionless).
    pub max_principal_strain: Vec<f64>,
    /// `eps_1 / eps_r` ([`CrackIndicator`]); 1 or more: cracked.
    pub crack_indicator: Vec<f64>,
    /// Rate factor `F` of the microplane model's last update (1 before the first, NaN without a
    /// history); 0 for elements of materials without a rate effect.
    pub rate_factor: Vec<f64>,
}

impl Model {
    /// Stress and strain of every element at displacement `u` (microplane bodies get NaN stresses
    /// and rate factors: use [`Self::element_fields_with_history`]).
    pub fn element_fields(&self, u: &[Vector3<f64>]) -> ElementFields {
        self.element_fields_with_history(u, None)
    }

    /// Stress and strain of every element at displacement `u`; the stresses of bodies with a
    /// history are those of its last update, which the explicit stepper makes at `u`.
    pub fn element_fields_with_history(
        &self,
        u: &[Vector3<f64>],
        history: Option<&MaterialHistory>,
    ) -> ElementFields {
        let n = self.element_count();
        let mut out = ElementFields {
            cauchy: Vec::with_capacity(n),
            green_lagrange: Vec::with_capacity(n),
            max_principal_strain: Vec::with_capacity(n),
            crack_indicator: Vec::with_capacity(n),
            rate_factor: Vec::with_capacity(n),
        };
        let strains = |out: &mut ElementFields, e: usize| {
            let h = self.strain_gradient(e, u);
            let green = green_lagrange_from_h(&h);
            let eps_1 = principal_values(&green)[2];
            out.max_principal_strain.push(eps_1);
            out.crack_indicator
                .push(eps_1 / self.crack_indicator.cracking_strain(self.element_size(e)));
            out.green_lagrange.push(voigt(&green));
            h
        };
        // A rank of a distributed run that keeps its own elements' connectivity writes only their
        // cells: the others get no value.
        let stored = self.tets.stored_range();
        let unknown = |out: &mut ElementFields| {
            out.cauchy.push([f64::NAN; 6]);
            out.green_lagrange.push([f64::NAN; 6]);
            out.max_principal_strain.push(f64::NAN);
            out.crack_indicator.push(f64::NAN);
            out.rate_factor.push(f64::NAN);
        };
        for (b, body) in self.bodies.iter().enumerate() {
            let material = &body.material;
            if material.history_len() == 0 {
                for e in body.elements.clone() {
                    if !stored.contains(&e) {
                        unknown(&mut out);
                        continue;
                    }
                    let deformation = Deformation::at_rest(strains(&mut out, e));
                    let f = deformation.f;
                    let local = e - body.elements.start;
                    let stateless = ElementState::stateless();
                    let cauchy = match material.update(local, &deformation, stateless) {
                        // sigma = P F^T / det F, symmetrised.
                        Some(first_piola) => {
                            let s = first_piola * f.transpose() / f.determinant();
                            voigt(&(0.5 * (s + s.transpose())))
                        }
                        None => [f64::NAN; 6],
                    };
                    out.cauchy.push(cauchy);
                    out.rate_factor.push(0.0);
                }
                continue;
            }
            // A model with a history reports the stress of its last update.
            let body_history = history
                .and_then(|h| h.bodies.get(b))
                .and_then(Option::as_ref);
            for e in body.elements.clone() {
                if !stored.contains(&e) {
                    unknown(&mut out);
                    continue;
                }
                strains(&mut out, e);
                let local = e - body.elements.start;
                // A rank of a distributed run holds its own elements' history only, and writes
                // only their cells: the others get no value.
                match body_history.and_then(|h| h.stress(local).map(|c| (h, c))) {
                    Some((h, cauchy)) => {
                        out.cauchy.push(cauchy);
                        out.rate_factor.push(material.rate_factor(h.element(local)));
                    }
                    None => {
                        out.cauchy.push([f64::NAN; 6]);
                        out.rate_factor.push(f64::NAN);
                    }
                }
            }
        }
        out
    }
}
