//! The energy the planes dissipate in one update, counted only when the dilatancy reads it.
//!
//! The growth of the dilatant strain is capped by the energy the plane branches dissipate by
//! virgin loading (MICROPLANE "Dilatancy", [`super::MicroplaneConcrete::admissible_dilatancy`]),
//! `sum_p 6 w_p sum_b f_b (W_b - (s^2 / 2C)|_before^after)` over the branches `b` of plane `p`
//! that loaded on their virgin law ([`Branch::dissipated_since`], four divisions each; `f_b` the
//! cyclic shear damage, 1 for the normal branch). Counting it in every update doubled the cost of
//! a virgin update, yet the cap reads it only where the dilatant strain grows into volumetric
//! compression. So the plane loop records each virgin step (its branch before and after, in `f64`
//! as the count used them) and the sum is formed afterwards, where it is read: the same
//! operations in the same order, so the same bits (`tests/microplane_dissipation_count.rs`).

use std::mem::MaybeUninit;

use super::cyclic::{Branch, UnloadingRule};
use super::directions::MAX_PLANES;

/// Which law a branch loads on: it gives the initial modulus and the peak of the unloading rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Law {
    /// The deviatoric tension law.
    Tension,
    /// The deviatoric compression law.
    Compression,
    /// Either shear law.
    Shear,
}

/// One branch that loaded on its virgin law in this update.
#[derive(Debug, Clone, Copy)]
struct VirginStep {
    plane: usize,
    law: Law,
    before: Branch,
    after: Branch,
    /// The factor on the branch's dissipation: the cyclic shear damage, 1 for a normal branch.
    factor: f64,
}

/// The virgin steps of one update, in the order of the plane loop (plane by plane; within a
/// plane the normal branch, then `M`, then `K`).
pub(super) struct VirginSteps {
    steps: [MaybeUninit<VirginStep>; 3 * MAX_PLANES],
    len: usize,
}

impl VirginSteps {
    /// No steps yet. (The array is left uninitialised: zeroing its 5 KB cost more than the
    /// divisions it saves in a near-elastic update.)
    #[inline(always)]
    pub fn new() -> Self {
        Self {
            steps: [const { MaybeUninit::uninit() }; 3 * MAX_PLANES],
            len: 0,
        }
    }

    /// Records that the branch of `law` on `plane` went from `before` to `after` on its virgin
    /// law, its dissipation to be multiplied by `factor`.
    #[inline(always)]
    pub fn push(&mut self, plane: usize, law: Law, before: Branch, after: Branch, factor: f64) {
        // At most three branches per plane and `MAX_PLANES` planes: the plane loop cannot fill it.
        self.steps[self.len].write(VirginStep {
            plane,
            law,
            before,
            after,
            factor,
        });
        self.len += 1;
    }

    /// Records the virgin step `(before, after, damage)` of a shear branch of `plane`; with
    /// `eager` (the law's initial modulus and peak, and the unloading rule) also returns its
    /// dissipation times the damage, the reference count's term, and 0 without.
    #[inline(always)]
    pub fn push_shear(
        &mut self,
        plane: usize,
        (before, after, damage): (Branch, Branch, f64),
        eager: Option<(f64, (f64, f64), &UnloadingRule)>,
    ) -> f64 {
        self.push(plane, Law::Shear, before, after, damage);
        match eager {
            Some((c0, peak, rule)) => damage * after.dissipated_since(&before, c0, peak, rule),
            None => 0.0,
        }
    }

    /// The energy dissipated per unit volume, `sum_p weight(p) sum_b f_b D_b`, summed as the
    /// plane loop summed it: per plane from zero, then weighted into the total (a plane without
    /// steps added `weight * 0.0`, which changes no total). `modulus(law)` gives the initial
    /// modulus and the peak `(e_p, s_p)` of the law's unloading rule.
    pub fn dissipation(
        &self,
        weight: impl Fn(usize) -> f64,
        modulus: impl Fn(Law) -> (f64, (f64, f64)),
        rule: &UnloadingRule,
    ) -> f64 {
        // SAFETY: `push` wrote the first `len` entries.
        let steps = unsafe {
            std::slice::from_raw_parts(self.steps.as_ptr().cast::<VirginStep>(), self.len)
        };
        let mut total = 0.0;
        for group in steps.chunk_by(|a, b| a.plane == b.plane) {
            let mut dissipated = 0.0;
            for step in group {
                let (c0, peak) = modulus(step.law);
                dissipated +=
                    step.factor * step.after.dissipated_since(&step.before, c0, peak, rule);
            }
            total += weight(group[0].plane) * dissipated;
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lazy sum equals the sum formed step by step in the plane loop's order, bit for bit.
    #[test]
    fn sum_equals_the_running_count() {
        let rule = UnloadingRule {
            alpha: 0.5,
            beta: 0.5,
        };
        let modulus = |law: Law| match law {
            Law::Tension => (3.0e10, (1.0e-4, 2.5e6)),
            Law::Compression => (3.0e10, (2.0e-3, 4.0e7)),
            Law::Shear => (2.5e10, (1.5e-3, 1.0e7)),
        };
        let weight = |p: usize| 6.0 * (0.01 + 0.001 * p as f64);
        let mut steps = VirginSteps::new();
        let mut running = 0.0;
        for p in 0..21 {
            let mut dissipated = 0.0;
            for (j, law) in [Law::Tension, Law::Shear, Law::Shear]
                .into_iter()
                .enumerate()
            {
                if (p + j) % 3 == 0 {
                    continue;
                }
                let (c0, _) = modulus(law);
                let e0 = 1e-5 * (1 + p + j) as f64;
                let before = Branch {
                    reached: e0,
                    stress_reached: 0.9 * c0 * e0,
                };
                let after = Branch {
                    reached: 1.7 * e0,
                    stress_reached: 0.8 * c0 * 1.7 * e0,
                };
                let factor = if law == Law::Shear { 0.7 } else { 1.0 };
                let (c0, peak) = modulus(law);
                let d = after.dissipated_since(&before, c0, peak, &rule);
                dissipated += if law == Law::Shear { factor * d } else { d };
                steps.push(p, law, before, after, factor);
            }
            running += weight(p) * dissipated;
        }
        let lazy = steps.dissipation(weight, modulus, &rule);
        assert_eq!(lazy.to_bits(), running.to_bits());
        assert!(lazy > 0.0);
    }
}
