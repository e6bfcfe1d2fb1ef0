//! Microplane concrete as a [`Material`]: the model prepared for one body (its laws and the crack
//! band of each element) and the element update around the model's stress update.

use nalgebra::Matrix3;

use super::{
    state, CrackBand, CrackBandWidth, ElementShape, MicroplaneConcrete, MicroplaneParameters, Sym,
    CRACK_HISTORY,
};
use crate::error::{Result, SolverError};
use crate::kinematics::{cofactor, green_lagrange_from_h, polar_rotation, voigt};
use crate::material::{
    Deformation, ElementDataError, ElementState, IsotropicElastic, Material, MaterialModel,
    RemeshedElements, StrengthField,
};

/// Microplane concrete prepared for a body: the model with its microplanes and laws precomputed,
/// and the crack band of each element from its reference volume.
#[derive(Debug, Clone)]
pub struct MicroplaneMaterial {
    /// The model with its microplanes and laws precomputed.
    pub model: MicroplaneConcrete,
    /// Crack band of each element of the body, in the body's element order.
    pub bands: Vec<CrackBand>,
    /// The body's strength field (`parameters.strength_field`), kept so that a remeshed
    /// element takes the field's value at its own centroid.
    pub strength_field: Option<StrengthField>,
    /// With `crack_band: across_crack`, each element's reference shape, whose length across its
    /// crack becomes its band at the crack's onset (`crack_width.rs`); `None` with the
    /// volume size's band.
    pub shapes: Option<Vec<ElementShape>>,
}

impl MicroplaneMaterial {
    /// The model for `parameters` and the crack bands of the elements of `volumes` with the
    /// reference centroids `centroids` (the body's elements in order; `first_element` is the
    /// global id of the first). An element too large for the crack band is an error naming the
    /// body, the element (global id and id in its mesh), its size and the limit. With
    /// `crack_band: across_crack` the elements' shapes must follow
    /// ([`MicroplaneMaterial::with_shapes`]).
    pub fn new(
        body: &str,
        parameters: MicroplaneParameters,
        volumes: &[f64],
        centroids: &[[f64; 3]],
        first_element: usize,
    ) -> Result<Self> {
        let model = MicroplaneConcrete::new(parameters).map_err(|e| SolverError::InvalidScene {
            entity: format!("body `{body}` material.microplane.parameters"),
            message: e.to_string(),
        })?;
        let strength_field = match &parameters.strength_field {
            Some(spec) => {
                Some(
                    StrengthField::new(spec).map_err(|e| SolverError::InvalidScene {
                        entity: format!("body `{body}` material.microplane.strength_field"),
                        message: e.to_string(),
                    })?,
                )
            }
            None => None,
        };
        let mut bands = Vec::with_capacity(volumes.len());
        let mut too_large: Option<(usize, String)> = None;
        let mut count = 0;
        for (local, &v) in volumes.iter().enumerate() {
            let strength = strength_at(strength_field.as_ref(), centroids[local]);
            match model.crack_band_with_strength(MicroplaneConcrete::element_size(v), strength) {
                Ok(band) => bands.push(band),
                Err(message) => {
                    count += 1;
                    too_large.get_or_insert((local, message.to_string()));
                }
            }
        }
        if let Some((local, message)) = too_large {
            let more = match count {
                1 => String::new(),
                n => format!(" ({} more elements of the body are too large)", n - 1),
            };
            return Err(SolverError::InvalidScene {
                entity: format!(
                    "body `{body}` element {} (element {local} of its mesh)",
                    first_element + local
                ),
                message: format!("{message}{more}"),
            });
        }
        Ok(Self {
            model,
            bands,
            strength_field,
            shapes: None,
        })
    }

    /// The material with the band across the crack, for elements with the reference nodes
    /// `corners` (in the body's element order; `first_element` is the global id of the first),
    /// if its parameters ask for it (`crack_band: across_crack`); unchanged otherwise. An
    /// element whose longest edge, the widest band it can take, is too large for its laws is an
    /// error naming the body and the element.
    pub fn with_shapes(
        mut self,
        body: &str,
        corners: impl Iterator<Item = [[f64; 3]; 4]>,
        first_element: usize,
    ) -> Result<Self> {
        if self.model.parameters.crack_band != CrackBandWidth::AcrossCrack {
            return Ok(self);
        }
        let mut shapes = Vec::new();
        for (local, c) in corners.enumerate() {
            let shape = ElementShape::new(&c).ok_or_else(|| SolverError::InvalidScene {
                entity: format!(
                    "body `{body}` element {} (element {local} of its mesh)",
                    first_element + local
                ),
                message: "degenerate: its nodes span no volume, so it has no length across a \
                          crack"
                    .to_string(),
            })?;
            shapes.push(shape);
        }
        let mut refused =
            shapes
                .iter()
                .zip(&self.bands)
                .enumerate()
                .filter_map(|(local, (shape, band))| {
                    let err = self.model.check_widest_crack(shape, band).err()?;
                    Some((local, err))
                });
        if let Some((local, message)) = refused.next() {
            let more = match refused.count() {
                0 => String::new(),
                n => format!(" ({n} more elements of the body are too wide)"),
            };
            return Err(SolverError::InvalidScene {
                entity: format!(
                    "body `{body}` element {} (element {local} of its mesh)",
                    first_element + local
                ),
                message: format!("{message}{more}"),
            });
        }
        self.shapes = Some(shapes);
        Ok(self)
    }
}

