//! The Goldstein-Price line search on a merit `psi(t)` along a descent direction (Goldstein &
//! Price 1967; the rule of Siconos's `fc3d_nonsmooth_Newton` line search): accept `t` when
//!
//! ```text
//! psi(0) + m2 t psi'(0) <= psi(t) <= psi(0) + m1 t psi'(0),   0 < m1 < m2 < 1,
//! ```
//!
//! the right inequality (enough decrease) rejecting steps too long, the left one steps too
//! short. The bracket `[t_min, t_max]` is halved until both hold. The Newton step `t = 1` is
//! tried first and is never exceeded: a step too short at `t = 1` is taken as it is.

/// The line search's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSearch {
    /// Sufficient decrease `m1`.
    pub m1: f64,
    /// Not-too-short `m2`.
    pub m2: f64,
    /// Most trial steps.
    pub max_trials: usize,
}

impl Default for LineSearch {
    fn default() -> Self {
        Self {
            m1: 0.01,
            m2: 0.99,
            max_trials: 40,
        }
    }
}

/// The accepted step, or `None` when no trial decreased `psi` (`slope = psi'(0) < 0`). When the
/// trials run out with some decrease found but the conditions unmet, the best step is returned.
pub fn goldstein_price(
    psi0: f64,
    slope: f64,
    mut psi: impl FnMut(f64) -> f64,
    search: &LineSearch,
) -> Option<f64> {
    let (mut t_min, mut t_max) = (0.0, 1.0);
    let mut t = 1.0;
    let mut best: Option<(f64, f64)> = None;
    for _ in 0..search.max_trials {
        let value = psi(t);
        if value < psi0 && best.is_none_or(|(_, b)| value < b) {
            best = Some((t, value));
        }
        if !value.is_finite() || value > psi0 + search.m1 * t * slope {
            t_max = t;
        } else if value < psi0 + search.m2 * t * slope && t < 1.0 {
            t_min = t;
        } else {
            return Some(t);
        }
        t = 0.5 * (t_min + t_max);
    }
    best.map(|(t, _)| t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quadratic_takes_the_full_step_and_an_overshoot_is_cut() {
        // psi(t) = (1 - t)^2 / 2 * 2: Newton's step lands on the minimum.
        let s = LineSearch::default();
        assert_eq!(
            goldstein_price(1.0, -2.0, |t| (1.0 - t).powi(2), &s),
            Some(1.0)
        );
        // A direction four times too long: psi(t) = (1 - 4t)^2, slope -8.
        let t = goldstein_price(1.0, -8.0, |t| (1.0 - 4.0 * t).powi(2), &s).unwrap();
        assert!(t < 0.5 && t > 0.0, "{t}");
        // An ascent direction finds nothing.
        assert_eq!(goldstein_price(1.0, -2.0, |t| 1.0 + t, &s), None);
    }
}
