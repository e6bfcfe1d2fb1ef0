//! The element kernel every analysis shares: the forces of one element from its deformation
//! and its material's update ([`super::BodyMaterial`] runs it over the assembly's chunks).

use nalgebra::{Matrix3, Vector3};

use crate::kinematics::{element_gradient, triple_product_determinant};
use crate::material::{Deformation, ElementState, Material};

/// What one element gives the assembly.
#[derive(Debug, Clone, Copy)]
pub struct ElementForces {
    /// Nodal forces `V P grad_X N_a`.
    pub forces: [Vector3<f64>; 4],
    /// `det F`; not positive (or not finite) for an inverted element. An element the model could
    /// not update has zero forces and an unchanged state (the run stops).
    pub det: f64,
}

/// Forces `f_a = V P grad_X N_a` of element `element` (its id in the body) at displacements `u`,
/// advancing its `state` (thesis 3.102, in the total Lagrangian form of FORMULATION 1). With
/// `rate` (the nodal velocities of the half step before and the time step) a model that reads the
/// strain rate gets `Fdot`; without, the rate is zero (statics).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn element_forces<M: Material + ?Sized>(
    material: &M,
    element: usize,
    grad_n: &[Vector3<f64>; 4],
    volume: f64,
    u: &[Vector3<f64>; 4],
    rate: Option<(&[Vector3<f64>; 4], f64)>,
    state: ElementState<'_>,
) -> ElementForces {
    let h = element_gradient(u, grad_n);
    let f = Matrix3::identity() + h;
    let det = triple_product_determinant(&f);
    let (f_dot, dt) = match rate {
        Some((v, dt)) if material.reads_rate() => (element_gradient(v, grad_n), dt),
        _ => (Matrix3::zeros(), 0.0),
    };
    let deformation = Deformation {
        f,
        h,
        det,
        f_dot,
        dt,
    };
    forces_of_update(material, element, grad_n, &deformation, state, |p| {
        p * volume
    })
}

/// The element forces `f_a = P_r grad_X N_a` of the material's update at `deformation`, with
/// `P_r = reference(P)` the stress times the volume on the model's reference; zero forces and a
/// non-positive `det` when the material cannot update the element (an inverted one).
#[inline(always)]
fn forces_of_update<M: Material + ?Sized>(
    material: &M,
    element: usize,
    grad_n: &[Vector3<f64>; 4],
    deformation: &Deformation,
    state: ElementState<'_>,
    reference: impl FnOnce(Matrix3<f64>) -> Matrix3<f64>,
) -> ElementForces {
    let det = deformation.det;
    match material.update(element, deformation, state) {
        Some(first_piola) => {
            let [g0, g1, g2, g3] = grad_n;
            let p = reference(first_piola);
            ElementForces {
                forces: [p * g0, p * g1, p * g2, p * g3],
                det,
            }
        }
        None => ElementForces {
            forces: [Vector3::zeros(); 4],
            det: if det.is_finite() { det.min(0.0) } else { det },
        },
    }
}

/// [`element_forces`] of an element of a remeshed model, which carries the deformation
/// gradient `f0` (`F_0`, from the stress-free configuration to the model's reference) and its
/// `pull_back = F_0^T / det F_0` ([`super::CarriedState`]): the material sees
/// `F = (I + grad_X u) F_0` and `Fdot = grad_X v F_0`, and the forces on the model's reference
/// are `f_a = V P F_0^T / det F_0 grad_X N_a` (module `remesh`, thesis 8.4.1.1).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn element_forces_carried<M: Material + ?Sized>(
    material: &M,
    element: usize,
    grad_n: &[Vector3<f64>; 4],
    volume: f64,
    u: &[Vector3<f64>; 4],
    rate: Option<(&[Vector3<f64>; 4], f64)>,
    state: ElementState<'_>,
    (f0, pull_back): (&Matrix3<f64>, &Matrix3<f64>),
) -> ElementForces {
    let f = (Matrix3::identity() + element_gradient(u, grad_n)) * f0;
    let h = f - Matrix3::identity();
    let det = triple_product_determinant(&f);
    let (f_dot, dt) = match rate {
        Some((v, dt)) if material.reads_rate() => (element_gradient(v, grad_n) * f0, dt),
        _ => (Matrix3::zeros(), 0.0),
    };
    let deformation = Deformation {
        f,
        h,
        det,
        f_dot,
        dt,
    };
    forces_of_update(material, element, grad_n, &deformation, state, |p| {
        p * pull_back * volume
    })
}
