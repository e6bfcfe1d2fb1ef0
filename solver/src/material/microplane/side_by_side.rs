//! The plane work of the 21-direction rule with the planes side by side: every step of
//! [`MicroplaneConcrete::planes_one_by_one`] as a pass over all planes at once, on arrays of a
//! length fixed at compile time (21 planes padded to 24 lanes, six AVX2 registers of four `f64`),
//! with each `if` of a plane's law turned into a select between both sides computed.
//!
//! Bit for bit the stresses and histories of the plane-by-plane loop: every lane performs the
//! operations of its plane in the same order (`f64` throughout; Rust never fuses a product and
//! a sum, so the AVX2 build's FMA changes no rounding), and the sums over planes, the
//! homogenisation (5.36) included, run in plane order as before. What is not side by side is
//! done plane by plane with the scalar code itself: a component that loads on its virgin law
//! (the law, its Hordijk tail, the cyclic damage's growth and the virgin step the dilatancy
//! reads) and crack friction. The unloading class, every branch below its turning point, is the
//! most common update of a structure that vibrates after cracking (78 % in a step of the drop
//! test, `examples/microplane_replay.rs`).

use super::cyclic::UnloadingRule;
use super::directions::Microplane;
use super::dissipation::{Law, VirginSteps};
use super::plane_loop::{PlaneScales, PlaneSums};
use super::tabulated::DecayTable;
use super::{state, MicroplaneConcrete, Sym};

/// Planes of the 21-direction rule (Bažant & Oh 1986).
pub(super) const PLANES: usize = 21;
/// Lanes: the planes padded to a multiple of four.
const LANES: usize = 24;
/// The number of the 63 components loading on their virgin laws above which an update runs
/// plane by plane (a third: chosen, not tuned; the side-by-side pass costs about as much as the
/// unloading lines of all planes one by one, and each virgin component then runs its scalar
/// law as well).
const MOSTLY_LOADING: usize = 21;
/// A branch of a negative strain sits two values after that of the positive one, in each
/// component's history: the read picks it by offset.
const _: () = assert!(state::D_NEGATIVE == state::D_POSITIVE + 2);
/// One value per plane, padding lanes last.
type Lanes = [f64; LANES];

/// The planes of the 21-direction rule laid out side by side; padding lanes have zero weight
/// and zero projections.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SideBySide {
    nn: [Lanes; 6],
    mn: [Lanes; 6],
    kn: [Lanes; 6],
    /// `6 w`: the weight of the sum over the hemisphere (5.36).
    weight: Lanes,
    /// The same tensors plane by plane, for the homogenisation: each plane's six components
    /// (two padding zeros), so that its terms of all components are formed side by side.
    by_plane: [[Components; 3]; PLANES],
}

/// The six components of a plane's tensor, padded to two AVX2 registers.
type Components = [f64; 8];

impl SideBySide {
    /// The layout of `planes`, if they are the 21 of the rule this kernel is built for.
    pub(super) fn new(planes: &[Microplane]) -> Option<Self> {
        if planes.len() != PLANES {
            return None;
        }
        let mut out = Self {
            nn: [[0.0; LANES]; 6],
            mn: [[0.0; LANES]; 6],
            kn: [[0.0; LANES]; 6],
            weight: [0.0; LANES],
            by_plane: [[[0.0; 8]; 3]; PLANES],
        };
        for (p, plane) in planes.iter().enumerate() {
            for i in 0..6 {
                out.nn[i][p] = plane.nn[i];
                out.mn[i][p] = plane.mn[i];
                out.kn[i][p] = plane.kn[i];
                out.by_plane[p][0][i] = plane.nn[i];
                out.by_plane[p][1][i] = plane.mn[i];
                out.by_plane[p][2][i] = plane.kn[i];
            }
            out.weight[p] = 6.0 * plane.weight;
        }
        Some(out)
    }

