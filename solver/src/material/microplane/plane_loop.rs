//! The plane work of one update, plane by plane: the normal and shear components of every
//! microplane (5.85, 5.86, 5.23, 5.100-5.104), crack friction and the tensile boundary, and their
//! homogenisation (5.36). The general path, for every rule and every option; the 21-plane rule
//! without the tensile boundary runs the same operations with the planes side by side
//! (`side_by_side`).

use super::cyclic::{Branch, UnloadingRule};
use super::dissipation::{Law, VirginSteps};
use super::shear::ShearScale;
use super::tension_boundary::ElementBoundary;
use super::{state, CrackBand, MicroplaneConcrete, RELAXATION_ONSET};

/// What the plane laws of one update share, computed once per update.
#[derive(Debug, Clone, Copy)]
pub(super) struct PlaneScales {
    /// The element's relaxation `psi` (5.91) after this update.
    pub relaxation: f64,
    /// The volumetric strain and stress (5.21, 5.22).
    pub e_v: f64,
    pub s_v: f64,
    /// `1 / e1` and `E_D0 e1` of the deviatoric tension law, `1 / e2` and `E_D0 e2` of the
    /// compression law (one division per update, not per plane).
    pub inverse_e1: f64,
    pub tension_amplitude: f64,
    pub inverse_e2: f64,
    pub compression_amplitude: f64,
    /// `1 / E_D0`.
    pub inverse_e_d0: f64,
    /// The peaks `(e_p, s_p)` of the unloading rules (5.103).
    pub tension_peak: (f64, f64),
    pub compression_peak: (f64, f64),
    pub shear_peak: (f64, f64),
    pub shear: ShearScale,
    /// The crack-band factor of the tension law.
    pub band_tension: f64,
    /// Whether the virgin steps are recorded for the dilatancy, and whether their dissipation is
    /// counted in the loop (the reference count).
    pub dilatant: bool,
    pub eager: bool,
}

impl PlaneScales {
    /// The initial modulus and the peak of each law's unloading rule.
    pub fn modulus(&self, model: &MicroplaneConcrete, law: Law) -> (f64, (f64, f64)) {
        match law {
            Law::Tension => (model.e_d0, self.tension_peak),
            Law::Compression => (model.e_d0, self.compression_peak),
            Law::Shear => (model.e_t0, self.shear_peak),
        }
    }
}

/// What the plane loop hands back to the homogenisation.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct PlaneSums {
    /// `sum_p 6 w_p (s_D N + s_M M + s_K K)` (5.36, without the volumetric part).
    pub sigma: [f64; 6],
    /// `sum_p 6 w_p s_D`, for the deviatoric trace term.
    pub sum_d: f64,
    /// `sum_p 6 w_p <-e_D - s_D / E_D0>` over planes in deviatoric compression (dilatancy).
    pub inelastic_compression: f64,
    /// The eager count of the planes' dissipation (reference only; 0 otherwise).
    pub dissipation: f64,
}

impl MicroplaneConcrete {
    /// The scales of the plane laws at the rate factor `f` (5.110), the volumetric strain and
    /// stress `e_v`, `s_v`, the crack band `band` and the relaxation `relaxation` of this update:
    /// the strain scales `e1 = f s e1`, `e2 = f e2` and `e5 = f (e3 - e4 <-e_V>)` (5.23) and what
    /// follows from them once per update.
    #[inline(always)]
    pub(super) fn plane_scales(
        &self,
        e_v: f64,
        s_v: f64,
        f: f64,
        band: &CrackBand,
        relaxation: f64,
    ) -> PlaneScales {
        let p = &self.parameters;
        let e1 = f * band.strength * p.e1;
        let e5 = f * if e_v >= 0.0 { p.e3 } else { p.e3 - p.e4 * e_v };
        let e2 = f * p.e2;
        let shear_peak = self.shear.peak(e5, self.e_t0);
        let dilatant = p.dilatancy > 0.0;
        PlaneScales {
            relaxation,
            e_v,
            s_v,
            inverse_e1: 1.0 / e1,
            tension_amplitude: self.e_d0 * e1,
            inverse_e2: 1.0 / e2,
            compression_amplitude: self.e_d0 * e2,
            inverse_e_d0: 1.0 / self.e_d0,
            tension_peak: self.tension.peak(e1, self.e_d0),
            compression_peak: self.compression.peak(e2, self.e_d0),
            shear_peak,
            shear: ShearScale {
                e5,
                peak: shear_peak,
                band: band.shear,
                monotonic_energy: self.e_t0
                    * e5
                    * e5
                    * (self.shear.area_before_peak + self.shear.area_after_peak / band.shear),
            },
            band_tension: band.tension,
            dilatant,
            // The energy the planes dissipate in this update (J/m^3, each branch that loads on
            // its virgin law) may pay for the growth of the dilatant strain: the virgin steps
            // are recorded, and summed only where the growth reads them (`dissipation`).
            eager: dilatant && self.always_count_dissipation,
        }
    }

