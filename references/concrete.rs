//! Reference relations for plain concrete (the material cases of the catalogue, CATALOGUE
//! "Concrete material"; fib Model Code 2010, CEB-FIP Model Code 1990 and Hordijk
//! 1991). Each function states its formula and source; the harness evaluates them with the
//! targets a case states, never with numbers from a run of the model.

use super::analytic::mc2010_dynamic_increase_factor;

/// fib Model Code 2010 §5.1.8.1 (the Sargin form) for the uniaxial compressive stress-strain
/// curve, compression positive: `sigma / f_cm = (k eta - eta^2) / (1 + (k - 2) eta)` with
/// `eta = eps / eps_c1` and `k = E_ci eps_c1 / f_cm` (plasticity number), valid for
/// `0 <= eps <= eps_c,lim`. Stresses in the unit of `f_cm` and `e_ci`.
pub fn mc2010_compression_stress(eps: f64, f_cm: f64, e_ci: f64, eps_c1: f64) -> f64 {
    let eta = eps / eps_c1;
    let k = e_ci * eps_c1 / f_cm;
    f_cm * (k * eta - eta * eta) / (1.0 + (k - 2.0) * eta)
}

/// The ratio of the fib MC2010 dynamic increase factors (§5.1.11.1) at strain rates `rate` and
/// `relative_to` (1/s): how much stronger concrete is at `rate` than at `relative_to` according
/// to the code, for comparison with a model's peak-stress ratio between the same two rates.
/// Tension: `(rate / 1e-6)^0.018` up to 10 /s, `0.0062 (rate / 1e-6)^(1/3)` above; compression:
/// `(rate / 30e-6)^0.014` up to 30 /s, `0.012 (rate / 30e-6)^(1/3)` above.
pub fn mc2010_dif_ratio(rate: f64, relative_to: f64, tension: bool) -> f64 {
    mc2010_dynamic_increase_factor(rate, tension)
        / mc2010_dynamic_increase_factor(relative_to, tension)
}

/// Dynamic increase factor of CEB-FIP Model Code 1990 (CEB Bulletin 213/214, §2.1.6.4, as in the
/// research notes 3.3; the factors 1.026 and 1.016 and the constants 6.156 and 7.11 are quoted
/// from memory there, so this curve is drawn for comparison only), with `f_cm0 = 10 MPa`:
/// - compression: `(rate / 30e-6)^(1.026 alpha_s)` up to 30 /s, `gamma_s (rate / 30e-6)^(1/3)`
///   above, `alpha_s = 1 / (5 + 9 f_cm / f_cm0)`, `log10 gamma_s = 6.156 alpha_s - 2`;
/// - tension: `(rate / 3e-6)^(1.016 delta_s)` up to 30 /s, `beta_s (rate / 3e-6)^(1/3)` above,
///   `delta_s = 1 / (10 + 6 f_cm / f_cm0)`, `log10 beta_s = 7.11 delta_s - 2.33`.
///
/// `f_cm` in MPa.
pub fn cebfip1990_dynamic_increase_factor(rate: f64, tension: bool, f_cm: f64) -> f64 {
    let ratio = f_cm / 10.0;
    if tension {
        let delta = 1.0 / (10.0 + 6.0 * ratio);
        let r = rate / 3e-6;
        if rate <= 30.0 {
            r.powf(1.016 * delta)
        } else {
            10f64.powf(7.11 * delta - 2.33) * r.cbrt()
        }
    } else {
        let alpha = 1.0 / (5.0 + 9.0 * ratio);
        let r = rate / 30e-6;
        if rate <= 30.0 {
            r.powf(1.026 * alpha)
        } else {
            10f64.powf(6.156 * alpha - 2.0) * r.cbrt()
        }
    }
}

/// fib MC2010 §5.1.8.2 bilinear stress-crack opening law in tension:
/// `sigma = f_t (1 - 0.8 w / w_1)` for `w <= w_1 = G_F / f_t`, then `f_t (0.25 - 0.05 w / w_1)`
/// up to `w_c = 5 G_F / f_t`, zero beyond; the area under it is `G_F`. Units: `f_t` in a stress
/// unit, `g_f` in that unit times the unit of `w`.
pub fn mc2010_bilinear_softening(w: f64, f_t: f64, g_f: f64) -> f64 {
    let w1 = g_f / f_t;
    if w <= 0.0 {
        f_t
    } else if w <= w1 {
        f_t * (1.0 - 0.8 * w / w1)
    } else if w <= 5.0 * w1 {
        f_t * (0.25 - 0.05 * w / w1)
    } else {
        0.0
    }
}

/// Hordijk's (1991) stress-crack opening law in tension, with `w_c = 5.14 G_F / f_t`:
/// `sigma / f_t = (1 + (3 y)^3) exp(-6.93 y) - 28 y exp(-6.93)` at `y = w / w_c` on [0, 1],
/// `f_t` at `w <= 0` and zero beyond `w_c` (written out here, apart from the solver's tail).
/// Units as [`mc2010_bilinear_softening`].
pub fn hordijk_softening(w: f64, f_t: f64, g_f: f64) -> f64 {
    let y = w / (5.14 * g_f / f_t);
    if y <= 0.0 {
        return f_t;
    }
    if y >= 1.0 {
        return 0.0;
    }
    f_t * ((1.0 + 27.0 * y * y * y) * (-6.93 * y).exp() - 28.0 * y * (-6.93f64).exp()).max(0.0)
}

