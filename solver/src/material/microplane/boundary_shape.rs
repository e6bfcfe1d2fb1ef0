//! The shape of a plane's tensile boundary `F(y)` over its crack strain `y` (`tension_boundary`):
//! M4 and M7's exponential, or the bilinear softening of fib Model Code 2010.
//!
//! Both are written with the boundary's strength `f0` and strain scale `eps_f`, and both enclose
//! `int F dy = f0 eps_f`, so the crack band (`TensionBoundary::scaled`, Bažant & Oh 1983) scales
//! `eps_f` alike and keeps `G_F`.

use serde::{Deserialize, Serialize};

/// The shape of the boundary.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryShape {
    /// `F = f0 exp(-y / eps_f)` (M4, M7; Caner & Bažant 2013).
    #[default]
    Exponential,
    /// fib Model Code 2010, 5.1.5.2 (eq. 5.1-9, the crack opening `w` replaced by the crack strain
    /// `y` and `w1 = G_F / f_t` by `eps_f`): `F = f0 (1 - 0.8 y / eps_f)` up to `eps_f`, then
    /// `f0 (0.25 - 0.05 y / eps_f)` down to zero at `5 eps_f`. Its area is `f0 eps_f`, as
    /// MC2010's is `f_t w1 = G_F`.
    Mc2010,
}

impl BoundaryShape {
    /// Whether it is the default (exponential) shape, which the files do not write.
    pub fn is_exponential(&self) -> bool {
        *self == Self::Exponential
    }

    /// The largest fall `-F'(y)` of the boundary over `f0 / eps_f`: 1 for the exponential (at
    /// `y = 0`), 0.8 for MC2010's first branch. A plane of stiffness `E` snaps back unless
    /// `E > slope f0 / eps_f`.
    pub fn steepest_fall(&self) -> f64 {
        match self {
            Self::Exponential => 1.0,
            Self::Mc2010 => 0.8,
        }
    }
}

/// MC2010's bilinear boundary and its slope at the crack strain `y`, strength `f0`, strain scale
/// `eps_f` (see [`BoundaryShape::Mc2010`]).
pub(super) fn mc2010(f0: f64, eps_f: f64, y: f64) -> (f64, f64) {
    let x = y / eps_f;
    if x <= 1.0 {
        (f0 * (1.0 - 0.8 * x), -0.8 * f0 / eps_f)
    } else if x <= 5.0 {
        (f0 * (0.25 - 0.05 * x), -0.05 * f0 / eps_f)
    } else {
        (0.0, 0.0)
    }
}

/// The crack strain `y` where a plane of stiffness `e` driven to `kappa > f0` meets MC2010's
/// boundary: the root of `kappa - e y - F(y)`, which falls from `kappa - f0 > 0` (no snap-back,
/// `e > 0.8 f0 / eps_f`), branch by branch.
pub(super) fn mc2010_crack_strain(kappa: f64, e: f64, f0: f64, eps_f: f64) -> f64 {
    let first = (kappa - f0) / (e - 0.8 * f0 / eps_f);
    if first <= eps_f {
        return first;
    }
    let second = (kappa - 0.25 * f0) / (e - 0.05 * f0 / eps_f);
    if second <= 5.0 * eps_f {
        return second;
    }
    kappa / e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mc2010_follows_the_model_code() {
        let (f0, eps_f) = (3e6, 1e-3);
        // MC2010 5.1.5.2: 0.2 f_t at w1, zero at 5 w1, continuous at w1.
        assert!((mc2010(f0, eps_f, eps_f).0 - 0.2 * f0).abs() < 1e-6);
        assert!((mc2010(f0, eps_f, 1.000001 * eps_f).0 - 0.2 * f0).abs() < 1.0);
        assert!(mc2010(f0, eps_f, 5.0 * eps_f).0.abs() < 1e-6);
        // The area is f0 eps_f (G_F = f_t w1).
        let n = 100_000;
        let area: f64 = (0..n)
            .map(|i| mc2010(f0, eps_f, 6.0 * eps_f * (i as f64 + 0.5) / n as f64).0)
            .sum::<f64>()
            * 6.0
            * eps_f
            / n as f64;
        assert!((area / (f0 * eps_f) - 1.0).abs() < 1e-6, "{area}");
    }

    #[test]
    fn the_crack_strain_puts_the_plane_on_the_boundary() {
        let (f0, eps_f, e) = (3e6, 1e-3, 30e9);
        for kappa in [3.01e6, 4e6, 3e7, 6e7, 2e8, 1e9] {
            let y = mc2010_crack_strain(kappa, e, f0, eps_f);
            let on_boundary = mc2010(f0, eps_f, y).0;
            assert!(
                (kappa - e * y - on_boundary).abs() < 1e-6 * f0,
                "kappa {kappa}: {} against {on_boundary}",
                kappa - e * y
            );
        }
    }
}
