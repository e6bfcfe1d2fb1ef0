//! The shear components of a microplane: the laws with their two branches and the cyclic damage
//! (thesis 5.20, 5.23, 5.104), and the Coulomb slider of crack friction (MICROPLANE "Crack
//! friction"). Called from the plane loop of [`MicroplaneConcrete::update`].

use super::cyclic::Branch;
use super::MicroplaneConcrete;

/// What the shear laws of one update share: the strain scale `e5` of the law at this update's
/// rate and volumetric strain (5.23), the law's peak `(e_p, s_p)`, the element's crack-band
/// factor, and the energy of monotonic loading to full softening that scales the cyclic damage
/// (5.104).
#[derive(Debug, Clone, Copy)]
pub(super) struct ShearScale {
    pub(super) e5: f64,
    pub(super) peak: (f64, f64),
    pub(super) band: f64,
    pub(super) monotonic_energy: f64,
}

impl MicroplaneConcrete {
    /// The shear stress `[s_m, s_k]` of a plane with crack friction (MICROPLANE "Crack
    /// friction"). Until the plane cracks (`cracked` false: no shear law past its peak, `psi`
    /// still 1) the laws' stress `s`, with the slider's slip set so that it carries `s` too.
    /// After, the Coulomb slider at the plane's shear strain `e` (without `psi`),
    /// `t = E_T0 (e - slip)` with `|t| <= bound` (the slip advancing along `t` where the trial
    /// passes the bound: M4's shear boundary acts on the shear vector), where it carries more
    /// than `s` and does not oppose it; `s` otherwise.
    #[inline(always)]
    pub(super) fn crack_friction(
        &self,
        s: [f64; 2],
        e: [f64; 2],
        slip: &mut [f32],
        bound: f64,
        cracked: bool,
    ) -> (f64, f64) {
        if !cracked {
            for i in 0..2 {
                slip[i] = (e[i] - s[i] / self.e_t0) as f32;
            }
            return (s[0], s[1]);
        }
        let mut t = [
            self.e_t0 * (e[0] - slip[0] as f64),
            self.e_t0 * (e[1] - slip[1] as f64),
        ];
        // Squared norms compare: `hypot` guards against an overflow these stresses cannot
        // reach, and it took 8 % of the nail run's time (perf).
        let norm_squared = t[0] * t[0] + t[1] * t[1];
        if norm_squared > bound * bound {
            let scale = bound / norm_squared.sqrt();
            for i in 0..2 {
                t[i] *= scale;
                slip[i] = (e[i] - t[i] / self.e_t0) as f32;
            }
        }
        let carried = |v: [f64; 2]| v[0] * v[0] + v[1] * v[1];
        if t[0] * s[0] + t[1] * s[1] >= 0.0 && carried(t) > carried(s) {
            (t[0], t[1])
        } else {
            (s[0], s[1])
        }
    }

    /// One shear component (5.20, 5.23) with its two branches and the cyclic damage (5.104):
    /// `history` holds `[e+, s+, e-, s-, Lambda]`. Returns the stress and, where the branch
    /// loaded on its virgin law, the branch before and after with the cyclic damage its
    /// dissipation is to be multiplied by.
    #[inline(always)]
    pub(super) fn shear_stress(
        &self,
        e: f64,
        history: &mut [f32],
        scale: &ShearScale,
    ) -> (f64, Option<(Branch, Branch, f64)>) {
        let ShearScale {
            e5,
            peak,
            band,
            monotonic_energy,
        } = *scale;
        let (own, other) = if e >= 0.0 { (0, 2) } else { (2, 0) };
        let mut branch = Branch::load(&history[own..own + 2]);
        let before = branch;
        let law = &self.shear;
        let c0 = self.e_t0;
        let (inverse_e5, amplitude) = (1.0 / e5, c0 * e5);
        let x = e.abs();
        let s = match branch.unloading(x, c0, peak, &self.rule) {
            Some(s) => s,
            None => branch.virgin(x, law.scaled_stress(x * inverse_e5, amplitude, band)),
        };
        branch.store(&mut history[own..own + 2]);
        let mut damage = 1.0;
        if self.parameters.shear_cyclic_damage {
            // Energy dissipated while loading in the direction opposite to earlier damage
            // (Eligehausen, Popov & Bertero 1983): it weakens both directions.
            let opposite = Branch::load(&history[other..other + 2]);
            if opposite.damaged(c0) && branch.reached > before.reached {
                let dissipated = branch.dissipated_since(&before, c0, peak, &self.rule);
                history[4] += dissipated.max(0.0) as f32;
            }
            let lambda = history[4] as f64;
            if lambda > 0.0 {
                let x = lambda / monotonic_energy;
                damage = if self.exact {
                    (-1.2 * x.powf(1.1)).exp()
                } else {
                    self.cyclic_damage.eval(x)
                };
            }
        }
        let virgin = (branch.reached > before.reached).then_some((before, branch, damage));
        (s.copysign(e) * damage, virgin)
    }
}
