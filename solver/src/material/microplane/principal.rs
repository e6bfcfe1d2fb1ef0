//! Principal values of a symmetric tensor in closed form (Smith 1961): the largest principal
//! stress of the crack closure (5.97) and Mazars' equivalent strain of the tension driver.

use super::Sym;

/// Mazars' (1986) equivalent strain `sqrt(sum <e_i>^2)` over the principal values of `e`.
pub fn mazars_strain(e: &Sym) -> f64 {
    principal_values(e)
        .iter()
        .map(|v| v.max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The three eigenvalues of a symmetric tensor, largest first (trigonometric closed form; Smith
/// 1961).
pub fn principal_values(s: &Sym) -> [f64; 3] {
    match spectral_angle(s) {
        None => [(s[0] + s[1] + s[2]) / 3.0; 3],
        Some((mean, p, phi)) => {
            let largest = mean + 2.0 * p * phi.cos();
            let smallest = mean + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
            [largest, 3.0 * mean - largest - smallest, smallest]
        }
    }
}

/// Largest eigenvalue of a symmetric tensor (trigonometric closed form; Smith 1961).
pub fn largest_principal(s: &Sym) -> f64 {
    match spectral_angle(s) {
        None => (s[0] + s[1] + s[2]) / 3.0,
        Some((mean, p, phi)) => mean + 2.0 * p * phi.cos(),
    }
}

/// The largest principal stress as the crack closure `f(s_I)` (5.97) of the next update reads it
/// after rounding to `f32`: exact only where the closure varies. Where the largest diagonal term
/// is positive, `s_I` is too (it bounds `s_I` from below) and the closure is 1; where Gershgorin's
/// bound `max_i (s_ii + sum_j |s_ij|)` lies below `s_I,min` even after rounding, so does `s_I` and
/// the closure is 0. The bound is stored then (rounding is monotonic, so the closure of the stored
/// value is that of the exact one, bit for bit), and the eigenvalue's `acos` and `cos` are spent
/// only in between. The slot holds `s_I` itself, or a value on the same side of both limits.
#[inline(always)]
pub fn principal_stress_for_closure(s: &Sym, s_i_min: f64) -> f64 {
    let largest_diagonal = s[0].max(s[1]).max(s[2]);
    if largest_diagonal > 0.0 {
        return largest_diagonal;
    }
    let upper = (s[0] + s[5].abs() + s[4].abs())
        .max(s[1] + s[5].abs() + s[3].abs())
        .max(s[2] + s[4].abs() + s[3].abs());
    if ((upper as f32) as f64) < s_i_min {
        return upper;
    }
    largest_principal(s)
}

/// Smith's (1961) parametrisation of the eigenvalues, `mean + 2 p cos(phi + 2 pi k / 3)`:
/// `(mean, p, phi)`, or `None` for an isotropic tensor (all three equal to the mean).
fn spectral_angle(s: &Sym) -> Option<(f64, f64, f64)> {
    let mean = (s[0] + s[1] + s[2]) / 3.0;
    let p1 = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    let (a, b, c) = (s[0] - mean, s[1] - mean, s[2] - mean);
    let p2 = a * a + b * b + c * c + 2.0 * p1;
    if p2 <= 1e-300 {
        return None;
    }
    let p = (p2 / 6.0).sqrt();
    // det((s - mean I) / p) / 2
    let (xx, yy, zz, yz, xz, xy) = (a / p, b / p, c / p, s[3] / p, s[4] / p, s[5] / p);
    let det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    Some((mean, p, (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::microplane::discontinuity::closure;
    use crate::rng::SplitMix64;

    /// The bound the volumetric tension driver skips Mazars' eigenvalues below: the strain's norm
    /// `sqrt(E : E)`, with its 1e-9 margin, is at least the computed Mazars strain on random
    /// strains of every sign mix, including all-positive ones where the two are equal in exact
    /// arithmetic and only the margin covers the rounding of both.
    #[test]
    fn strain_norm_with_margin_bounds_the_computed_mazars_strain() {
        let mut rng = SplitMix64::new(31);
        let mut tight = 0;
        for k in 0..200_000 {
            let scale = [1e-6, 1e-4, 1e-2][k % 3];
            let centre = if k % 2 == 0 { 2.0 * scale } else { 0.0 };
            let e: Sym = std::array::from_fn(|i| {
                let shear = if i < 3 { 1.0 } else { 0.3 };
                centre * f64::from(u8::from(i < 3)) + shear * rng.uniform(-scale, scale)
            });
            let norm = crate::material::microplane::contract(&e, &e).sqrt();
            let mazars = mazars_strain(&e);
            assert!(mazars <= norm * (1.0 + 1e-9), "{e:?}: {mazars} > {norm}");
            if mazars > norm * (1.0 - 1e-12) {
                tight += 1;
            }
        }
        assert!(
            tight > 10_000,
            "only {tight} states with all principal strains positive"
        );
    }

    /// On random stress states of every sign mix and scale, the closure of the stored value is
    /// the closure of the exact largest principal stress, bit for bit, and a third of the
    /// states still take the exact eigenvalue (the test covers all three ranges).
    #[test]
    fn principal_stress_for_closure_gives_the_exact_closure() {
        let s_i_min = -2.0e5;
        let mut rng = SplitMix64::new(97);
        let mut counts = [0usize; 3];
        for k in 0..200_000 {
            let scale = [1e3, 1e5, 3e5, 1e7][k % 4];
            let centre = rng.uniform(-2.0, 0.3) * scale;
            let s: Sym = std::array::from_fn(|i| {
                if i < 3 {
                    centre + rng.uniform(-0.5, 0.5) * scale
                } else {
                    rng.uniform(-0.3, 0.3) * scale
                }
            });
            let exact = largest_principal(&s) as f32 as f64;
            let stored = principal_stress_for_closure(&s, s_i_min);
            let read = stored as f32 as f64;
            assert_eq!(
                closure(read, s_i_min).to_bits(),
                closure(exact, s_i_min).to_bits(),
                "{s:?}: stored {stored}, exact {exact}"
            );
            let range = if stored == largest_principal(&s) {
                2
            } else {
                usize::from(stored > 0.0)
            };
            counts[range] += 1;
        }
        assert!(counts.iter().all(|&c| c > 20_000), "{counts:?}");
    }

    #[test]
    fn largest_principal_matches_eigen_decomposition() {
        let s = [3.0, -1.0, 2.0, 0.4, -0.7, 1.1];
        let m = nalgebra::Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2]);
        let max = m.symmetric_eigenvalues().max();
        assert!((largest_principal(&s) - max).abs() < 1e-12);
        assert_eq!(largest_principal(&[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]), 2.0);
        let mut all = m.symmetric_eigenvalues().as_slice().to_vec();
        all.sort_by(|a, b| b.total_cmp(a));
        for (v, w) in principal_values(&s).iter().zip(&all) {
            assert!((v - w).abs() < 1e-12, "{v} against {w}");
        }
        // Uniaxial strain and uniaxial stress both give Mazars' strain e_x.
        assert_eq!(mazars_strain(&[1e-4, 0.0, 0.0, 0.0, 0.0, 0.0]), 1e-4);
        assert!((mazars_strain(&[1e-4, -2e-5, -2e-5, 0.0, 0.0, 0.0]) - 1e-4).abs() < 1e-18);
    }
}
