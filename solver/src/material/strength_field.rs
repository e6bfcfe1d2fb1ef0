//! A seeded random field of tensile strength over a body: the scatter of real concrete, which
//! breaks the symmetry of a symmetric specimen the way a test does, instead of a mirror plane
//! or round-off choosing the side a crack takes.
//!
//! The field is lognormal, `s(x) = exp(sigma_L g(x) - sigma_L^2 / 2)` with
//! `sigma_L^2 = ln(1 + c^2)`, so that its mean is 1 and its coefficient of variation `c`
//! (Bažant & Pang 2007 and Vořechovský 2007 model concrete strength as a weakest-link or
//! lognormal field). `g` is a standard Gaussian field with the squared-exponential correlation
//! `rho(r) = exp(-r^2 / l^2)` of correlation length `l`, drawn by the randomised spectral method
//! (Shinozuka & Deodatis 1991, 1996): `g(x) = sqrt(2 / N) sum_i cos(k_i . x + phi_i)` with the
//! wave vectors `k_i` drawn from the correlation's spectral density, a normal distribution of
//! variance `2 / l^2` per component (then `E[cos(k . r)] = exp(-r^2 / l^2)`), and the phases
//! `phi_i` uniform on `[0, 2 pi)`. With `N` = [`StrengthField::MODES`] the sum is Gaussian to the
//! central limit's precision; every draw comes from [`SplitMix64`] seeded by `seed`, so the
//! field is the same function of position on every machine, thread and rank count, and a
//! remeshed element takes the field's value at its own centroid.

use serde::{Deserialize, Serialize};

use crate::rng::SplitMix64;

/// The strength field of a body as a scene writes it:
/// `strength_field: { coefficient_of_variation: 0.1, correlation_length: 0.05, seed: 1 }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthFieldSpec {
    /// Coefficient of variation `c` of the tensile strength (standard deviation over mean),
    /// in `(0, 1]`.
    pub coefficient_of_variation: f64,
    /// Correlation length `l` of `rho(r) = exp(-r^2 / l^2)` (m), positive.
    pub correlation_length: f64,
    /// Seed of the draws: the same seed, the same field.
    pub seed: u64,
}

/// What is wrong with a [`StrengthFieldSpec`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StrengthFieldError {
    /// The coefficient of variation is not in `(0, 1]`.
    #[error(
        "strength_field.coefficient_of_variation must be in (0, 1] (0.05 to 0.2 for concrete), \
         got {0}"
    )]
    Variation(f64),
    /// The correlation length is not positive and finite.
    #[error(
        "strength_field.correlation_length must be positive and finite (m; about the aggregate \
         size to a few element sizes), got {0}"
    )]
    Length(f64),
}

impl StrengthFieldSpec {
    /// Checks the ranges; the error names the key and its admissible range.
    pub fn validate(&self) -> Result<(), StrengthFieldError> {
        let c = self.coefficient_of_variation;
        if !(c > 0.0 && c <= 1.0) {
            return Err(StrengthFieldError::Variation(c));
        }
        let l = self.correlation_length;
        if !(l > 0.0 && l.is_finite()) {
            return Err(StrengthFieldError::Length(l));
        }
        Ok(())
    }
}

/// The field drawn from a [`StrengthFieldSpec`], ready to be evaluated anywhere.
#[derive(Debug, Clone, PartialEq)]
pub struct StrengthField {
    /// `sigma_L` of the lognormal.
    log_deviation: f64,
    /// Wave vectors `k_i` (1/m) and phases `phi_i`.
    waves: Vec<([f64; 3], f64)>,
}

impl StrengthField {
    /// Number of spectral modes `N` of the Gaussian field.
    pub const MODES: usize = 512;

    /// Draws the field of `spec` (validated).
    pub fn new(spec: &StrengthFieldSpec) -> Result<Self, StrengthFieldError> {
        spec.validate()?;
        let mut rng = SplitMix64::new(spec.seed);
        let deviation = 2f64.sqrt() / spec.correlation_length;
        let waves = (0..Self::MODES)
            .map(|_| {
                let k = [0; 3].map(|_| deviation * standard_normal(&mut rng));
                (k, rng.uniform(0.0, std::f64::consts::TAU))
            })
            .collect();
        let c = spec.coefficient_of_variation;
        Ok(Self {
            log_deviation: (1.0 + c * c).ln().sqrt(),
            waves,
        })
    }

