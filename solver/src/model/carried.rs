//! What a model carries from before a remeshing (thesis chapter 8, module `remesh`): the new
//! mesh is built over the current configuration and becomes the reference, so the deformation
//! reached so far travels with the elements, and the displacement reached so far with the nodes.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Result, SolverError};

/// The deformation and displacement a remeshed model starts from.
///
/// With it, element `e` sees `F = F_r F_0[e]` (`F_r = I + grad_X u`, the deformation since the
/// remeshing on the model's reference, which is the configuration at the remeshing), and its
/// first Piola stress on the model's reference is `P_r = P(F) F_0^T / det F_0` (the Cauchy
/// stress `sigma = P F^T / det F` written with `F = F_r F_0`: `P_r = det F_r sigma F_r^-T`), so
/// the forces `f_a = V_r P_r grad_X N_a` are those of the stress-free formulation. Without it
/// (`None` in the model) `F_0 = I` and nothing is computed.
#[derive(Debug, Clone, PartialEq)]
pub struct CarriedState {
    /// `F_0` per element, from the stress-free configuration to the model's reference.
    pub deformation: Vec<Matrix3<f64>>,
    /// `F_0^T / det F_0` per element, the factor that maps `P` to the reference (cached).
    pub(crate) pull_back: Vec<Matrix3<f64>>,
    /// Displacement of each node of the reference from the original configuration (m): the
    /// prescribed motions, given as functions of the original coordinates, read
    /// `X_0 = X - displacement` and compare with `displacement + u`.
    pub displacement: Vec<Vector3<f64>>,
    /// Mass of each element (kg), a quarter to each node: the lumped masses of a remeshed
    /// model are kept, not recomputed from volumes (the reference volume of an element is its
    /// current one at the remeshing, and its density the transferred one).
    pub element_mass: Vec<f64>,
}

impl CarriedState {
    /// The carried deformation `F_0` and mass per element and displacement per node; an element
    /// with a non-positive or non-finite `det F_0` is an error naming it.
    pub fn new(
        deformation: Vec<Matrix3<f64>>,
        displacement: Vec<Vector3<f64>>,
        element_mass: Vec<f64>,
    ) -> Result<Self> {
        let mut pull_back = Vec::with_capacity(deformation.len());
        for (e, f0) in deformation.iter().enumerate() {
            let det = f0.determinant();
            if !(det.is_finite() && det > 0.0) {
                return Err(SolverError::Remesh {
                    entity: format!("element {e}"),
                    message: format!("carried det F_0 = {det:e} is not positive"),
                });
            }
            pull_back.push(f0.transpose() / det);
        }
        Ok(Self {
            deformation,
            pull_back,
            displacement,
            element_mass,
        })
    }
}
