//! Linear elasticity in the co-rotated frame: the elastic limit of the microplane model.

use nalgebra::Matrix3;

use super::{Elastic, Hooke, IsotropicElastic, MaterialModel};
use crate::kinematics::cofactor;

/// Hooke's law between the back-rotated Cauchy stress `s` and the Green-Lagrange strain `E`,
/// `s = lambda tr(E) I + 2 mu E`, with `sigma = R s R^T` (FORMULATION 1; MICROPLANE.md gives the
/// microplane model the same measures, so this is its elastic limit).
///
/// For an isotropic law the rotation need not be computed: `R E R^T = (F F^T - I)/2 = e_b` and
/// `tr E = tr e_b`, so `sigma = lambda tr(e_b) I + 2 mu e_b` and `P = sigma cof F`. The model is
/// objective to round-off at any rotation, costs no polar decomposition, and coincides with
/// Saint-Venant-Kirchhoff to first order in the strain. It is Cauchy-elastic, not
/// hyperelastic: on large closed strain cycles its work is zero only to second order, so use
/// Saint-Venant-Kirchhoff where exact energy conservation at large strain matters.
#[derive(Debug, Clone, Copy)]
pub struct LinearElastic {
    c: IsotropicElastic,
    hooke: Hooke,
}

impl LinearElastic {
    /// The model of the elastic constants `c` (assumed valid: `IsotropicElastic::validate`).
    pub fn new(c: IsotropicElastic) -> Self {
        Self {
            c,
            hooke: c.hooke(),
        }
    }

    /// `e_b = (F F^T - I)/2 = (H + H^T + H H^T)/2`.
    #[inline(always)]
    fn spatial_strain(h: &Matrix3<f64>) -> Matrix3<f64> {
        0.5 * (h + h.transpose() + h * h.transpose())
    }
}

impl Elastic for LinearElastic {
    const NAME: &'static str = "linear_elastic";

    fn constants(&self) -> IsotropicElastic {
        self.c
    }

    fn model(&self) -> MaterialModel {
        MaterialModel::LinearElastic(self.c)
    }

    /// `P = sigma cof F` with `sigma = hooke(e_b)`.
    #[inline(always)]
    fn first_piola(&self, f: &Matrix3<f64>, h: &Matrix3<f64>) -> Matrix3<f64> {
        self.hooke.stress(&Self::spatial_strain(h)) * cofactor(f)
    }

    /// `dP = d(sigma) cof F + sigma d(cof F)`, with `d sigma = hooke(sym(dF F^T))` and the
    /// derivative of the cofactor taken column by column from `cof F = [f1 x f2 | ...]`.
    fn first_piola_derivative(&self, f: &Matrix3<f64>, df: &Matrix3<f64>) -> Matrix3<f64> {
        let h = f - Matrix3::identity();
        let sigma = self.hooke.stress(&Self::spatial_strain(&h));
        let df_ft = df * f.transpose();
        let dsigma = self.hooke.stress(&(0.5 * (df_ft + df_ft.transpose())));
        let (c0, c1, c2) = (f.column(0), f.column(1), f.column(2));
        let (d0, d1, d2) = (df.column(0), df.column(1), df.column(2));
        let dcof = Matrix3::from_columns(&[
            d1.cross(&c2) + c1.cross(&d2),
            d2.cross(&c0) + c2.cross(&d0),
            d0.cross(&c1) + c0.cross(&d1),
        ]);
        dsigma * cofactor(f) + sigma * dcof
    }
}
