//! Materials with a history (the microplane concrete model): what the model precomputes for them,
//! the history an analysis owns, and their element kernel.
//!
//! The history is not part of [`Model`], which stays immutable: an analysis creates it with
//! [`Model::initial_history`] and hands it to [`Model::advance_internal_forces`] exactly once per
//! step, which computes the forces at the current displacement and commits the update. Anything
//! else that wants forces or stresses of such a body (a second force evaluation at another
//! displacement, a static Newton iteration, an energy) must not advance it: the explicit stepper
//! computes forces once per step, the static solver updates copies of the committed history at
//! each Newton iteration and commits one per converged load step (`statics::path`), and stored
//! energy and field output read the history without changing it.

use nalgebra::{Matrix3, Vector3};

use super::Model;
use crate::error::{Result, SolverError};
use crate::kinematics::{cofactor, green_lagrange_from_h, polar_rotation, voigt};
use crate::material::microplane::{
    state, CrackBand, MicroplaneConcrete, MicroplaneParameters, Sym,
};

/// What a microplane body needs besides its history: the model with its microplanes and laws
/// precomputed, and the crack band of each element from its reference volume.
#[derive(Debug, Clone)]
pub struct MicroplaneBody {
    pub model: MicroplaneConcrete,
    /// Crack band of each element of the body, in the body's element order.
    pub bands: Vec<CrackBand>,
}

impl MicroplaneBody {
    /// The model for `parameters` and the crack bands of the elements of `volumes` (the body's
    /// elements in order; `first_element` is the global id of the first). An element too large
    /// for the crack band is an error naming the body, the element (global id and id in its
    /// mesh), its size and the limit.
    pub fn new(
        body: &str,
        parameters: MicroplaneParameters,
        volumes: &[f64],
        first_element: usize,
    ) -> Result<Self> {
        let model =
            MicroplaneConcrete::new(parameters).map_err(|message| SolverError::InvalidScene {
                entity: format!("body `{body}` material.microplane.parameters"),
                message,
            })?;
        let mut bands = Vec::with_capacity(volumes.len());
        let mut too_large: Option<(usize, String)> = None;
        let mut count = 0;
        for (local, &v) in volumes.iter().enumerate() {
            match model.crack_band(MicroplaneConcrete::element_size(v)) {
                Ok(band) => bands.push(band),
                Err(message) => {
                    count += 1;
                    too_large.get_or_insert((local, message));
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
        Ok(Self { model, bands })
    }
}

/// The history of one body of a material with history.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyHistory {
    /// `f32` values per element ([`MicroplaneConcrete::state_len`]).
    pub state_len: usize,
    /// The elements' histories one after the other, in the body's element order.
    pub values: Vec<f32>,
    /// Cauchy stress of each element at the last update, `[xx, yy, zz, xy, yz, xz]` (Pa), for the
    /// output: zero before the first step.
    pub cauchy: Vec<[f64; 6]>,
}

impl BodyHistory {
    /// History of element `local` of the body.
    pub fn element(&self, local: usize) -> &[f32] {
        &self.values[local * self.state_len..(local + 1) * self.state_len]
    }

    /// Rate factor `F` of the last update of element `local` (1 before the first).
    pub fn rate_factor(&self, local: usize) -> f64 {
        self.element(local)[state::RATE_FACTOR] as f64
    }

    /// Bytes held per element.
    pub fn bytes_per_element(&self) -> usize {
        self.state_len * std::mem::size_of::<f32>() + std::mem::size_of::<[f64; 6]>()
    }
}

/// The histories of all bodies of a model (`None` for bodies without one), owned by an analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialHistory {
    pub bodies: Vec<Option<BodyHistory>>,
}

impl MaterialHistory {
    /// Whether any body has a history.
    pub fn is_empty(&self) -> bool {
        self.bodies.iter().all(Option::is_none)
    }
}

impl Model {
    /// A virgin history for every body whose material has one.
    pub fn initial_history(&self) -> MaterialHistory {
        MaterialHistory {
            bodies: self
                .bodies
                .iter()
                .map(|body| {
                    body.microplane.as_ref().map(|m| {
                        let n = body.elements.len();
                        let virgin = m.model.initial_state();
                        let state_len = virgin.values.len();
                        let mut values = Vec::with_capacity(n * state_len);
                        for _ in 0..n {
                            values.extend_from_slice(&virgin.values);
                        }
                        BodyHistory {
                            state_len,
                            values,
                            cauchy: vec![[0.0; 6]; n],
                        }
                    })
                })
                .collect(),
        }
    }