/// The strength factor at `x`: the field's, or 1 without one.
fn strength_at(field: Option<&StrengthField>, x: [f64; 3]) -> f64 {
    field.map_or(1.0, |field| field.factor(x))
}

/// `[11, 22, 33, 23, 13, 12]` of a symmetric matrix (the microplane model's order, tensor shears).
#[inline(always)]
pub fn sym(a: &Matrix3<f64>) -> Sym {
    [
        a[(0, 0)],
        a[(1, 1)],
        a[(2, 2)],
        a[(1, 2)],
        a[(0, 2)],
        a[(0, 1)],
    ]
}

/// The symmetric matrix of `[11, 22, 33, 23, 13, 12]`.
#[inline(always)]
fn matrix(s: &Sym) -> Matrix3<f64> {
    Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2])
}

impl Material for MicroplaneMaterial {
    fn name(&self) -> &'static str {
        "microplane"
    }

    fn constants(&self) -> IsotropicElastic {
        self.model.parameters.elastic()
    }

    fn model(&self) -> Option<MaterialModel> {
        Some(MaterialModel::Microplane(self.model.parameters))
    }

    fn history_len(&self) -> usize {
        self.model.state_len() + self.shapes.as_ref().map_or(0, |_| CRACK_HISTORY)
    }

    /// One elastic-like update per microplane direction on top of the element's own: 22 for the
    /// 21 directions, against the 20 to 25 times a linear element that the benchmarks measure
    /// (docs/performance.md).
    fn relative_cost(&self) -> f64 {
        1.0 + self.model.planes().len() as f64
    }

    /// The model's virgin history, then (across the crack) no band yet: zeros.
    fn initial_history(&self, history: &mut [f32]) {
        let (laws, crack) = history.split_at_mut(self.model.state_len());
        laws.copy_from_slice(&self.model.initial_state().values);
        crack.fill(0.0);
    }

    /// Only with the rate effect on: without it the rate factor is 1 whatever the rate, so the
    /// element loop skips the corner velocities and `F_dot`, and the update the strain rate.
    fn reads_rate(&self) -> bool {
        self.model.parameters.rate_effect.is_some()
    }

    /// The update of one element (FORMULATION 1, MICROPLANE.md):
    ///
    /// - the rotation `R` of `F = R U` by [`polar_rotation`] (`None` for an inverted element);
    /// - Green-Lagrange strain `E = (H + H^T + H^T H)/2` (small strains keep their digits);
    /// - strain rate from the velocities `v_{n-1/2}` of the half step before:
    ///   `Edot = sym(F_{n-1/2}^T Fdot)` with `F_{n-1/2} = F - dt/2 Fdot`. Since
    ///   `u_n - u_{n-1} = dt v_{n-1/2}`, `F_n - F_{n-1} = dt Fdot` and this `Edot` equals
    ///   `(E_n - E_{n-1})/dt` exactly (up to round-off; the first step, where `v` is the initial
    ///   velocity, and contact position corrections make it a first-order estimate), the backward
    ///   difference that the material-point driver uses too. Equivalent rate
    ///   `gamma_dot = sqrt(1/2 Edot:Edot)` (5.111), 0 with the rate effect off;
    /// - back-rotated Cauchy stress `s` from the model, `sigma = R s R^T`, first Piola
    ///   `P = J sigma F^-T = sigma cof F`.
    #[inline]
    fn update(&self, element: usize, d: &Deformation, state: ElementState) -> Option<Matrix3<f64>> {
        let rotation = match polar_rotation(&d.f) {
            Some(r) if d.det > 0.0 && d.det.is_finite() => r,
            _ => return None,
        };
        let strain = sym(&green_lagrange_from_h(&d.h));
        let gamma_dot = if self.reads_rate() {
            let f_mid = d.f - (0.5 * d.dt) * d.f_dot;
            let e_dot = f_mid.transpose() * d.f_dot;
            let e_dot = 0.5 * (e_dot + e_dot.transpose());
            (0.5 * e_dot.norm_squared()).sqrt()
        } else {
            0.0
        };
        let (s, _) = match &self.shapes {
            None => self
                .model
                .update(state.history, &strain, gamma_dot, &self.bands[element]),
            Some(shapes) => self.model.update_across_crack(
                state.history,
                &strain,
                gamma_dot,
                &self.bands[element],
                &shapes[element],
            ),
        };
        let sigma = rotation * matrix(&s) * rotation.transpose();
        if let Some(cauchy) = state.cauchy {
            *cauchy = voigt(&sigma);
        }
        Some(sigma * cofactor(&d.f))
    }

    fn rate_factor(&self, history: &[f32]) -> f64 {
        history[state::RATE_FACTOR] as f64
    }

    fn fast_updates(&self, history: &[f32]) -> Option<f64> {
        Some(history[state::ELASTIC_UPDATES] as f64)
    }

    /// Each kept element keeps its crack band; a new element gets the band of its own size (and
    /// strength, with a strength field, at its centroid), so that the fracture energy stays that
    /// of the new element's size (crack band, Bažant & Oh 1983).
    fn remeshed(&self, elements: &RemeshedElements<'_>) -> Result<Option<Self>, (usize, String)> {
        let new = elements.origin.iter().position(Option::is_none);
        if let (Some(_), Some(e)) = (&self.shapes, new) {
            // A remeshed element has no reference shape here to measure its crack across.
            return Err((
                e,
                "crack_band: across_crack does not carry through a remeshing yet (a new \
                 element's reference nodes are not passed to the material); use crack_band: \
                 volume"
                    .to_string(),
            ));
        }
        let shapes = self.shapes.as_ref().map(|shapes| {
            elements
                .origin
                .iter()
                .map(|o| shapes[o.expect("no new element") as usize])
                .collect()
        });
        let mut bands = Vec::with_capacity(elements.origin.len());
        for (e, (o, v)) in elements.origin.iter().zip(elements.volumes).enumerate() {
            bands.push(match o {
                Some(o) => self.bands[*o as usize],
                None => {
                    let centroid = elements.centroids[e].into();
                    let strength = strength_at(self.strength_field.as_ref(), centroid);
                    self.model
                        .crack_band_with_strength(MicroplaneConcrete::element_size(*v), strength)
                        .map_err(|message| (e, message.to_string()))?
                }
            });
        }
        Ok(Some(MicroplaneMaterial {
            model: self.model.clone(),
            bands,
            strength_field: self.strength_field.clone(),
            shapes,
        }))
    }

    /// Each element's crack band: size, tension and shear factors, strength (four numbers).
    fn element_data(&self) -> Option<Vec<f64>> {
        Some(
            self.bands
                .iter()
                .flat_map(|b| [b.size, b.tension, b.shear, b.strength])
                .collect(),
        )
    }

    fn with_element_data(&self, data: &[f64]) -> Result<Option<Self>, ElementDataError> {
        if data.len() % 4 != 0 {
            return Err(ElementDataError {
                numbers: data.len(),
                per_element: 4,
                what: "a crack band's size, tension and shear factors and strength",
            });
        }
        let bands = data
            .chunks_exact(4)
            .map(|b| CrackBand {
                size: b[0],
                tension: b[1],
                shear: b[2],
                strength: b[3],
            })
            .collect::<Vec<_>>();
        if let Some(shapes) = &self.shapes {
            // The shapes come from the scene's mesh, which a restart reads again; a band fixed
            // across a crack is in each element's history.
            if shapes.len() != bands.len() {
                return Err(ElementDataError {
                    numbers: data.len(),
                    per_element: 4,
                    what: "a crack band for each element of the scene's mesh (across_crack)",
                });
            }
        }
        Ok(Some(MicroplaneMaterial {
            model: self.model.clone(),
            bands,
            strength_field: self.strength_field.clone(),
            shapes: self.shapes.clone(),
        }))
    }

    fn strength_factor(&self, element: usize) -> Option<f64> {
        self.strength_field
            .as_ref()
            .map(|_| self.bands[element].strength)
    }

    fn summary(&self) -> Option<String> {
        let (lo, hi) = self
            .bands
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
                (lo.min(b.size), hi.max(b.size))
            });
        let strength = match self.strength_field {
            Some(_) => {
                let (weak, strong) = self
                    .bands
                    .iter()
                    .fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
                        (lo.min(b.strength), hi.max(b.strength))
                    });
                format!(", tensile strength {weak:.3}-{strong:.3} of the material's")
            }
            None => String::new(),
        };
        let across = match self.shapes {
            Some(_) => ", crack band across each element's crack (Oliver's length)",
            None => "",
        };
        Some(format!(
            "{} directions, element sizes {:.1}-{:.1} mm, limit {:.1} mm{strength}{across}",
            self.model.planes().len(),
            lo * 1e3,
            hi * 1e3,
            self.model.largest_element() * 1e3,
        ))
    }
}
