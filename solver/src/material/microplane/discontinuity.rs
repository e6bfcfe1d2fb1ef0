//! The discontinuity (relaxation) functions of the relaxed kinematic constraint (thesis 5.5.3),
//! with the sign typos fixed as in MICROPLANE.md.

/// Crack closure `f(s_I)` (5.97): 1 for a positive largest principal stress, 0 below the small
/// negative limit `s_I,min`, and `1 - sin(pi/2 |s_I / s_I,min|)` between.
#[inline(always)]
pub fn closure(s_i: f64, s_i_min: f64) -> f64 {
    if s_i > 0.0 {
        1.0
    } else if s_i < s_i_min {
        0.0
    } else {
        1.0 - (std::f64::consts::FRAC_PI_2 * (s_i / s_i_min).abs()).sin()
    }
}

/// Crack opening `o(s_I)`, the mirror image of the closure [`closure`] about `s_I = 0`: 0 for a
/// largest principal stress at or below zero, 1 from `|s_I,min|` up, `sin(pi/2 s_I / |s_I,min|)`
/// between (docs/MICROPLANE.md "Tension under lateral compression"). It tells a crack opened by a
/// tensile stress from the lateral expansion of compressed concrete, which shows the same
/// positive principal strain without any tensile stress.
#[inline(always)]
pub fn opening(s_i: f64, s_i_min: f64) -> f64 {
    if s_i <= 0.0 {
        0.0
    } else if s_i >= -s_i_min {
        1.0
    } else {
        (std::f64::consts::FRAC_PI_2 * (s_i / s_i_min).abs()).sin()
    }
}

/// `psi = exp(-|f(s_I) e_V / e1|^m)` (5.91, 5.96, 5.99) for `argument = f(s_I) <e_V>`: the secant
/// factor of the volumetric tension law at that strain, crack band included, so that the relaxed
/// deviatoric modulus stays proportional to the volumetric one (5.84) in every element.
///
/// The argument is the positive part of `e_V`: under volumetric compression nothing relaxes. (Read
/// literally, (5.99) would relax shear whenever `s_I > s_I,min`, which under uniaxial compression,
/// where `s_I = 0`, removes all shear stiffness and with it the compressive strength.)
#[inline(always)]
pub fn relaxation(argument: f64, e1: f64, law: &super::laws::ExponentialLaw, band: f64) -> f64 {
    if argument <= 0.0 {
        1.0
    } else {
        law.stress(argument, e1, 1.0, band) / argument
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closure_is_continuous_between_its_limits() {
        let s_min = -2.0;
        assert_eq!(closure(1.0, s_min), 1.0);
        assert_eq!(closure(0.0, s_min), 1.0);
        assert!((closure(-1.0, s_min) - (1.0 - (std::f64::consts::FRAC_PI_4).sin())).abs() < 1e-15);
        assert!(closure(-2.0, s_min).abs() < 1e-15);
        assert_eq!(closure(-3.0, s_min), 0.0);
    }

    #[test]
    fn opening_mirrors_closure() {
        let s_min = -2.0;
        for s in [-3.0, -2.0, -1.3, -0.5, 0.0] {
            assert!(
                (opening(-s, s_min) - (1.0 - closure(s, s_min))).abs() < 1e-15,
                "{s}"
            );
        }
        assert_eq!(opening(0.0, s_min), 0.0);
        assert_eq!(opening(5.0, s_min), 1.0);
    }
}