    /// `T : E` of every plane, the sums in the order of [`super::contract`].
    #[inline(always)]
    fn project(tensor: &[Lanes; 6], e: &Sym) -> Lanes {
        let mut out = [0.0; LANES];
        for p in 0..LANES {
            out[p] = tensor[0][p] * e[0]
                + tensor[1][p] * e[1]
                + tensor[2][p] * e[2]
                + 2.0 * (tensor[3][p] * e[3] + tensor[4][p] * e[4] + tensor[5][p] * e[5]);
        }
        out
    }
}

/// One stress component of every plane: the branch of the strain's sign, read from the
/// history (the strain's magnitude is `|e|`, as the plane-by-plane loop forms it up to the sign
/// of a zero, which the unloading line's clamp at zero stress removes). Padding lanes, of zero
/// strain, sit below a turning point of strain 1 and stress 0, so they unload to zero stress.
struct Component {
    reached: Lanes,
    stress_reached: Lanes,
}

impl Component {
    fn new() -> Self {
        Self {
            reached: [1.0; LANES],
            stress_reached: [0.0; LANES],
        }
    }

    /// Reads plane `p`'s branch at `slot` of its history.
    #[inline(always)]
    fn read(&mut self, p: usize, history: &[f32], slot: usize) {
        self.reached[p] = history[slot] as f64;
        self.stress_reached[p] = history[slot + 1] as f64;
    }

    /// [`super::cyclic::Branch::unloading`] of every lane, with the peak strain `e_p` of each
    /// lane's law and its residual strain at the peak `<e_p - s_p / C0>` (5.103, see
    /// [`residual_at_peak`]): the stress on the unloading line into `stress` (not used where a
    /// lane is at or beyond its turning point, loading on its virgin law).
    #[inline(always)]
    fn unloading(
        &self,
        strain: &Lanes,
        c0: f64,
        peak: (&Lanes, &Lanes),
        rule: &UnloadingRule,
        stress: &mut Lanes,
    ) {
        // Most components of most updates have every plane at or before its peak (`e <= e_p`),
        // where the modulus after the peak, and its division, is never selected: the pass
        // without it gives the same bits. `!(e <= e_p)` also takes a NaN turning point, which
        // selects the modulus after the peak. Padding lanes (turning point 1) unload to zero
        // stress with either modulus, so only the planes are asked.
        let past_peak = (0..PLANES).any(|p| !(self.reached[p] <= peak.0[p]));
        if past_peak {
            self.unloading_lines::<true>(strain, c0, peak, rule, stress)
        } else {
            self.unloading_lines::<false>(strain, c0, peak, rule, stress)
        }
    }

    /// The pass of [`Self::unloading`] over the lanes; `PAST_PEAK` false leaves out the modulus
    /// after the peak, which no lane then selects (the compiler drops its arithmetic).
    #[inline(always)]
    fn unloading_lines<const PAST_PEAK: bool>(
        &self,
        strain: &Lanes,
        c0: f64,
        peak: (&Lanes, &Lanes),
        rule: &UnloadingRule,
        stress: &mut Lanes,
    ) {
        let (alpha, beta) = (rule.alpha, rule.beta);
        for p in 0..LANES {
            let (e, s, x) = (self.reached[p], self.stress_reached[p], strain[p].abs());
            let (e_p, at_peak) = (peak.0[p], peak.1[p]);
            // `UnloadingRule::modulus` with both sides of its tests computed, then selected.
            let before = alpha * c0 + (1.0 - alpha) * (s / e);
            let before = if before < c0 { before } else { c0 };
            let modulus = if e <= 0.0 {
                c0
            } else if !PAST_PEAK || e <= e_p {
                before
            } else {
                let residual = (at_peak + beta * (e - e_p)).min(e);
                let towards = if e > residual { s / (e - residual) } else { c0 };
                (alpha * c0 + (1.0 - alpha) * towards).max(s / e).min(c0)
            };
            let unloaded = s - modulus * (e - x);
            stress[p] = if unloaded > 0.0 { unloaded } else { 0.0 };
        }
    }
}

