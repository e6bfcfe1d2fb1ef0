//! The volumetric strain `e_V` the microplane laws see at finite strain.
//!
//! MICROPLANE.md takes `e_V = tr E / 3` of the Green-Lagrange strain `E` (thesis (5.11), (5.33)).
//! At the strains of a penetration that measure no longer follows the volume: under the nail an
//! element crushed to `J = det F = 0.02` with principal stretches `0.012, 1.29, 1.43` has
//! `tr E / 3 = +0.116`, a volumetric *tension*, so the volumetric law softens, the deviatoric
//! and shear laws relax with it, and nothing resists the element's collapse
//! (`cargo run --release -p impact-solver --example remesh_diagnose` on the nail case, issue 21).
//! A stretch `l` adds `(l^2 - 1) / 2` to `tr E`: a large stretch in one direction outweighs any
//! crushing in another, whose contribution is bounded by `-1/2`.
//!
//! [`VolumetricStrain::VolumeRatio`] measures `e_V` by the volume instead: the Green-Lagrange
//! strain of the dilatational part `J^(1/3) I` of `F` (Flory's split `F = J^(1/3) F_iso`),
//! `e_V = (J^(2/3) - 1) / 2`. It equals `tr E / 3` for every pure dilatation, to first order in
//! the strain for any deformation (so the small-strain calibration is unchanged), is negative
//! whenever the volume shrinks, and tends to `-1/2` as `J -> 0`, where the compaction law
//! `s_V ~ E_V0 e_V |e_V / b|^q` (5.22) stiffens by two orders of magnitude. The deviatoric strains
//! keep the Green-Lagrange deviator: the strain handed to the laws is
//! `dev E + e_V I` (`e_D = e_N - e_V = n . dev E . n` as before).

use serde::{Deserialize, Serialize};

use super::directions::Sym;

/// How the volumetric strain `e_V` is measured (see the module).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumetricStrain {
    /// `e_V = tr E / 3` (MICROPLANE.md, thesis (5.11)): blind to a loss of volume accompanied by
    /// a large stretch.
    #[default]
    GreenLagrangeTrace,
    /// `e_V = (J^(2/3) - 1) / 2` with `J^2 = det(I + 2E)`: negative whenever the volume shrinks.
    VolumeRatio,
}

/// `det(I + 2E) - 1 = J^2 - 1` from the Green-Lagrange strain `E` (tensor shears,
/// `[11, 22, 33, 23, 13, 12]`), expanded as `2 I1 + 4 I2 + 8 I3` so that small strains keep
/// their digits.
pub fn volume_ratio_squared_minus_one(e: &Sym) -> f64 {
    let [xx, yy, zz, yz, xz, xy] = *e;
    let i1 = xx + yy + zz;
    let i2 = xx * yy + yy * zz + zz * xx - yz * yz - xz * xz - xy * xy;
    let i3 = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    2.0 * i1 + 4.0 * i2 + 8.0 * i3
}

/// `e_V = (J^(2/3) - 1) / 2` of the Green-Lagrange strain `e`, in a form that keeps its digits at
/// small strain: with `d = J^2 - 1` (expanded, [`volume_ratio_squared_minus_one`]) and
/// `r = (1 + d)^(1/3) = J^(2/3)`, `r - 1 = d / (r^2 + r + 1)`, so the small difference comes from
/// `d` itself and only the denominator (about 3, `cube_root_denominator`) carries the rounding:
/// a relative error of a few `1e-16` at any strain (against the `log1p`/`expm1` form in the
/// tests). `None` where `J^2 <= 0` (no volume: an inverted or collapsed element).
pub fn dilatational_strain(e: &Sym) -> Option<f64> {
    let d = volume_ratio_squared_minus_one(e);
    (d > -1.0).then(|| 0.5 * d / cube_root_denominator(d))
}

/// `|d|` up to which [`cube_root_denominator`] sums its series: the first term left out,
/// `c_9 d^9` with `c_9 = 0.0203`, is then below `1.2e-18`, 4e-19 of the sum.
const SERIES_RANGE: f64 = 1.0 / 64.0;

/// `r^2 + r + 1` with `r = (1 + d)^(1/3)`: for `|d| <= 1/64`, the strains of every element not
/// crushed, the binomial series `(1 + d)^(1/3) + (1 + d)^(2/3) + 1 = sum c_k d^k` to `d^8`
/// (`c_k` the sums of the binomial coefficients of 1/3 and 2/3, exact fractions), summed in
/// powers of `d^2` from the smallest term; beyond, `cbrt`. The series costs a few products where
/// `cbrt` (correctly rounded, in software) took 3 % of a drop test's samples (perf).
#[inline(always)]
fn cube_root_denominator(d: f64) -> f64 {
    if d.abs() <= SERIES_RANGE {
        let d2 = d * d;
        let pair = |even: f64, odd: f64| even + odd * d;
        let high = pair(-245.0 / 6561.0, 194.0 / 6561.0) + d2 * (-1429.0 / 59049.0);
        let high = pair(-17.0 / 243.0, 4.0 / 81.0) + d2 * high;
        let high = pair(-2.0 / 9.0, 1.0 / 9.0) + d2 * high;
        pair(3.0, 1.0) + d2 * high
    } else {
        let r = (1.0 + d).cbrt();
        r * r + r + 1.0
    }
}

