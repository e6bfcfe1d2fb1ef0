//! Analytic reference solutions. Each function states its formula and source; the catalogue
//! names them under `reference: { analytic: ... }` and the harness evaluates them with the
//! material constants of the case's scene, so no reference number is pasted into a case.

use impact_solver::material::IsotropicElastic;
use nalgebra::Matrix3;

/// Dilatational (P) wave speed `c_d = sqrt((lambda + 2 mu) / rho)` (e.g. Achenbach 1973, (2.27)).
pub fn dilatational_wave_speed(c: &IsotropicElastic) -> f64 {
    c.dilatational_wave_speed()
}

/// Shear wave speed `c_s = sqrt(mu / rho)`.
pub fn shear_wave_speed(c: &IsotropicElastic) -> f64 {
    (c.mu() / c.density).sqrt()
}

/// Rayleigh wave speed: the root `x = (c_R / c_s)^2` in `(0, 1)` of Rayleigh's equation
/// `x^3 - 8 x^2 + (24 - 16 k) x - 16 (1 - k) = 0` with `k = (c_s / c_d)^2`
/// (Rayleigh 1885; Achenbach 1973, (5.56)), found by bisection to round-off.
pub fn rayleigh_wave_speed(c: &IsotropicElastic) -> f64 {
    let cs = shear_wave_speed(c);
    let k = (cs / dilatational_wave_speed(c)).powi(2);
    let f = |x: f64| x * x * x - 8.0 * x * x + (24.0 - 16.0 * k) * x - 16.0 * (1.0 - k);
    // f(0) = -16 (1 - k) < 0 and f(1) = 1 > 0: exactly one root in between for -1 < nu < 0.5.
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    cs * (0.5 * (lo + hi)).sqrt()
}

/// Axial Cauchy stress behind a plane dilatational wave driven by a boundary velocity `v`
/// into the body: `sigma_xx = -rho c_d v` (compression; one-dimensional wave theory, Kolsky 1963).
pub fn plane_wave_stress(c: &IsotropicElastic, velocity: f64) -> f64 {
    -c.density * dilatational_wave_speed(c) * velocity
}

/// Saint-Venant-Kirchhoff under uniaxial stress at axial stretch `l` (from (2.123) with
/// `S22 = S33 = 0`): `E11 = (l^2 - 1)/2`, `E22 = E33 = -nu E11`, `S11 = E E11`,
/// `P11 = l S11 = E l (l^2 - 1)/2`, and the Cauchy stress `sigma11 = P11 l / J = P11 / l_t^2`
/// with the lateral stretch `l_t = sqrt(1 + 2 E22)`.
pub struct SvkUniaxial {
    /// Axial Green-Lagrange strain `E11 = (l^2 - 1) / 2` (dimensionless).
    pub e11: f64,
    /// Lateral Green-Lagrange strain `E22 = E33 = -nu E11` (dimensionless).
    pub e22: f64,
    /// Axial second Piola-Kirchhoff stress `S11 = E E11` (Pa).
    pub s11: f64,
    /// Axial first Piola-Kirchhoff (nominal) stress `P11 = l S11` (Pa).
    pub p11: f64,
    /// Axial Cauchy (true) stress `sigma11 = P11 / l_t^2` (Pa).
    pub sigma11: f64,
}

/// The uniaxial-stress state of Saint-Venant-Kirchhoff with constants `c` at axial stretch
/// `stretch` (see [`SvkUniaxial`]).
pub fn svk_uniaxial(c: &IsotropicElastic, stretch: f64) -> SvkUniaxial {
    let e11 = 0.5 * (stretch * stretch - 1.0);
    let e22 = -c.poisson_ratio * e11;
    let p11 = c.youngs_modulus * stretch * e11;
    SvkUniaxial {
        e11,
        e22,
        s11: c.youngs_modulus * e11,
        p11,
        sigma11: p11 / (1.0 + 2.0 * e22),
    }
}

/// Saint-Venant-Kirchhoff in uniaxial strain `F = diag(1, 1, l)` (laterally confined): from
/// (2.123), `E33 = (l^2 - 1)/2`, `S33 = (lambda + 2 mu) E33`, and the Cauchy stress
/// `sigma33 = l^2 S33 / J = l S33`.
pub fn svk_uniaxial_strain_stress(c: &IsotropicElastic, stretch: f64) -> f64 {
    stretch * (c.lambda() + 2.0 * c.mu()) * 0.5 * (stretch * stretch - 1.0)
}