/// Which lanes of each component load on their virgin laws (strain magnitude at or beyond the
/// turning point), and how many in all.
#[inline(always)]
fn loading_on_virgin_laws(components: [(&Component, &Lanes); 3]) -> ([[bool; LANES]; 3], usize) {
    let mut virgin = [[false; LANES]; 3];
    let mut loading = 0;
    for ((c, e), virgin) in components.into_iter().zip(&mut virgin) {
        for p in 0..LANES {
            virgin[p] = e[p].abs() >= c.reached[p];
            loading += usize::from(virgin[p]);
        }
    }
    (virgin, loading)
}

/// `<e_p - s_p / C0>`, the residual strain of the unloading rule at the peak `(e_p, s_p)` of a law
/// of initial modulus `c0` (5.103): the same for every plane of a law, so computed once per
/// update instead of once per plane (the same value, so the same bits).
fn residual_at_peak((e_p, s_p): (f64, f64), c0: f64) -> f64 {
    (e_p - s_p / c0).max(0.0)
}

/// [`DecayTable::eval`] of every lane whose `lambda` is positive, 1 elsewhere: the cyclic shear
/// damage `exp(-1.2 (Lambda / W)^1.1)` (5.104) of every plane.
#[inline(always)]
fn cyclic_damage(table: &DecayTable, exact: bool, lambda: &Lanes, energy: f64) -> Lanes {
    let mut out = [1.0; LANES];
    // Most planes of most elements have no cyclic damage: no table to read.
    if !lambda.iter().any(|&l| l > 0.0) {
        return out;
    }
    if exact {
        for p in 0..LANES {
            if lambda[p] > 0.0 {
                let x = lambda[p] / energy;
                out[p] = (-1.2 * x.powf(1.1)).exp();
            }
        }
        return out;
    }
    let x: Lanes = std::array::from_fn(|p| lambda[p] / energy);
    let decay = table.eval_lanes(&x);
    for p in 0..LANES {
        out[p] = if lambda[p] > 0.0 { decay[p] } else { 1.0 };
    }
    out
}