impl VolumetricStrain {
    /// The strain handed to the microplane laws: `e` itself, or `dev e + e_V I` with the
    /// dilatational `e_V` ([`dilatational_strain`]); a strain with no volume keeps `e` (the
    /// element that has it stops the run anyway).
    pub fn measured(self, e: &Sym) -> Sym {
        match self {
            VolumetricStrain::GreenLagrangeTrace => *e,
            VolumetricStrain::VolumeRatio => match dilatational_strain(e) {
                Some(e_v) => {
                    let shift = e_v - (e[0] + e[1] + e[2]) / 3.0;
                    let mut out = *e;
                    for v in out.iter_mut().take(3) {
                        *v += shift;
                    }
                    out
                }
                None => *e,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Green-Lagrange strain of `F = diag(l)`.
    fn stretched(l: [f64; 3]) -> Sym {
        [
            0.5 * (l[0] * l[0] - 1.0),
            0.5 * (l[1] * l[1] - 1.0),
            0.5 * (l[2] * l[2] - 1.0),
            0.0,
            0.0,
            0.0,
        ]
    }

    #[test]
    fn a_pure_dilatation_keeps_the_trace() {
        for l in [0.3, 0.9, 0.999, 1.0 + 1e-7, 1.2, 2.5] {
            let e = stretched([l; 3]);
            let measured = VolumetricStrain::VolumeRatio.measured(&e);
            for k in 0..6 {
                assert!(
                    (measured[k] - e[k]).abs() <= 1e-14 * e[0].abs().max(1e-300),
                    "stretch {l}: component {k} {} against {}",
                    measured[k],
                    e[k]
                );
            }
        }
    }

    #[test]
    fn a_crushed_and_stretched_point_is_in_volumetric_compression() {
        // The element under the nail: J = 0.0227, tr E / 3 = +0.116.
        let e = stretched([0.012, 1.286, 1.429]);
        assert!((e[0] + e[1] + e[2]) / 3.0 > 0.1);
        let j: f64 = 0.012 * 1.286 * 1.429;
        let e_v = dilatational_strain(&e).unwrap();
        assert!((e_v - 0.5 * (j.powf(2.0 / 3.0) - 1.0)).abs() < 1e-14);
        assert!(e_v < -0.45);
        // The deviator is kept.
        let m = VolumetricStrain::VolumeRatio.measured(&e);
        let mean = (m[0] + m[1] + m[2]) / 3.0;
        assert!((mean - e_v).abs() < 1e-15);
        let old_mean = (e[0] + e[1] + e[2]) / 3.0;
        for k in 0..3 {
            assert!(((m[k] - mean) - (e[k] - old_mean)).abs() < 1e-15);
        }
    }

    #[test]
    fn small_strains_agree_to_second_order_and_keep_their_digits() {
        // A general small strain with shears: the two measures differ by O(|E|^2).
        let base: Sym = [1.0, -0.4, 0.3, 0.2, -0.5, 0.7];
        for scale in [1e-3, 1e-5, 1e-8] {
            let e = base.map(|v| v * scale);
            let e_v = dilatational_strain(&e).unwrap();
            let trace = (e[0] + e[1] + e[2]) / 3.0;
            assert!(
                (e_v - trace).abs() <= 10.0 * scale * scale,
                "scale {scale}: {e_v:e} against {trace:e}"
            );
        }
        // Rigid rotations have E = 0 and J = 1 exactly.
        assert_eq!(dilatational_strain(&[0.0; 6]), Some(0.0));
    }

    #[test]
    fn the_expansion_is_the_determinant() {
        let e: Sym = [0.3, -0.2, 0.1, 0.05, -0.15, 0.25];
        let m = nalgebra::Matrix3::new(
            1.0 + 2.0 * e[0],
            2.0 * e[5],
            2.0 * e[4],
            2.0 * e[5],
            1.0 + 2.0 * e[1],
            2.0 * e[3],
            2.0 * e[4],
            2.0 * e[3],
            1.0 + 2.0 * e[2],
        );
        assert!((volume_ratio_squared_minus_one(&e) - (m.determinant() - 1.0)).abs() < 1e-14);
    }

    /// The series and `cbrt` forms against `0.5 expm1(log1p(d) / 3)`, which keeps its digits by
    /// construction, from `J^2 - 1 = 1e-12` to crushing (`J^2 = 1e-6`) and stretching
    /// (`J^2 = 8`), and on both sides of the series' range.
    #[test]
    fn the_cube_root_form_keeps_its_digits() {
        let mut worst: f64 = 0.0;
        for k in 0..2000 {
            let magnitude = 10f64.powf(-12.0 + 12.0 * k as f64 / 1999.0);
            let edges = [
                SERIES_RANGE * (1.0 - magnitude),
                SERIES_RANGE * (1.0 + magnitude),
            ];
            for d in [magnitude, -magnitude.min(1.0 - 1e-6), 7.0 * magnitude]
                .into_iter()
                .chain(edges)
                .chain(edges.map(|d| -d))
            {
                // A pure dilatation with J^2 = 1 + d: E = ((1 + d)^(1/3) - 1) / 2 I.
                let reference = 0.5 * (d.ln_1p() / 3.0).exp_m1();
                let e = [reference, reference, reference, 0.0, 0.0, 0.0];
                let d_measured = volume_ratio_squared_minus_one(&e);
                let exact = 0.5 * (d_measured.ln_1p() / 3.0).exp_m1();
                let e_v = dilatational_strain(&e).unwrap();
                worst = worst.max(((e_v - exact) / exact).abs());
            }
        }
        assert!(worst < 1e-15, "largest relative difference {worst:e}");
    }
}