    /// The normal component of a plane at the deviatoric strain `e_d` (5.19, 5.100-5.103):
    /// its stress magnitude `s >= 0`, advancing the branch of `e_d`'s sign in `history` (the
    /// plane's values), and where the branch loaded on its virgin law, the law and the branch
    /// before and after.
    #[inline(always)]
    pub(super) fn normal_branch(
        &self,
        e_d: f64,
        history: &mut [f32],
        scales: &PlaneScales,
    ) -> (f64, Option<(Law, Branch, Branch)>) {
        let positive = e_d >= 0.0;
        let (slot, law, x) = if positive {
            (state::D_POSITIVE, Law::Tension, e_d)
        } else {
            (state::D_NEGATIVE, Law::Compression, -e_d)
        };
        let mut b = Branch::load(&history[slot..slot + 2]);
        let before = b;
        let peak = if positive {
            scales.tension_peak
        } else {
            scales.compression_peak
        };
        // The split form of `Branch::stress`: its law closure was called out of line, outside
        // the AVX2 build (perf).
        let s = match b.unloading(x, self.e_d0, peak, &self.rule) {
            Some(s) => s,
            None if positive => b.virgin(
                x,
                self.tension.scaled_stress(
                    e_d * scales.inverse_e1,
                    scales.tension_amplitude,
                    scales.band_tension,
                ),
            ),
            None => b.virgin(
                x,
                self.compression.scaled_stress(
                    -e_d * scales.inverse_e2,
                    scales.compression_amplitude,
                    1.0,
                ),
            ),
        };
        b.store(&mut history[slot..slot + 2]);
        (s, (b.reached > before.reached).then_some((law, before, b)))
    }