impl MicroplaneConcrete {
    /// [`MicroplaneConcrete::planes_one_by_one`] for the 21-direction rule without the tensile
    /// boundary and without the eager dissipation count, the planes side by side (see the module
    /// documentation).
    #[inline(always)]
    pub(super) fn planes_side_by_side(
        &self,
        layout: &SideBySide,
        planes: &mut [f32],
        sliders: &mut [f32],
        strain: &Sym,
        scales: &PlaneScales,
        virgin_steps: &mut VirginSteps,
    ) -> PlaneSums {
        let planes = &mut planes[..PLANES * state::PER_PLANE];
        let relaxation = scales.relaxation;
        let e_v = scales.e_v;
        // The kinematic constraint (5.85, 5.86) and the relaxation of the normal component in
        // compression and of the shear components (5.91).
        let normal = SideBySide::project(&layout.nn, strain);
        let along_m = SideBySide::project(&layout.mn, strain);
        let along_k = SideBySide::project(&layout.kn, strain);
        let mut e_d = [0.0; LANES];
        let mut e_m = [0.0; LANES];
        let mut e_k = [0.0; LANES];
        for p in 0..LANES {
            let total = normal[p] - e_v;
            e_d[p] = if total < 0.0 {
                total * relaxation
            } else {
                total
            };
            e_m[p] = along_m[p] * relaxation;
            e_k[p] = along_k[p] * relaxation;
        }
        // Padding lanes carry no strain (their normal one would be `-e_V`): at magnitude 0 they
        // stay below their turning point.
        for e in [&mut e_d, &mut e_m, &mut e_k] {
            e[PLANES..].fill(0.0);
        }

        // Each component's branch of its strain's sign, and the shears' cyclic dissipation.
        let (mut d, mut m, mut k) = (Component::new(), Component::new(), Component::new());
        let mut lambda_m = [0.0; LANES];
        let mut lambda_k = [0.0; LANES];
        for (p, history) in planes.chunks_exact(state::PER_PLANE).enumerate() {
            let side = |e: f64| if e >= 0.0 { 0 } else { 2 };
            d.read(p, history, state::D_POSITIVE + side(e_d[p]));
            m.read(p, history, state::M + side(e_m[p]));
            k.read(p, history, state::K + side(e_k[p]));
            lambda_m[p] = history[state::M + 4] as f64;
            lambda_k[p] = history[state::K + 4] as f64;
        }

        // An update that loads most components on their virgin laws (a structure loaded
        // monotonically, the quasi-static beam) would compute their unloading lines for nothing
        // and then run them plane by plane: it runs plane by plane from the start.
        let ([virgin_d, virgin_m, virgin_k], loading) =
            loading_on_virgin_laws([(&d, &e_d), (&m, &e_m), (&k, &e_k)]);
        if loading > MOSTLY_LOADING {
            let strains = [&normal[..PLANES], &along_m[..PLANES], &along_k[..PLANES]];
            return self.planes_one_by_one(planes, sliders, strains, scales, None, virgin_steps);
        }

        // The unloading lines (5.102, 5.103) of all components.
        let tension = (
            scales.tension_peak.0,
            residual_at_peak(scales.tension_peak, self.e_d0),
        );
        let compression = (
            scales.compression_peak.0,
            residual_at_peak(scales.compression_peak, self.e_d0),
        );
        let mut peak_e = [0.0; LANES];
        let mut peak_s = [0.0; LANES];
        for p in 0..LANES {
            let peak = if e_d[p] >= 0.0 { tension } else { compression };
            (peak_e[p], peak_s[p]) = peak;
        }
        let mut s_d = [0.0; LANES];
        let mut s_m = [0.0; LANES];
        let mut s_k = [0.0; LANES];
        let rule = &self.rule;
        d.unloading(&e_d, self.e_d0, (&peak_e, &peak_s), rule, &mut s_d);
        let shear_e = [scales.shear_peak.0; LANES];
        let shear_s = [residual_at_peak(scales.shear_peak, self.e_t0); LANES];
        let shear_peak = (&shear_e, &shear_s);
        m.unloading(&e_m, self.e_t0, shear_peak, rule, &mut s_m);
        k.unloading(&e_k, self.e_t0, shear_peak, rule, &mut s_k);

        // The shears' sign and cyclic damage (5.104).
        if self.parameters.shear_cyclic_damage {
            let energy = scales.shear.monotonic_energy;
            let damage_m = cyclic_damage(&self.cyclic_damage, self.exact, &lambda_m, energy);
            let damage_k = cyclic_damage(&self.cyclic_damage, self.exact, &lambda_k, energy);
            for p in 0..LANES {
                s_m[p] = s_m[p].copysign(e_m[p]) * damage_m[p];
                s_k[p] = s_k[p].copysign(e_k[p]) * damage_k[p];
            }
        } else {
            for p in 0..LANES {
                s_m[p] = s_m[p].copysign(e_m[p]) * 1.0;
                s_k[p] = s_k[p].copysign(e_k[p]) * 1.0;
            }
        }

        // Components on their virgin laws, plane by plane in the order of the loop they replace
        // (normal, M, K), so that the virgin steps are recorded in its order.
        if loading > 0 {
            self.virgin_components(
                planes,
                [&e_d, &e_m, &e_k],
                [&virgin_d, &virgin_m, &virgin_k],
                [&mut s_d, &mut s_m, &mut s_k],
                scales,
                virgin_steps,
            );
        }

        // The normal stress's sign, and the inelastic compressive strain the dilatancy reads.
        let mut inelastic = [0.0; LANES];
        for p in 0..LANES {
            let compressed = e_d[p].is_nan() || e_d[p] < 0.0;
            inelastic[p] = if compressed {
                layout.weight[p] * (-e_d[p] - s_d[p] * scales.inverse_e_d0).max(0.0)
            } else {
                0.0
            };
            s_d[p] = if compressed { -s_d[p] } else { s_d[p] };
        }

        if let Some(mu) = self.parameters.crack_friction {
            for (p, history) in planes.chunks_exact(state::PER_PLANE).enumerate() {
                (s_m[p], s_k[p]) = self.plane_friction(
                    mu,
                    (scales.s_v + s_d[p], s_m[p], s_k[p]),
                    [along_m[p], along_k[p]],
                    history,
                    &mut sliders[2 * p..2 * p + 2],
                    relaxation,
                    scales.shear_peak.0,
                );
            }
        }

        homogenised(layout, &s_d, &s_m, &s_k, &inelastic)
    }

