//! The elastic path of the microplane update: an element whose planes are all on their virgin
//! branches, where every plane law equals its initial modulus to the `f32` precision of the
//! history, takes the linear map of the planes instead of 63 laws with their branches
//! (`MicroplaneConcrete::update`; verified in `tests/microplane_elastic_path.rs`).

use super::directions::contract;
use super::{
    principal_stress_for_closure, state, MicroplaneConcrete, MicroplaneParameters, Sym, UpdateInfo,
};

impl MicroplaneConcrete {
    /// The same model without the elastic path: every update takes the full path over the
    /// planes (the reference the elastic path is verified against).
    pub fn with_full_update(mut self) -> Self {
        self.elastic_path = false;
        self
    }

    /// The strain below which the elastic path is taken (see [`MicroplaneConcrete::update`]).
    pub fn elastic_limit(&self) -> f64 {
        self.elastic_limit
    }

    /// Whether every plane law is linear to `f32` precision at `strain`: the strain deviator
    /// bounds every plane's deviatoric and shear strain (`|n.dev.n|`, `|m.dev.n| <= |dev|_2 <=
    /// |dev|_F`), and a positive volumetric strain drives the relaxation `psi` through the tension
    /// law (5.91).
    #[inline(always)]
    /// A weaker element (`strength` below 1, a strength field) has its tension law linear over
    /// a proportionally smaller range.
    pub(super) fn on_elastic_path(&self, strain: &Sym, e_v: f64, strength: f64) -> bool {
        let deviator: Sym = [
            strain[0] - e_v,
            strain[1] - e_v,
            strain[2] - e_v,
            strain[3],
            strain[4],
            strain[5],
        ];
        let deviator = contract(&deviator, &deviator);
        let limit = self.elastic_limit * strength.min(1.0);
        deviator <= limit * limit && e_v <= limit
    }

    /// The update of an element whose planes are all virgin and linear: `s = D E + s_V I`, with
    /// the plane stiffness `D` and the volumetric stress `s_V` of the full update; the plane
    /// histories stay zero, and the rate factor and largest principal stress are stored as the
    /// full update stores them.
    #[inline(always)]
    pub(super) fn elastic_update(
        &self,
        header: &mut [f32],
        strain: &Sym,
        s_v: f64,
        f: f64,
    ) -> (Sym, UpdateInfo) {
        let d = &self.plane_stiffness;
        let mut sigma: Sym = std::array::from_fn(|i| {
            d[i][0] * strain[0]
                + d[i][1] * strain[1]
                + d[i][2] * strain[2]
                + d[i][3] * strain[3]
                + d[i][4] * strain[4]
                + d[i][5] * strain[5]
        });
        for s in &mut sigma[..3] {
            *s += s_v;
        }
        header[state::RATE_FACTOR] = f as f32;
        header[state::PRINCIPAL_STRESS] =
            principal_stress_for_closure(&sigma, self.parameters.s_i_min) as f32;
        self.advance_opening(header, &sigma);
        header[state::ELASTIC_UPDATES] += 1.0;
        (
            sigma,
            UpdateInfo {
                rate_factor: f,
                psi: header[state::RELAXATION] as f64,
            },
        )
    }

    /// The planes' part of the initial stiffness, `[11, 22, 33, 23, 13, 12]` with tensor shears:
    /// deviatoric and shear laws at `E_D0`, `E_T0`, homogenised (5.36), less the deviatoric trace
    /// term where the model keeps it. With `E_V0 e_V` on the normal components it is
    /// [`MicroplaneConcrete::elastic_stiffness`].
    pub(super) fn plane_stiffness(&self) -> [[f64; 6]; 6] {
        let mut c = [[0.0; 6]; 6];
        for j in 0..6 {
            let mut e = [0.0; 6];
            e[j] = 1.0;
            let e_v = (e[0] + e[1] + e[2]) / 3.0;
            let mut s = [0.0; 6];
            let mut sum_d = 0.0;
            for plane in &self.planes {
                let w = 6.0 * plane.weight;
                let s_d = self.e_d0 * (contract(&plane.nn, &e) - e_v);
                let s_m = self.e_t0 * contract(&plane.mn, &e);
                let s_k = self.e_t0 * contract(&plane.kn, &e);
                sum_d += w * s_d;
                for i in 0..6 {
                    s[i] += w * (s_d * plane.nn[i] + s_m * plane.mn[i] + s_k * plane.kn[i]);
                }
            }
            if self.parameters.deviatoric_trace_term {
                for v in &mut s[..3] {
                    *v -= sum_d / 3.0;
                }
            }
            for i in 0..6 {
                c[i][j] = s[i];
            }
        }
        c
    }
}

/// The strain up to which every plane law is linear to `f32` precision, the elastic path's limit:
/// `exp(-x^m) >= 1 - x^m` rounds to 1 in `f32` while `x^m <= 2^-25`, so the limit is
/// `2^(-25/m)` strain scales of the least of the tension (`e1`, exponent `m`), compression (`e2`,
/// `n`) and shear (`e3`, `k`) laws. The rate factor only widens the laws (`F >= 1`), and
/// compression only widens the shear law (`e3 - e4 e_V`), so the limit holds at every rate and
/// pressure.
pub(super) fn elastic_limit_of(p: &MicroplaneParameters) -> f64 {
    let linear = |scale: f64, exponent: f64| scale * (-25.0 / exponent).exp2();
    linear(p.e1, p.m)
        .min(linear(p.e2, p.n))
        .min(linear(p.e3, p.k))
}

impl MicroplaneConcrete {
    /// The initial (elastic) stiffness as a 6 x 6 matrix on `[11, 22, 33, 23, 13, 12]` with tensor
    /// shears: `sigma = C : E` homogenised from the elastic split (5.37 with undamaged moduli).
    pub fn elastic_stiffness(&self) -> [[f64; 6]; 6] {
        let mut c = [[0.0; 6]; 6];
        let unit: [Sym; 6] = std::array::from_fn(|j| {
            let mut e = [0.0; 6];
            e[j] = if j < 3 { 1.0 } else { 0.5 };
            e
        });
        for (j, e) in unit.iter().enumerate() {
            let e_v = (e[0] + e[1] + e[2]) / 3.0;
            let mut s = [0.0; 6];
            for plane in &self.planes {
                let w = 6.0 * plane.weight;
                let s_d = self.e_d0 * (contract(&plane.nn, e) - e_v);
                let s_m = self.e_t0 * contract(&plane.mn, e);
                let s_k = self.e_t0 * contract(&plane.kn, e);
                for i in 0..6 {
                    s[i] += w * (s_d * plane.nn[i] + s_m * plane.mn[i] + s_k * plane.kn[i]);
                }
            }
            for v in &mut s[..3] {
                *v += self.e_v0 * e_v;
            }
            for i in 0..6 {
                c[i][j] = s[i];
            }
        }
        c
    }
}
