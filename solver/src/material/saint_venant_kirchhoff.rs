//! Saint-Venant-Kirchhoff hyperelasticity (thesis 2.120-2.123; Bonet & Wood 1997).

use nalgebra::Matrix3;

use super::{Elastic, Hooke, IsotropicElastic, MaterialModel};
use crate::kinematics::green_lagrange_from_h;

/// `W(E) = lambda/2 (tr E)^2 + mu tr E^2` (2.120), `S = lambda tr(E) I + 2 mu E` (2.123),
/// `P = F S`. Objective and exactly energy-conserving; not meant for large compression (the
/// thesis notes that `E -> -I/2` as `det F -> 0`).
#[derive(Debug, Clone, Copy)]
pub struct SaintVenantKirchhoff {
    c: IsotropicElastic,
    hooke: Hooke,
}

impl SaintVenantKirchhoff {
    /// The model of the elastic constants `c` (assumed valid: `IsotropicElastic::validate`).
    pub fn new(c: IsotropicElastic) -> Self {
        Self {
            c,
            hooke: c.hooke(),
        }
    }

    /// Second Piola-Kirchhoff stress `S = lambda tr(E) I + 2 mu E` (2.123).
    #[inline(always)]
    pub fn second_piola(&self, e: &Matrix3<f64>) -> Matrix3<f64> {
        self.hooke.stress(e)
    }
}

impl Elastic for SaintVenantKirchhoff {
    const NAME: &'static str = "saint_venant_kirchhoff";

    fn constants(&self) -> IsotropicElastic {
        self.c
    }

    fn model(&self) -> MaterialModel {
        MaterialModel::SaintVenantKirchhoff(self.c)
    }

    /// `P = F S` with `S = hooke(E)`.
    #[inline(always)]
    fn first_piola(&self, f: &Matrix3<f64>, h: &Matrix3<f64>) -> Matrix3<f64> {
        f * self.second_piola(&green_lagrange_from_h(h))
    }

    /// `dP = dF S + F dS`, `dS = lambda tr(dE) I + 2 mu dE`, `dE = sym(F^T dF)`.
    fn first_piola_derivative(&self, f: &Matrix3<f64>, df: &Matrix3<f64>) -> Matrix3<f64> {
        let h = f - Matrix3::identity();
        let s = self.second_piola(&green_lagrange_from_h(&h));
        let ft_df = f.transpose() * df;
        let de = 0.5 * (ft_df + ft_df.transpose());
        df * s + f * self.second_piola(&de)
    }
}