    /// The components on their virgin laws (`virgin`), plane by plane in the order of the loop
    /// they replace (normal, `M`, `K`), so that the virgin steps are recorded in its order: the
    /// scalar code of [`MicroplaneConcrete::planes_one_by_one`] itself, with the Hordijk tail and
    /// the growth of the cyclic shear damage, overwriting the unloading stresses of `stress`
    /// (the normal one as a magnitude, the shears signed and damaged).
    #[inline(always)]
    fn virgin_components(
        &self,
        planes: &mut [f32],
        [e_d, e_m, e_k]: [&Lanes; 3],
        [virgin_d, virgin_m, virgin_k]: [&[bool; LANES]; 3],
        [s_d, s_m, s_k]: [&mut Lanes; 3],
        scales: &PlaneScales,
        virgin_steps: &mut VirginSteps,
    ) {
        let dilatant = scales.dilatant;
        for (p, history) in planes.chunks_exact_mut(state::PER_PLANE).enumerate() {
            if virgin_d[p] {
                let (s, step) = self.normal_branch(e_d[p], history, scales);
                s_d[p] = s;
                if let Some((law, before, after)) = step.filter(|_| dilatant) {
                    virgin_steps.push(p, law, before, after, 1.0);
                }
            }
            for (virgin, e, s, slot) in [
                (virgin_m, e_m, &mut *s_m, state::M),
                (virgin_k, e_k, &mut *s_k, state::K),
            ] {
                if virgin[p] {
                    let (stress, step) =
                        self.shear_stress(e[p], &mut history[slot..slot + 5], &scales.shear);
                    s[p] = stress;
                    if let Some((before, after, damage)) = step.filter(|_| dilatant) {
                        virgin_steps.push(p, Law::Shear, before, after, damage);
                    }
                }
            }
        }
    }
}

/// The homogenisation (5.36) of the planes' signed stresses, with the sum of the normal
/// stresses for the trace term and of `inelastic` for the dilatancy. The sums run in plane order,
/// each plane's terms of the six components side by side (the same products in the same order
/// as the plane-by-plane loop, so its sums bit for bit): one pass with two registers of sums,
/// where terms formed per component across the planes had to be read back one by one.
#[inline(always)]
fn homogenised(
    layout: &SideBySide,
    s_d: &Lanes,
    s_m: &Lanes,
    s_k: &Lanes,
    inelastic: &Lanes,
) -> PlaneSums {
    let w = &layout.weight;
    let mut sigma: Components = [0.0; 8];
    let mut sums = PlaneSums::default();
    for p in 0..PLANES {
        let [nn, mn, kn] = &layout.by_plane[p];
        let (d, m, k, weight) = (s_d[p], s_m[p], s_k[p], w[p]);
        for i in 0..8 {
            sigma[i] += weight * (d * nn[i] + m * mn[i] + k * kn[i]);
        }
        sums.inelastic_compression += inelastic[p];
        sums.sum_d += weight * d;
    }
    sums.sigma.copy_from_slice(&sigma[..6]);
    sums
}