    /// The planes one by one (see the module documentation), advancing `planes` (the plane
    /// histories) and `sliders` (the crack-friction slips), recording the virgin steps.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn planes_one_by_one(
        &self,
        planes: &mut [f32],
        sliders: &mut [f32],
        strains: [&[f64]; 3],
        scales: &PlaneScales,
        boundary: Option<&ElementBoundary>,
        virgin_steps: &mut VirginSteps,
    ) -> PlaneSums {
        let [normal, along_m, along_k] = strains;
        let PlaneScales {
            relaxation,
            e_v,
            s_v,
            inverse_e_d0,
            shear_peak,
            dilatant,
            eager,
            ..
        } = *scales;
        let rule: &UnloadingRule = &self.rule;
        // The dissipation of one virgin step, for the eager count (the reference).
        let dissipated_by = |law: Law, before: &Branch, after: &Branch| {
            let (c0, peak) = scales.modulus(self, law);
            after.dissipated_since(before, c0, peak, rule)
        };
        let p_friction = self.parameters.crack_friction;
        // The shear branches' modulus, peak and rule for the eager reference count.
        let eager_shear = eager.then_some((self.e_t0, shear_peak, rule));
        let mut sums = PlaneSums::default();
        for (p, (plane, history)) in self
            .planes
            .iter()
            .zip(planes.chunks_exact_mut(state::PER_PLANE))
            .enumerate()
        {
            let e_d_total = normal[p] - e_v;
            let (e_d, psi_t) = (
                if e_d_total < 0.0 {
                    e_d_total * relaxation
                } else {
                    e_d_total
                },
                relaxation,
            );
            let mut dissipated = 0.0;
            let s_d = if e_d >= 0.0 && boundary.is_some() {
                // The plane's boundary, below, caps the total normal stress.
                self.e_d0 * e_d
            } else {
                let (s, step) = self.normal_branch(e_d, history, scales);
                if e_d.is_nan() || e_d < 0.0 {
                    sums.inelastic_compression +=
                        6.0 * plane.weight * (-e_d - s * inverse_e_d0).max(0.0);
                }
                if let Some((law, before, after)) = step.filter(|_| dilatant) {
                    virgin_steps.push(p, law, before, after, 1.0);
                    if eager {
                        dissipated += dissipated_by(law, &before, &after);
                    }
                }
                if e_d >= 0.0 {
                    s
                } else {
                    -s
                }
            };
            let e_m = along_m[p] * psi_t;
            let e_k = along_k[p] * psi_t;
            // M, then K, each by a direct call (a closure would not inherit the AVX2 build's
            // features). Not a loop over a two-element array either: its 8-byte stores were
            // read back by one wider load, which store forwarding cannot serve, and the stall
            // took a tenth of the update's samples (perf, static beam).
            let (s_m, step_m) =
                self.shear_stress(e_m, &mut history[state::M..state::M + 5], &scales.shear);
            if let Some(step) = step_m.filter(|_| dilatant) {
                dissipated += virgin_steps.push_shear(p, step, eager_shear);
            }
            let (s_k, step_k) =
                self.shear_stress(e_k, &mut history[state::K..state::K + 5], &scales.shear);
            if let Some(step) = step_k.filter(|_| dilatant) {
                dissipated += virgin_steps.push_shear(p, step, eager_shear);
            }
            let (s_m, s_k) = match p_friction.filter(|_| boundary.is_none()) {
                Some(mu) => self.plane_friction(
                    mu,
                    (s_v + s_d, s_m, s_k),
                    [along_m[p], along_k[p]],
                    history,
                    &mut sliders[2 * p..2 * p + 2],
                    relaxation,
                    shear_peak.0,
                ),
                None => (s_m, s_k),
            };
            let w = 6.0 * plane.weight;
            sums.dissipation += w * dissipated;
            sums.sum_d += w * s_d;
            let (s_d, s_m, s_k) = match boundary {
                Some(b) => {
                    let slip = sliders.get_mut(2 * p..2 * p + 2);
                    let shear = (s_m, s_k, [along_m[p], along_k[p]]);
                    b.plane_stresses(self, history, slip, s_v, s_d, shear, shear_peak.0)
                }
                None => (s_d, s_m, s_k),
            };
            for i in 0..6 {
                sums.sigma[i] += w * (s_d * plane.nn[i] + s_m * plane.mn[i] + s_k * plane.kn[i]);
            }
        }
        sums
    }

    /// Crack friction on one plane (MICROPLANE "Crack friction") with coefficient `mu`, given
    /// the plane's normal stress `s_V + s_D` and the laws' shear stresses, its shear strains
    /// without `psi`, its history (after the laws' update) and its two slips.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn plane_friction(
        &self,
        mu: f64,
        (normal_stress, s_m, s_k): (f64, f64, f64),
        strain: [f64; 2],
        history: &[f32],
        slip: &mut [f32],
        relaxation: f64,
        shear_peak_strain: f64,
    ) -> (f64, f64) {
        let bound = mu * (-normal_stress).max(0.0);
        // The cracks slide once a shear law has passed its peak on this plane or the element's
        // cracks have opened (psi < 1, beyond rounding). The slider sees the plane's shear
        // strain itself: psi stands for open cracks, which carry nothing, and an open crack has
        // no compressive normal stress to bound friction by, but once closed under pressure it
        // slides with friction however wide it was.
        let reached = [state::M, state::M + 2, state::K, state::K + 2];
        let cracked = relaxation < RELAXATION_ONSET
            || reached
                .iter()
                .any(|&i| history[i] as f64 > shear_peak_strain);
        self.crack_friction([s_m, s_k], strain, slip, bound, cracked)
    }
}