    /// Whether some body's material keeps a history.
    pub fn has_history(&self) -> bool {
        self.bodies.iter().any(|b| b.microplane.is_some())
    }
}

/// `[11, 22, 33, 23, 13, 12]` of a symmetric matrix (the microplane model's order, tensor shears).
#[inline(always)]
fn sym(a: &Matrix3<f64>) -> Sym {
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

/// What one microplane element gives the assembly.
pub struct MicroplaneElementUpdate {
    /// Nodal forces `V P grad_X N_a`.
    pub forces: [Vector3<f64>; 4],
    /// `det F`; not positive (or not finite) for an inverted element, whose history is left as it
    /// was and whose forces are zero (the run stops).
    pub det: f64,
    /// Cauchy stress `[xx, yy, zz, xy, yz, xz]`.
    pub cauchy: [f64; 6],
}

/// Forces of one microplane element at displacements `u` with the nodal velocities `v` of the
/// half step before, advancing its history `state` (FORMULATION 1, MICROPLANE.md):
///
/// - `F = I + H`, `H = sum_a u_a (x) grad_X N_a`; the rotation `R` of `F = R U` by
///   [`polar_rotation`];
/// - Green-Lagrange strain `E = (H + H^T + H^T H)/2` (small strains keep their digits);
/// - strain rate from the velocities `v_{n-1/2}` of the half step before: `Fdot = sum_a v_a (x)
///   grad_X N_a`, `Edot = sym(F_{n-1/2}^T Fdot)` with `F_{n-1/2} = F - dt/2 Fdot`. Since
///   `u_n - u_{n-1} = dt v_{n-1/2}`, `F_n - F_{n-1} = dt Fdot` and this `Edot` equals
///   `(E_n - E_{n-1})/dt` exactly (up to round-off; the first step, where `v` is the initial
///   velocity, and contact position corrections make it a first-order estimate), the backward
///   difference that the material-point driver uses too. Equivalent rate
///   `gamma_dot = sqrt(1/2 Edot:Edot)` (5.111);
/// - back-rotated Cauchy stress `s` from the model, `sigma = R s R^T`, first Piola
///   `P = J sigma F^-T = sigma cof F`, forces `V P grad_X N_a`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn microplane_element_forces(
    model: &MicroplaneConcrete,
    band: &CrackBand,
    state: &mut [f32],
    grad_n: &[Vector3<f64>; 4],
    volume: f64,
    u: &[Vector3<f64>; 4],
    v: &[Vector3<f64>; 4],
    dt: f64,
) -> MicroplaneElementUpdate {
    let [g0, g1, g2, g3] = grad_n;
    let h = (u[1] - u[0]) * g1.transpose()
        + (u[2] - u[0]) * g2.transpose()
        + (u[3] - u[0]) * g3.transpose();
    let f = Matrix3::identity() + h;
    let det = f.column(0).dot(&f.column(1).cross(&f.column(2)));
    let rotation = match polar_rotation(&f) {
        Some(r) if det > 0.0 && det.is_finite() => r,
        _ => {
            return MicroplaneElementUpdate {
                forces: [Vector3::zeros(); 4],
                det: if det.is_finite() { det.min(0.0) } else { det },
                cauchy: [0.0; 6],
            }
        }
    };
    let strain = sym(&green_lagrange_from_h(&h));
    let f_dot = (v[1] - v[0]) * g1.transpose()
        + (v[2] - v[0]) * g2.transpose()
        + (v[3] - v[0]) * g3.transpose();
    let f_mid = f - (0.5 * dt) * f_dot;
    let e_dot = f_mid.transpose() * f_dot;
    let e_dot = 0.5 * (e_dot + e_dot.transpose());
    let gamma_dot = (0.5 * e_dot.norm_squared()).sqrt();
    let (s, _) = model.update(state, &strain, gamma_dot, band);
    let sigma = rotation * matrix(&s) * rotation.transpose();
    let p = sigma * cofactor(&f) * volume;
    MicroplaneElementUpdate {
        forces: [p * g0, p * g1, p * g2, p * g3],
        det,
        cauchy: voigt(&sigma),
    }
}
