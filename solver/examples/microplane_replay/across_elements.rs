//! The plane work of the unloading class with four elements side by side: the lever the
//! production kernel does not pull yet, measured before the history is laid out for it.
//!
//! The production kernel (`side_by_side.rs`) puts the 21 planes of one element side by side:
//! its branch read gathers each plane's values from that plane's stretch of the history, its
//! lanes are padded from 21 to 24, and its sums over the planes run across the lanes. Here each
//! lane is an element and the planes are taken one after the other, on histories laid out per
//! quantity and plane with the four elements' values next to each other (`interleaved`): the
//! read is a vector load and a select, no lane is padding, and each lane sums its planes in
//! plane order, as the production homogenisation (5.36) does, so that the stresses can be the
//! production's bit for bit off their isotropic part (the volumetric stress, left out here).
//!
//! Only groups of four unloading updates are run: a group with a lane on its virgin law would
//! need that lane's plane work done the scalar way as well, which the share of mixed groups
//! printed beside the timing prices.

use super::side_by_side::{per_quantity, planes_f64, Planes};
use super::*;

/// Elements side by side: one AVX2 register of `f64`.
pub const WIDTH: usize = 4;
/// Planes of the 21-direction rule.
const PLANES: usize = 21;
/// One value per element of a group.
type Lanes = [f64; WIDTH];

/// The plane histories of `group` (`WIDTH` whole element histories), value `q` of plane `p` of
/// element `l` at `(p * QUANTITIES + q) * WIDTH + l`: plane after plane, as the kernel reads
/// them (laid out quantity after quantity instead, the streamed pass took 1.5 times as long).
fn interleaved(group: [&[f32]; WIDTH]) -> Vec<f32> {
    let mut out = vec![0.0; QUANTITIES * PLANES * WIDTH];
    for (l, history) in group.iter().enumerate() {
        for p in 0..PLANES {
            for q in 0..QUANTITIES {
                out[(p * QUANTITIES + q) * WIDTH + l] = history[state::HEADER + p * QUANTITIES + q];
            }
        }
    }
    out
}

/// What each element of a group brings besides its history: its strain, the volumetric strain,
/// the relaxation `psi` and the peaks `(e_p, <e_p - s_p / C0>)` of its laws at its rate factor.
struct Group {
    strain: [Lanes; 6],
    e_v: Lanes,
    psi: Lanes,
    tension: (Lanes, Lanes),
    compression: (Lanes, Lanes),
    shear: (Lanes, Lanes),
    /// The monotonic shear energy the cyclic damage is measured in (5.104).
    monotonic: Lanes,
}

impl Group {
    /// The group of the unloading updates `members` (index, production stress, `psi`, rate
    /// factor), with the laws' peaks as the prototype of planes side by side forms them.
    fn new(c: &Planes, updates: &[Update], members: &[(usize, Sym, f64, f64)]) -> Self {
        let mut g = Group {
            strain: [[0.0; WIDTH]; 6],
            e_v: [0.0; WIDTH],
            psi: [0.0; WIDTH],
            tension: ([0.0; WIDTH], [0.0; WIDTH]),
            compression: ([0.0; WIDTH], [0.0; WIDTH]),
            shear: ([0.0; WIDTH], [0.0; WIDTH]),
            monotonic: [0.0; WIDTH],
        };
        let [e1, e2, e3, e4] = c.scales;
        for (l, &(i, _, psi, f)) in members.iter().enumerate() {
            let u = &updates[i];
            let e_v = (u.strain[0] + u.strain[1] + u.strain[2]) / 3.0;
            let e5 = f * if e_v >= 0.0 { e3 } else { e3 - e4 * e_v };
            let peak = |law: &ExponentialLaw, scale: f64, c0: f64, to: &mut (Lanes, Lanes)| {
                let (e, s) = law.peak(scale, c0);
                (to.0[l], to.1[l]) = (e, (e - s / c0).max(0.0));
            };
            peak(&c.tension, f * e1, c.e_d0, &mut g.tension);
            peak(&c.compression, f * e2, c.e_d0, &mut g.compression);
            peak(&c.shear, e5, c.e_t0, &mut g.shear);
            for k in 0..6 {
                g.strain[k][l] = u.strain[k];
            }
            g.e_v[l] = e_v;
            g.psi[l] = psi;
            g.monotonic[l] = c.e_t0
                * e5
                * e5
                * (c.shear.area_before_peak + c.shear.area_after_peak / u.band.shear);
        }
        g
    }
}

/// The stress magnitudes on the unloading lines of the lanes (5.102, 5.103), the production
/// kernel's operations in its order: turning points `(e, s)`, strain magnitudes `x`, peak
/// strains `e_p` and residual strains at the peak `at_peak`. As in the production kernel, the
/// modulus after the peak (two more divisions) is formed only where a lane needs it.
#[inline(always)]
fn unloaded(
    (e, s, x): (&Lanes, &Lanes, &Lanes),
    c0: f64,
    (e_p, at_peak): (&Lanes, &Lanes),
    c: &Planes,
) -> Lanes {
    if (0..WIDTH).any(|l| !(e[l] <= e_p[l])) {
        unloading_lines::<true>((e, s, x), c0, (e_p, at_peak), c)
    } else {
        unloading_lines::<false>((e, s, x), c0, (e_p, at_peak), c)
    }
}