/// Cauchy stress of Saint-Venant-Kirchhoff at a homogeneous deformation gradient `F`:
/// `S = lambda tr(E) I + 2 mu E`, `E = (F^T F - I)/2` (2.123), `sigma = F S F^T / det F`.
/// The exact stress of the static and dynamic patch tests.
pub fn svk_cauchy(c: &IsotropicElastic, f: &Matrix3<f64>) -> Matrix3<f64> {
    let e = 0.5 * (f.transpose() * f - Matrix3::identity());
    let s = Matrix3::identity() * (c.lambda() * e.trace()) + e * (2.0 * c.mu());
    f * s * f.transpose() / f.determinant()
}

/// Cauchy stress of the co-rotated linear elastic model at `F`, from its definition
/// `sigma = R (lambda tr(E) I + 2 mu E) R^T` with `R` the rotation of `F = R U` taken from an
/// SVD (`F = W S V^T`, `R = W V^T`), independently of the solver's own formula.
pub fn corotated_cauchy(c: &IsotropicElastic, f: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = f.svd(true, true);
    let r = svd.u.expect("u requested") * svd.v_t.expect("v_t requested");
    let e = 0.5 * (f.transpose() * f - Matrix3::identity());
    let s = Matrix3::identity() * (c.lambda() * e.trace()) + e * (2.0 * c.mu());
    r * s * r.transpose()
}

/// First bending frequency of a cantilever (Euler-Bernoulli, clamped-free):
/// `f_1 = (beta_1 L)^2 / (2 pi L^2) sqrt(E I / (rho A))` with `beta_1 L = 1.875104`
/// (e.g. Rao, *Mechanical Vibrations*, Table 8.4). For a rectangular section of depth `h`
/// bending about its width, `I / A = h^2 / 12`.
pub fn cantilever_first_frequency(c: &IsotropicElastic, length: f64, depth: f64) -> f64 {
    let beta_l: f64 = 1.875_104_068_711_961;
    beta_l * beta_l / (2.0 * std::f64::consts::PI * length * length)
        * (c.youngs_modulus * depth * depth / 12.0 / c.density).sqrt()
}

/// Head-on impact of two identical elastic spheres (Hertz 1882; Johnson, *Contact Mechanics*
/// 1985, §11.4): `E* = E / (2 (1 - nu^2))`, `R* = R/2`, `m* = m/2` with `m` one sphere's mass,
/// approach `delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)` at relative speed `v`,
/// `F_max = 4/3 E* sqrt(R*) delta_max^(3/2)`, contact radius `a = sqrt(R* delta_max)` and
/// duration `2.943 delta_max / v` (2.9432 = 2 * 1.4716, the quasi-static Hertz integral).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzImpact {
    /// Largest approach of the sphere centres `delta_max` (m).
    pub max_approach: f64,
    /// Largest contact force `F_max` (N).
    pub max_force: f64,
    /// Contact radius `a` at the largest approach (m).
    pub contact_radius: f64,
    /// Duration of the contact (s).
    pub duration: f64,
}

/// The Hertz impact of two identical spheres of constants `c`, radius `radius` (m) and mass
/// `mass` (kg) each, approaching at `relative_speed` (m/s); see [`HertzImpact`].
pub fn hertz_impact(
    c: &IsotropicElastic,
    radius: f64,
    mass: f64,
    relative_speed: f64,
) -> HertzImpact {
    let e_star = c.youngs_modulus / (2.0 * (1.0 - c.poisson_ratio * c.poisson_ratio));
    let (r_star, m_star, v) = (0.5 * radius, 0.5 * mass, relative_speed);
    let delta = (15.0 * m_star * v * v / (16.0 * e_star * r_star.sqrt())).powf(0.4);
    HertzImpact {
        max_approach: delta,
        max_force: 4.0 / 3.0 * e_star * r_star.sqrt() * delta.powf(1.5),
        contact_radius: (r_star * delta).sqrt(),
        duration: 2.943 * delta / v,
    }
}

/// Peak load of a simply supported beam under a mid-span point load when the extreme fibre
/// reaches the modulus of rupture `f_r`: `P = 2 f_r b h^2 / (3 S)` (Euler-Bernoulli: `M = P S/4`,
/// `sigma = 6 M / (b h^2)`), for width `b`, depth `h` and span `S`.
pub fn modulus_of_rupture_load(f_r: f64, width: f64, depth: f64, span: f64) -> f64 {
    2.0 * f_r * width * depth * depth / (3.0 * span)
}