/// The rate factor of the microplane model, `F = 1 + c2 asinh(gamma_dot / c1)` (MICROPLANE.md
/// "Rate effect", Bažant et al. 2000), with the equivalent rate `gamma_dot = sqrt(1/2 Edot :
/// Edot)` (5.111), written here apart from the solver for the unit check of the rate law.
pub fn microplane_rate_factor(gamma_dot: f64, c1: f64, c2: f64) -> f64 {
    1.0 + c2 * (gamma_dot / c1).asinh()
}

/// The fraction of the work of hydrostatic loading to a volumetric strain `e_V = -end` that
/// unloading gives back, in closed form from the volumetric compression law (5.21)
/// `s_V = E_V0 x [(1 + x/a)^-p + (x/b)^q]` (x = -e_V) and its unloading rule: a straight line of
/// slope `C = max(E_V0, ds_V/dx)` from the turning point `X` down to zero stress (M4/M7). Loading
/// work `int_0^X s_V dx = E_V0 [a^2 ((u^(2-p) - 1)/(2-p) - (u^(1-p) - 1)/(1-p)) + X^(q+2) /
/// ((q+2) b^q)]` with `u = 1 + X/a` (`ln u` for the term whose exponent is 0); returned
/// `s_V(X)^2 / (2 C)`. The factor 3 of
/// `sigma : d eps = 3 s_V d e_V` cancels. `e_v0 = E / (1 - 2 nu)`; `[a, b, p, q]` of the law.
pub fn microplane_hydrostatic_returned_fraction(
    e_v0: f64,
    [a, b, p, q]: [f64; 4],
    end: f64,
) -> f64 {
    let x = end;
    let u = 1.0 + x / a;
    // int_1^u v^(k-1) dv, = ln u when k = 0.
    let power_integral = |k: f64| {
        if k.abs() < 1e-12 {
            u.ln()
        } else {
            (u.powf(k) - 1.0) / k
        }
    };
    let loading = e_v0
        * (a * a * (power_integral(2.0 - p) - power_integral(1.0 - p))
            + x.powf(q + 2.0) / ((q + 2.0) * b.powf(q)));
    let stress = e_v0 * x * (u.powf(-p) + (x / b).powf(q));
    let tangent = e_v0 * (u.powf(-p) * (1.0 - p * x / (a + x)) + (q + 1.0) * (x / b).powf(q));
    let slope = e_v0.max(tangent);
    stress * stress / (2.0 * slope) / loading
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sargin_curve_passes_the_research_notes_points() {
        // Research notes 5.1: E = 30000 MPa, eps_c1 = 2.3e-3 give 16.3 / 30.3 / 40.7 / 45.0 /
        // 38.2 MPa at 0.25 / 0.5 / 0.75 / 1 / 1.25 eps_c1 (0.575 / 1.15 / 1.72 / 2.30 / 2.87
        // per mille, rounded there).
        for (eta, sigma) in [
            (0.25, 16.3),
            (0.5, 30.3),
            (0.75, 40.7),
            (1.0, 45.0),
            (1.25, 38.2),
        ] {
            let eps = eta * 2.3e-3;
            let s = mc2010_compression_stress(eps, 45.0, 30000.0, 2.3e-3);
            assert!((s - sigma).abs() < 0.06, "{eps}: {s} vs {sigma}");
        }
        // The initial slope is E_ci.
        let e = mc2010_compression_stress(1e-9, 45.0, 30000.0, 2.3e-3) / 1e-9;
        assert!((e - 30000.0).abs() < 1e-3 * 30000.0, "{e}");
    }

    #[test]
    fn dif_ratios_match_the_research_notes_table() {
        // Research notes section 2: MC2010 tension 1.042 at 1e-5 and 1.282 at 1 /s.
        assert!((mc2010_dif_ratio(1.0, 1e-5, true) - 1.282 / 1.042).abs() < 2e-3);
        assert_eq!(mc2010_dif_ratio(1e-3, 1e-3, false), 1.0);
        // CEB-FIP 1990 at f_cm = 45 MPa: tension 1.173 and compression 1.082 at 1e-3 /s,
        // tension 1.510 and compression 1.332 at 10 /s.
        for (rate, tension, expected) in [
            (1e-3, true, 1.173),
            (1e-3, false, 1.082),
            (10.0, true, 1.510),
            (10.0, false, 1.332),
        ] {
            let dif = cebfip1990_dynamic_increase_factor(rate, tension, 45.0);
            assert!((dif - expected).abs() < 2e-3, "{rate} {tension}: {dif}");
        }
    }

    #[test]
    fn bilinear_softening_encloses_the_fracture_energy() {
        let (f_t, g_f) = (2.7, 0.10);
        let n = 200_000;
        let w_end = 6.0 * g_f / f_t;
        let dw = w_end / n as f64;
        let area: f64 = (0..n)
            .map(|i| {
                let (a, b) = (i as f64 * dw, (i + 1) as f64 * dw);
                0.5 * (mc2010_bilinear_softening(a, f_t, g_f)
                    + mc2010_bilinear_softening(b, f_t, g_f))
                    * dw
            })
            .sum();
        assert!((area - g_f).abs() < 1e-6, "{area}");
    }

    #[test]
    fn rate_factor_is_one_at_rest_and_logarithmic_when_fast() {
        assert_eq!(microplane_rate_factor(0.0, 4e-6, 0.022), 1.0);
        let fast = microplane_rate_factor(1.0, 4e-6, 0.022);
        assert!((fast - (1.0 + 0.022 * (2.0 / 4e-6f64).ln())).abs() < 1e-12);
    }
}
