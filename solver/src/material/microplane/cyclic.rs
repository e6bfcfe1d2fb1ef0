//! Loading, unloading and reloading of one microplane stress component (thesis 5.6).
//!
//! Each sign of each component (a *branch*) remembers the largest strain it reached on its virgin
//! law and the stress there. Beyond that strain the component loads on the virgin law (5.100);
//! below it, it unloads and reloads on a straight line through that point whose slope is the
//! unloading modulus (5.102), down to zero stress (an open crack carries nothing until the strain
//! changes sign). The line lies under the virgin law, so a closed strain cycle of one component
//! never gives energy back.

/// The history of one branch: largest strain magnitude reached on the virgin law and its stress.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Branch {
    /// Largest strain magnitude reached on the virgin law, the turning point (dimensionless).
    pub reached: f64,
    /// Stress magnitude of the virgin law at `reached` (Pa).
    pub stress_reached: f64,
}

/// The constants of the unloading rule (5.102, 5.103).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnloadingRule {
    /// Weight of the initial modulus `C0` in the unloading modulus (5.102), in `[0, 1]`: 1
    /// unloads elastically, 0 along the line to the residual strain.
    pub alpha: f64,
    /// Growth of the residual strain `e*` with the strain beyond the peak (5.103),
    /// dimensionless.
    pub beta: f64,
}

impl UnloadingRule {
    /// Unloading modulus from the branch's turning point `(e, s)` (5.102):
    /// `C = alpha C0 + (1 - alpha) s / (e - e*)`, with the residual strain `e* = 0` before the
    /// peak `(e_p, s_p)` of the virgin law and `e* = (e_p - s_p / C0) + beta (e - e_p)` beyond it
    /// (5.103). The thesis prints `e* = e_p` before the peak, which would aim the unloading line at
    /// a point right of the turning point; unloading to the origin is what its Fig. 5.11 draws.
    /// The modulus is kept between the secant `s / e` and `C0`.
    #[inline(always)]
    pub fn modulus(&self, branch: &Branch, c0: f64, peak: (f64, f64)) -> f64 {
        let (e, s) = (branch.reached, branch.stress_reached);
        if e <= 0.0 {
            return c0;
        }
        let (e_p, s_p) = peak;
        if e <= e_p {
            // Before the peak the line aims at the origin: `towards` is the secant, which the
            // virgin law keeps at or below C0, so the weighted modulus lies between the secant
            // and C0 and only the f32 rounding of the turning point can lift it above C0. This
            // is the common case of a vibrating structure (one division, plain comparisons).
            let modulus = self.alpha * c0 + (1.0 - self.alpha) * (s / e);
            return if modulus < c0 { modulus } else { c0 };
        }
        let residual = ((e_p - s_p / c0).max(0.0) + self.beta * (e - e_p)).min(e);
        let towards = if e > residual { s / (e - residual) } else { c0 };
        (self.alpha * c0 + (1.0 - self.alpha) * towards)
            .max(s / e)
            .min(c0)
    }
}

impl Branch {
    /// Reads the branch from its two history values `[reached, stress_reached]`.
    #[inline(always)]
    pub fn load(history: &[f32]) -> Self {
        Self {
            reached: history[0] as f64,
            stress_reached: history[1] as f64,
        }
    }

    /// Writes the branch back to its two history values (as `f32`).
    #[inline(always)]
    pub fn store(&self, history: &mut [f32]) {
        history[0] = self.reached as f32;
        history[1] = self.stress_reached as f32;
    }

    /// Stress magnitude at strain magnitude `x >= 0`, advancing the history.
    ///
    /// On virgin loading the secant never rises above the one already reached: damage does not
    /// heal when the virgin law moves up (a higher rate factor, more confinement).
    #[inline(always)]
    pub fn stress(
        &mut self,
        x: f64,
        c0: f64,
        peak: (f64, f64),
        rule: &UnloadingRule,
        envelope: impl Fn(f64) -> f64,
    ) -> f64 {
        match self.unloading(x, c0, peak, rule) {
            Some(s) => s,
            None => self.virgin(x, envelope(x)),
        }
    }