    /// The standard Gaussian field `g(x)` at `x` (m).
    pub fn gaussian(&self, x: [f64; 3]) -> f64 {
        let sum: f64 = self
            .waves
            .iter()
            .map(|(k, phi)| (k[0] * x[0] + k[1] * x[1] + k[2] * x[2] + phi).cos())
            .sum();
        sum * (2.0 / self.waves.len() as f64).sqrt()
    }

    /// The strength factor `s(x) = exp(sigma_L g(x) - sigma_L^2 / 2)` at `x` (m): the tensile
    /// strength there over the material's.
    pub fn factor(&self, x: [f64; 3]) -> f64 {
        let sigma = self.log_deviation;
        (sigma * self.gaussian(x) - 0.5 * sigma * sigma).exp()
    }
}

/// A standard normal draw (Box-Muller; the second variate of the pair is dropped, which keeps
/// the sequence simple at no cost that matters for a field drawn once).
fn standard_normal(rng: &mut SplitMix64) -> f64 {
    let u = 1.0 - rng.next_f64(); // (0, 1]: ln u is finite
    let v = rng.next_f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(c: f64, l: f64, seed: u64) -> StrengthFieldSpec {
        StrengthFieldSpec {
            coefficient_of_variation: c,
            correlation_length: l,
            seed,
        }
    }

    /// Points on a grid much wider than the correlation length, so that the sample statistics
    /// are those of the field.
    fn grid(step: f64, n: usize) -> Vec<[f64; 3]> {
        let mut points = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    points.push([i as f64 * step, j as f64 * step, k as f64 * step]);
                }
            }
        }
        points
    }

    #[test]
    fn factor_has_unit_mean_and_the_coefficient_of_variation_asked() {
        // Averaged over seeds and a 20 l wide grid: each point is a sample of the lognormal.
        let (c, l) = (0.15, 0.05);
        let points = grid(2.0 * l, 10);
        let mut values = Vec::new();
        for seed in 0..8 {
            let field = StrengthField::new(&spec(c, l, seed)).unwrap();
            values.extend(points.iter().map(|&x| field.factor(x)));
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        assert!((mean - 1.0).abs() < 0.01, "mean {mean}");
        let cov = variance.sqrt() / mean;
        assert!((cov - c).abs() < 0.01, "coefficient of variation {cov}");
        assert!(values.iter().all(|&v| v > 0.0));
    }

    #[test]
    fn correlation_follows_the_squared_exponential() {
        // The sample correlation of g at lags of 0.5 l, l and 2 l along x, over seeds and points.
        let l = 0.1;
        for (lag, expected) in [
            (0.5, (-0.25f64).exp()),
            (1.0, (-1.0f64).exp()),
            (2.0, 0.0183),
        ] {
            let (mut sum_xy, mut sum_xx, mut sum_yy) = (0.0, 0.0, 0.0);
            for seed in 0..16 {
                let field = StrengthField::new(&spec(0.1, l, seed)).unwrap();
                for x in grid(3.0 * l, 6) {
                    let a = field.gaussian(x);
                    let b = field.gaussian([x[0] + lag * l, x[1], x[2]]);
                    sum_xy += a * b;
                    sum_xx += a * a;
                    sum_yy += b * b;
                }
            }
            let rho = sum_xy / (sum_xx * sum_yy).sqrt();
            assert!(
                (rho - expected).abs() < 0.05,
                "lag {lag} l: correlation {rho}, expected {expected}"
            );
        }
    }

    #[test]
    fn the_seed_fixes_the_field_and_another_seed_changes_it() {
        let a = StrengthField::new(&spec(0.1, 0.05, 7)).unwrap();
        let b = StrengthField::new(&spec(0.1, 0.05, 7)).unwrap();
        let c = StrengthField::new(&spec(0.1, 0.05, 8)).unwrap();
        let x = [0.31, 0.12, 0.07];
        assert_eq!(a.factor(x).to_bits(), b.factor(x).to_bits());
        assert_ne!(a.factor(x), c.factor(x));
    }

    #[test]
    fn out_of_range_specs_are_refused_with_the_key() {
        let e = StrengthField::new(&spec(0.0, 0.05, 1)).unwrap_err();
        assert!(e.to_string().contains("coefficient_of_variation"));
        let e = StrengthField::new(&spec(0.1, -1.0, 1)).unwrap_err();
        assert!(e.to_string().contains("correlation_length"));
        assert!(StrengthField::new(&spec(f64::NAN, 0.05, 1)).is_err());
    }
}