/// The pass of [`unloaded`]; `PAST_PEAK` false leaves out the modulus after the peak.
#[inline(always)]
fn unloading_lines<const PAST_PEAK: bool>(
    (e, s, x): (&Lanes, &Lanes, &Lanes),
    c0: f64,
    (e_p, at_peak): (&Lanes, &Lanes),
    c: &Planes,
) -> Lanes {
    let (alpha, beta) = (c.alpha, c.beta);
    std::array::from_fn(|l| {
        let (e, s, e_p) = (e[l], s[l], e_p[l]);
        let before = alpha * c0 + (1.0 - alpha) * (s / e);
        let before = if before < c0 { before } else { c0 };
        let modulus = if e <= 0.0 {
            c0
        } else if !PAST_PEAK || e <= e_p {
            before
        } else {
            let residual = (at_peak[l] + beta * (e - e_p)).min(e);
            let towards = if e > residual { s / (e - residual) } else { c0 };
            (alpha * c0 + (1.0 - alpha) * towards).max(s / e).min(c0)
        };
        let unloaded = s - modulus * (e - x[l]);
        if unloaded > 0.0 {
            unloaded
        } else {
            0.0
        }
    })
}

/// The deviatoric-and-isotropic plane stress (5.36) of the four unloading updates of a group,
/// without the volumetric stress.
///
/// # Safety
/// The processor must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::needless_range_loop)]
unsafe fn planes_across(c: &Planes, h: &[f32], g: &Group) -> [Lanes; 6] {
    // One bounds check here instead of one per read.
    let h: &[f32; QUANTITIES * PLANES * WIDTH] = h.try_into().unwrap();
    let read = |q: usize, p: usize| -> [f64; WIDTH] {
        let at = (p * QUANTITIES + q) * WIDTH;
        std::array::from_fn(|l| h[at + l] as f64)
    };
    let project = |t: &[[f64; LANES_PLANES]; 6], p: usize| -> Lanes {
        let e = &g.strain;
        std::array::from_fn(|l| {
            t[0][p] * e[0][l]
                + t[1][p] * e[1][l]
                + t[2][p] * e[2][l]
                + 2.0 * (t[3][p] * e[3][l] + t[4][p] * e[4][l] + t[5][p] * e[5][l])
        })
    };
    let mut sigma = [[0.0; WIDTH]; 6];
    for p in 0..PLANES {
        let normal = project(&c.nn, p);
        let (de, ds, ne, ns) = (read(0, p), read(1, p), read(2, p), read(3, p));
        let (mut e, mut s, mut x) = ([0.0; WIDTH], [0.0; WIDTH], [0.0; WIDTH]);
        let (mut e_p, mut at_peak) = ([0.0; WIDTH], [0.0; WIDTH]);
        let mut positive = [false; WIDTH];
        for l in 0..WIDTH {
            let total = normal[l] - g.e_v[l];
            let e_d = if total < 0.0 { total * g.psi[l] } else { total };
            positive[l] = e_d >= 0.0;
            (e[l], s[l]) = if positive[l] {
                (de[l], ds[l])
            } else {
                (ne[l], ns[l])
            };
            x[l] = e_d.abs();
            let peak = if positive[l] {
                g.tension
            } else {
                g.compression
            };
            (e_p[l], at_peak[l]) = (peak.0[l], peak.1[l]);
        }
        let magnitude = unloaded((&e, &s, &x), c.e_d0, (&e_p, &at_peak), c);
        let s_d: Lanes = std::array::from_fn(|l| {
            if positive[l] {
                magnitude[l]
            } else {
                -magnitude[l]
            }
        });
        let mut shears = [[0.0; WIDTH]; 2];
        for (k, (tensor, base)) in [(&c.mn, state::M), (&c.kn, state::K)]
            .into_iter()
            .enumerate()
        {
            let along = project(tensor, p);
            let (pe, ps, me, ms) = (
                read(base, p),
                read(base + 1, p),
                read(base + 2, p),
                read(base + 3, p),
            );
            let strain: Lanes = std::array::from_fn(|l| along[l] * g.psi[l]);
            let (mut e, mut s) = ([0.0; WIDTH], [0.0; WIDTH]);
            for l in 0..WIDTH {
                (e[l], s[l]) = if strain[l] >= 0.0 {
                    (pe[l], ps[l])
                } else {
                    (me[l], ms[l])
                };
            }
            let x = strain.map(f64::abs);
            let magnitude = unloaded((&e, &s, &x), c.e_t0, (&g.shear.0, &g.shear.1), c);
            shears[k] = std::array::from_fn(|l| magnitude[l].copysign(strain[l]));
            let lambda = read(base + 4, p);
            for l in 0..WIDTH {
                if lambda[l] > 0.0 {
                    shears[k][l] *= c.damage.eval(lambda[l] / g.monotonic[l]);
                }
            }
        }
        let w = c.weight[p];
        for i in 0..6 {
            let (nn, mn, kn) = (c.nn[i][p], c.mn[i][p], c.kn[i][p]);
            for l in 0..WIDTH {
                sigma[i][l] += w * (s_d[l] * nn + shears[0][l] * mn + shears[1][l] * kn);
            }
        }
    }
    sigma
}

