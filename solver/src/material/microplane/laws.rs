//! Virgin microplane laws (thesis 5.17-5.23, secant form) and the crack-band scaling of their
//! softening branches (Bažant & Oh 1983).
//!
//! Every softening law here has the shape `s = C0 x exp(-|x / e_s|^m)`: a secant modulus that
//! decays from `C0`. In units of the strain scale (`x = e / e_s`) it is `g(x) = x exp(-x^m)`, with
//! its peak at `x_p = m^(-1/m)`; the constants of `g` that the crack band needs (areas before and
//! after the peak) are computed once per exponent.

/// `g(x) = x exp(-x^m)`, the dimensionless virgin law.
#[inline(always)]
fn shape(x: f64, exponent: f64) -> f64 {
    x * (-power(x, exponent)).exp()
}

/// `x^m` for `x >= 0`, with the common integer exponents written out (they are most of the
/// calibrated values and `powf` is the most expensive call of the update).
#[inline(always)]
pub fn power(x: f64, m: f64) -> f64 {
    if m == 1.0 {
        x
    } else if m == 2.0 {
        x * x
    } else if x == 0.0 {
        0.0
    } else {
        x.powf(m)
    }
}

/// An exponential softening law `s = C0 x exp(-x^m)`, `x = e / e_s`, with its crack-band data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExponentialLaw {
    pub exponent: f64,
    /// Peak of `g`: `x_p = m^(-1/m)`, `g_p = x_p exp(-1/m)`.
    pub x_peak: f64,
    pub g_peak: f64,
    /// `int_0^x_p g dx` and `int_x_p^inf g dx`.
    pub area_before_peak: f64,
    pub area_after_peak: f64,
}

impl ExponentialLaw {
    pub fn new(exponent: f64) -> Self {
        let x_peak = exponent.powf(-1.0 / exponent);
        let g_peak = shape(x_peak, exponent);
        // Simpson's rule on a fine grid; g decays like exp(-x^m), so 40 strain scales cover it
        // to round-off for every admissible exponent (`exp(-40)` at the end).
        let simpson = |a: f64, b: f64| {
            let n = 20_000;
            let h = (b - a) / n as f64;
            let mut s = shape(a, exponent) + shape(b, exponent);
            for i in 1..n {
                let w = if i % 2 == 1 { 4.0 } else { 2.0 };
                s += w * shape(a + i as f64 * h, exponent);
            }
            s * h / 3.0
        };
        let tail = x_peak + 40f64.powf(1.0 / exponent);
        let area_before_peak = simpson(0.0, x_peak);
        let area_after_peak = simpson(x_peak, tail);
        Self {
            exponent,
            x_peak,
            g_peak,
            area_before_peak,
            area_after_peak,
        }
    }

    /// Stress of the law at strain `e >= 0` with strain scale `scale`, modulus `c0` and crack-band
    /// factor `band` (see [`ExponentialLaw::band_factor`]).
    ///
    /// Beyond the peak the law is evaluated at `x_p + band (x - x_p)`: the element of size `h`
    /// softens `band` times faster than the element of size `h_ref` the law was calibrated at, so
    /// `h * (energy per unit volume)` stays the same (Bažant & Oh 1983). (MICROPLANE.md writes the
    /// map as `e* = e_p + (e - e_p) h_ref / h`, which is this map solved for the element's strain:
    /// the law's strain `x` is reached at the element strain `e*`.)
    #[inline(always)]
    pub fn stress(&self, e: f64, scale: f64, c0: f64, band: f64) -> f64 {
        let mut x = e / scale;
        if x > self.x_peak {
            x = self.x_peak + band * (x - self.x_peak);
        }
        c0 * scale * shape(x, self.exponent)
    }

    /// Strain and stress at the peak for a strain scale and modulus.
    pub fn peak(&self, scale: f64, c0: f64) -> (f64, f64) {
        (self.x_peak * scale, self.g_peak * scale * c0)
    }

    /// Crack-band factor for an element of size `h` when the law was calibrated at `h_ref`:
    /// `band` such that `h (A_pre + A_post / band) = h_ref (A_pre + A_post)`, i.e. the energy of the
    /// law per unit crack area is the same for every size. `None` when no factor can achieve it or
    /// the scaled law would snap back (a softening slope steeper than the initial modulus).
    pub fn band_factor(&self, h: f64, h_ref: f64) -> Option<f64> {
        let (pre, post) = (self.area_before_peak, self.area_after_peak);
        let denominator = h_ref / h * (pre + post) - pre;
        if !(denominator > 0.0) {
            return None;
        }
        Some(post / denominator)
    }

    /// The largest element size for which [`ExponentialLaw::band_factor`] exists:
    /// `h_ref (A_pre + A_post) / A_pre`.
    pub fn largest_element(&self, h_ref: f64) -> f64 {
        let (pre, post) = (self.area_before_peak, self.area_after_peak);
        h_ref * (pre + post) / pre
    }
}

/// Volumetric compression (5.21): `s_V = E_V0 e_V [(1 + |e_V/a|)^-p + |e_V/b|^q]`, no damage:
/// compaction first, then stiffening.
#[inline(always)]
pub fn volumetric_compression(e_v: f64, e_v0: f64, a: f64, b: f64, p: f64, q: f64) -> f64 {
    let x = e_v.abs();
    e_v0 * e_v * ((1.0 + x / a).powf(-p) + power(x / b, q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_law_constants_match_closed_forms() {
        // m = 1: g = x e^-x, peak at 1, areas 1 - 2/e and 2/e.
        let law = ExponentialLaw::new(1.0);
        assert!((law.x_peak - 1.0).abs() < 1e-15);
        assert!((law.area_before_peak - (1.0 - 2.0 / std::f64::consts::E)).abs() < 1e-10);
        assert!((law.area_after_peak - 2.0 / std::f64::consts::E).abs() < 1e-10);
        // m = 2: total area Gamma(1)/2 = 1/2.
        let law = ExponentialLaw::new(2.0);
        assert!((law.area_before_peak + law.area_after_peak - 0.5).abs() < 1e-10);
    }

    /// The crack-band map keeps `h * energy` equal to the reference size's.
    #[test]
    fn band_factor_conserves_energy_per_crack_area() {
        let law = ExponentialLaw::new(1.5);
        let h_ref = 0.1;
        for h in [0.025, 0.05, 0.1, 0.95 * law.largest_element(h_ref)] {
            let band = law.band_factor(h, h_ref).expect("admissible size");
            let energy = |band: f64| {
                let n = 400_000;
                let top = 60.0;
                let dx = top / n as f64;
                (0..n)
                    .map(|i| law.stress((i as f64 + 0.5) * dx, 1.0, 1.0, band) * dx)
                    .sum::<f64>()
            };
            let ratio = h * energy(band) / (h_ref * energy(1.0));
            assert!((ratio - 1.0).abs() < 1e-4, "h = {h}: ratio {ratio}");
        }
        assert!(law
            .band_factor(1.1 * law.largest_element(h_ref), h_ref)
            .is_none());
        assert!(law
            .band_factor(0.9 * law.largest_element(h_ref), h_ref)
            .is_some());
    }
}