/// Dynamic increase factor of concrete strength, fib Model Code 2010 §5.1.11.1 (fib 2013):
/// tension `(rate / 1e-6)^0.018` up to 10 /s, `0.0062 (rate / 1e-6)^(1/3)` above;
/// compression `(rate / 30e-6)^0.014` up to 30 /s, `0.012 (rate / 30e-6)^(1/3)` above
/// (both valid to 300 /s).
pub fn mc2010_dynamic_increase_factor(rate: f64, tension: bool) -> f64 {
    if tension {
        let r = rate / 1e-6;
        if rate <= 10.0 {
            r.powf(0.018)
        } else {
            0.0062 * r.cbrt()
        }
    } else {
        let r = rate / 30e-6;
        if rate <= 30.0 {
            r.powf(0.014)
        } else {
            0.012 * r.cbrt()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: IsotropicElastic = IsotropicElastic {
        density: 2300.0,
        youngs_modulus: 30e9,
        poisson_ratio: 0.18,
    };

    #[test]
    fn rayleigh_speed_matches_the_viktorov_approximation() {
        // Viktorov's fit c_R / c_s = (0.862 + 1.14 nu) / (1 + nu), good to about 0.5 %.
        let approx =
            shear_wave_speed(&C) * (0.862 + 1.14 * C.poisson_ratio) / (1.0 + C.poisson_ratio);
        let exact = rayleigh_wave_speed(&C);
        assert!((exact - approx).abs() / exact < 5e-3, "{exact} vs {approx}");
        // For nu = 0.25 the root is known in closed form: x = 2 - 2/sqrt(3).
        let c = IsotropicElastic {
            poisson_ratio: 0.25,
            ..C
        };
        let expected = shear_wave_speed(&c) * (2.0 - 2.0 / 3f64.sqrt()).sqrt();
        assert!((rayleigh_wave_speed(&c) - expected).abs() / expected < 1e-14);
    }

    #[test]
    fn hertz_peak_holds_the_initial_kinetic_energy() {
        // Independent check: the Hertz work 8/15 E* sqrt(R*) delta^(5/2) equals 1/2 m* v^2.
        let c = IsotropicElastic {
            density: 1200.0,
            youngs_modulus: 1e9,
            poisson_ratio: 0.3,
        };
        let r: f64 = 0.05;
        let m = c.density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let h = hertz_impact(&c, r, m, 10.0);
        let e_star = c.youngs_modulus / (2.0 * (1.0 - 0.09));
        let work = 8.0 / 15.0 * e_star * (r / 2.0).sqrt() * h.max_approach.powf(2.5);
        assert!((work - 0.5 * (m / 2.0) * 100.0).abs() < 1e-12 * work);
        // The catalogue's example: contact radius about 8 mm.
        assert!(
            (h.contact_radius - 8.0e-3).abs() < 0.2e-3,
            "{}",
            h.contact_radius
        );
    }

    #[test]
    fn mc2010_branches_meet_at_the_switch_rates() {
        // Tension: 0.0062 (1e7)^(1/3) = 1.3356 against (1e7)^0.018 = 1.3366, continuous to 0.1 %.
        // Compression: the code's rounded 0.012 leaves a step of 1.1 % at 30 /s
        // (1.2134 below, 1.2000 above); the formula is the code's, so the step stays.
        for (tension, switch, gap) in [(true, 10.0, 1e-3), (false, 30.0, 1.2e-2)] {
            let below = mc2010_dynamic_increase_factor(switch, tension);
            let above = mc2010_dynamic_increase_factor(switch * (1.0 + 1e-9), tension);
            assert!(
                (below - above).abs() < gap * below,
                "{tension}: {below} vs {above}"
            );
        }
        assert!((mc2010_dynamic_increase_factor(1e-6, true) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn modulus_of_rupture_load_of_the_thesis_beam() {
        // CATALOGUE: f_r from 1.0 to 1.3 ft (2.7 MPa) gives about 70 to 90 kN.
        let p = modulus_of_rupture_load(2.7e6, 0.3, 0.6, 2.8);
        assert!((p - 69.4e3).abs() < 0.1e3, "{p}");
    }

    #[test]
    fn svk_uniaxial_is_consistent_with_the_cauchy_formula() {
        let s = svk_uniaxial(&C, 1.3);
        let l2 = (1.0 + 2.0 * s.e22).sqrt();
        let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.3, l2, l2));
        let sigma = svk_cauchy(&C, &f);
        assert!(sigma[(1, 1)].abs() < 1e-6 * s.s11);
        // sigma11 = P11 F11 / J = P11 * 1.3 / (1.3 l2^2).
        assert!((sigma[(0, 0)] - s.p11 / (l2 * l2)).abs() < 1e-9 * s.s11);
    }
}