/// Checks the kernel across elements against the production stress off its isotropic part
/// and times it against the prototype with the planes side by side, on the same unloading
/// updates in groups of four consecutive ones (nothing for a rule other than the 21
/// directions the kernel is written for).
pub fn compare(
    model: &MicroplaneConcrete,
    parameters: &MicroplaneParameters,
    updates: &[Update],
    unloading: &[(usize, Sym, f64, f64)],
) {
    let planes = model.planes().len();
    if planes != PLANES {
        return;
    }
    let c = Planes::new(model, parameters);
    let groups: Vec<&[(usize, Sym, f64, f64)]> = unloading.chunks_exact(WIDTH).collect();
    let laid_out: Vec<(Vec<f32>, Group)> = groups
        .iter()
        .map(|members| {
            let histories = std::array::from_fn(|l| updates[members[l].0].history.as_slice());
            (interleaved(histories), Group::new(&c, updates, members))
        })
        .collect();
    let per_element: Vec<Vec<f32>> = groups
        .iter()
        .flat_map(|members| members.iter())
        .map(|&(i, ..)| per_quantity(&updates[i].history, planes))
        .collect();

    // The stress off its isotropic part against the production update's.
    let mut off_isotropic: f64 = 0.0;
    let mut shear_bits_differ = 0;
    for (members, (h, g)) in groups.iter().zip(&laid_out) {
        // SAFETY: the caller checked AVX2 and FMA.
        let sigma = unsafe { planes_across(&c, h, g) };
        for (l, (_, stress, ..)) in members.iter().enumerate() {
            let d: Sym = std::array::from_fn(|k| stress[k] - sigma[k][l]);
            shear_bits_differ += usize::from((3..6).any(|k| stress[k] != sigma[k][l]));
            let scale = stress.iter().fold(1e3f64, |a, v| a.max(v.abs()));
            let off = [d[3], d[4], d[5], d[0] - d[1], d[0] - d[2]];
            off_isotropic =
                off_isotropic.max(off.iter().fold(0.0f64, |a, v| a.max(v.abs())) / scale);
        }
    }

    // `count` groups from the first, each kernel timed alternately, best of 5 passes, median
    // of 7 rounds, per element.
    let timed = |count: usize| -> (f64, f64) {
        let elements = (WIDTH * count) as f64;
        let across = || {
            let start = Instant::now();
            let mut sink = 0.0;
            for (h, g) in &laid_out[..count] {
                // SAFETY: the caller checked AVX2 and FMA.
                sink += unsafe { planes_across(&c, h, g) }[0][0];
            }
            std::hint::black_box(sink);
            start.elapsed().as_secs_f64() * 1e9 / elements
        };
        let side_by_side = || {
            let start = Instant::now();
            let mut sink = 0.0;
            let members = groups[..count].iter().flat_map(|members| members.iter());
            for (&(i, _, psi, f), h) in members.zip(&per_element) {
                let u = &updates[i];
                // SAFETY: the caller checked AVX2 and FMA.
                sink += unsafe { planes_f64(&c, h, &u.strain, psi, f, &u.band) }[0];
            }
            std::hint::black_box(sink);
            start.elapsed().as_secs_f64() * 1e9 / elements
        };
        let best = |run: &dyn Fn() -> f64| (0..5).map(|_| run()).fold(f64::INFINITY, f64::min);
        let (mut a, mut s) = (Vec::new(), Vec::new());
        for _ in 0..7 {
            a.push(best(&across));
            s.push(best(&side_by_side));
        }
        (median(&a), median(&s))
    };
    // All groups, their histories streamed from memory; 64 groups, whose 300 KB of histories
    // stay in a core's cache.
    let (a, s) = timed(groups.len());
    let (a_cached, s_cached) = timed(groups.len().min(64));

    // How often four neighbours in element order are all of the unloading class.
    let mut classes = vec![false; updates.len()];
    for u in unloading {
        classes[u.0] = true;
    }
    let aligned = classes.chunks_exact(WIDTH);
    let all = aligned.len();
    let uniform = aligned.filter(|g| g.iter().all(|&u| u)).count();
    println!(
        "plane work of {} unloading updates in groups of {WIDTH}, f64, per element: elements \
         side by side {a:.0} ns, planes side by side {s:.0} ns ({:.2}x); 256 of them in cache \
         {a_cached:.0} ns against {s_cached:.0} ns ({:.2}x); off the isotropic part \
         {off_isotropic:.1e} of the production stress, shear stresses differing in a bit: \
         {shear_bits_differ}",
        groups.len() * WIDTH,
        s / a,
        s_cached / a_cached
    );
    println!(
        "  groups of {WIDTH} neighbours in element order all of the unloading class: {uniform} of \
         {all} ({:.1} %)",
        100.0 * uniform as f64 / all as f64
    );
}