    /// Below the turning point, the stress on the unloading-reloading line (5.102); at or beyond
    /// it `None`: the caller evaluates the virgin law and hands it to [`Branch::virgin`]. (The
    /// split form of [`Branch::stress`] for hot loops, where the law's closure was not inlined.)
    #[inline(always)]
    pub fn unloading(
        &self,
        x: f64,
        c0: f64,
        peak: (f64, f64),
        rule: &UnloadingRule,
    ) -> Option<f64> {
        if x >= self.reached {
            None
        } else {
            let c = rule.modulus(self, c0, peak);
            let s = self.stress_reached - c * (self.reached - x);
            Some(if s > 0.0 { s } else { 0.0 })
        }
    }

    /// Virgin loading to `x` where the law gives `envelope`, capped at the secant reached:
    /// the new turning point.
    #[inline(always)]
    pub fn virgin(&mut self, x: f64, envelope: f64) -> f64 {
        let mut s = envelope;
        // s <= (stress_reached / reached) x, compared without a division: it binds only where
        // the virgin law has moved up since the turning point.
        if self.reached > 0.0 && s * self.reached > self.stress_reached * x {
            s = self.stress_reached * x / self.reached;
        }
        self.reached = x;
        self.stress_reached = s;
        s
    }

    /// Whether the branch has lost at least 1 % of its secant stiffness.
    #[inline(always)]
    pub fn damaged(&self, c0: f64) -> bool {
        self.reached > 0.0 && self.stress_reached < 0.99 * c0 * self.reached
    }

    /// Energy dissipated by virgin loading from `before` to `self`: the work done (trapezoidal)
    /// less the growth of the energy an unloading would give back, `s^2 / (2 C)`.
    pub fn dissipated_since(
        &self,
        before: &Branch,
        c0: f64,
        peak: (f64, f64),
        rule: &UnloadingRule,
    ) -> f64 {
        let work =
            0.5 * (self.stress_reached + before.stress_reached) * (self.reached - before.reached);
        let recoverable =
            |b: &Branch| b.stress_reached * b.stress_reached / (2.0 * rule.modulus(b, c0, peak));
        work - (recoverable(self) - recoverable(before))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A softening law `s = x exp(-x)`, loaded past its peak, unloaded, reloaded: the unloading
    /// line has the modulus of (5.102) and the cycle dissipates.
    #[test]
    fn unloading_follows_the_rule_and_cycles_dissipate() {
        let law = |x: f64| x * (-x).exp();
        let peak = (1.0, (-1.0f64).exp());
        let rule = UnloadingRule {
            alpha: 0.5,
            beta: 0.5,
        };
        let mut b = Branch::default();
        let mut x_prev = 0.0;
        let mut s_prev = 0.0;
        let mut work = 0.0;
        let path: Vec<f64> = (0..=300)
            .map(|i| i as f64 * 0.01)
            .chain((0..=300).rev().map(|i| i as f64 * 0.01))
            .chain((0..=400).map(|i| i as f64 * 0.01))
            .collect();
        for &x in &path {
            let s = b.stress(x, 1.0, peak, &rule, law);
            work += 0.5 * (s + s_prev) * (x - x_prev);
            assert!(s <= law(x) + 1e-15, "above the virgin law at {x}");
            x_prev = x;
            s_prev = s;
        }
        assert!(work > 0.0);
        // The unloading modulus at e = 3: residual e* = (1 - 1/e) + 0.5 (3 - 1).
        let turning = Branch {
            reached: 3.0,
            stress_reached: law(3.0),
        };
        let residual = (1.0 - (-1.0f64).exp()) + 1.0;
        let expected = 0.5 + 0.5 * law(3.0) / (3.0 - residual);
        assert!((rule.modulus(&turning, 1.0, peak) - expected).abs() < 1e-15);
    }
}
