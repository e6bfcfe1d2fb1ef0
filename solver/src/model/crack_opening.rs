//! The crack opening of each element: the crack band's inelastic strain times the band width.
//!
//! In a crack band of width `L` (Bažant & Oh 1983) the opening of the smeared crack is
//! `w = L eps_in`, with `eps_in` the strain the elastic law does not explain. Here
//! `eps_in = E - C0^-1 sigma` (Green-Lagrange strain `E`, Cauchy stress `sigma` of the body's
//! last material update, `C0` the body's initial isotropic elasticity) and
//! `w = L max(0, lambda_max(eps_in))`. Under uniaxial tension across the crack this is the
//! familiar `w = L (eps_1 - sigma_1 / E)`; the full compliance keeps the Poisson strains of a
//! compressed element out of the opening. `L` is the crack indicator's length, by default the
//! element's own size `(6 V)^(1/3)`, so that `w` and the indicator `eps_1 / eps_r` (`eps_r = w_cr /
//! L`) speak of the same band. Unlike the indicator, `w` reads the stress: an element strained
//! elastically to `eps_r` (ahead of a crack tip, or behind a compressive front) has no opening.
//!
//! Only bodies whose material keeps a history (the microplane concrete) can open a crack; the
//! elements of the other bodies get 0.

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::{MaterialHistory, Model};
use crate::kinematics::green_lagrange_from_h;
use crate::material::microplane::{largest_principal, sym};
use crate::nodal::NodeValues;

impl Model {
    /// The crack opening `w` (m) of every element at displacement `u`, with the stresses of the
    /// bodies' last updates in `history` (see the module documentation). Each element is
    /// computed on its own, so the result does not depend on the thread count.
    pub fn crack_openings<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        u: &U,
        history: &MaterialHistory,
    ) -> Vec<f32> {
        self.crack_openings_of(u, history, 0..self.element_count())
    }

    /// [`Self::crack_openings`] of the elements of `elements` only, in order (one rank's part of
    /// a distributed run: it reads their nodes and their history only).
    pub fn crack_openings_of<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        u: &U,
        history: &MaterialHistory,
        elements: Range<usize>,
    ) -> Vec<f32> {
        let mut out = vec![0.0_f32; elements.len()];
        for (b, body) in self.bodies.iter().enumerate() {
            let Some(Some(h)) = history.bodies.get(b) else {
                continue;
            };
            let c0 = body.material.constants();
            let (young, nu) = (c0.youngs_modulus, c0.poisson_ratio);
            let part = body.elements.start.max(elements.start)..body.elements.end.min(elements.end);
            if part.is_empty() {
                continue;
            }
            out[part.start - elements.start..part.end - elements.start]
                .par_iter_mut()
                .zip(part)
                .for_each(|(w, e)| {
                    let local = e - body.elements.start;
                    let strain = green_lagrange_from_h(&self.strain_gradient(e, u));
                    let inelastic = strain
                        - elastic_strain(
                            &h.stress(local)
                                .expect("the history of the elements asked for"),
                            young,
                            nu,
                        );
                    let length = self
                        .crack_indicator
                        .length
                        .unwrap_or_else(|| self.element_size(e));
                    *w = (length * largest(&inelastic).max(0.0)) as f32;
                });
        }
        out
    }
}

/// `C0^-1 sigma = ((1 + nu) sigma - nu tr(sigma) I) / E` for the Voigt stress
/// `[xx, yy, zz, xy, yz, xz]` (Pa).
fn elastic_strain(sigma: &[f64; 6], young: f64, nu: f64) -> Matrix3<f64> {
    let [xx, yy, zz, xy, yz, xz] = *sigma;
    let s = Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    ((1.0 + nu) * s - Matrix3::from_diagonal_element(nu * (xx + yy + zz))) / young
}

/// Largest eigenvalue of a symmetric matrix (closed form, `largest_principal`).
fn largest(a: &Matrix3<f64>) -> f64 {
    largest_principal(&sym(a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_strain_inverts_hooke() {
        // Hooke's law sigma = lambda tr(eps) I + 2 mu eps for a general strain, inverted.
        let (young, nu) = (30e9, 0.18);
        let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = young / (2.0 * (1.0 + nu));
        let eps = Matrix3::new(1e-4, 2e-5, -3e-5, 2e-5, -4e-5, 5e-6, -3e-5, 5e-6, 7e-5);
        let s: Matrix3<f64> = lambda * eps.trace() * Matrix3::identity() + 2.0 * mu * eps;
        let voigt = crate::kinematics::voigt(&s);
        assert!((elastic_strain(&voigt, young, nu) - eps).norm() < 1e-18);
    }

    #[test]
    fn largest_eigenvalue_of_a_general_symmetric_matrix() {
        let a = Matrix3::new(3.0, 1.1, -0.7, 1.1, -1.0, 0.4, -0.7, 0.4, 2.0);
        let max = a.symmetric_eigenvalues().max();
        assert!((largest(&a) - max).abs() < 1e-12);
    }
}
