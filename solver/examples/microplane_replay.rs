//! The microplane updates of one step of the 2 m/s drop test (`cases/beam/drop-2ms.yaml`),
//! recorded and replayed on one thread: what they cost, in which order, and what a plane loop with
//! the planes side by side would cost (issue 20).
//!
//! The run goes to step `STEP - 1`. Each beam element's history is kept, and the run takes one
//! more step. Each element's update of that step is rebuilt from the two displacement fields:
//! the Green-Lagrange strain with the case's volumetric measure, the rate
//! `gamma_dot = sqrt(1/2 Edot : Edot)` with `Edot = (E_n - E_{n-1}) / dt`, and the crack band.
//! The rate is the backward difference the element forms to round-off. Then:
//!
//! - the classes of the updates: elastic path; every branch below its turning point (no plane
//!   history moves); some branch loading on its virgin law;
//! - the production update (planes side by side, `side_by_side.rs`) against the same update with
//!   the planes one by one (`MicroplaneConcrete::with_planes_one_by_one`): bit for bit on every
//!   update of the step, then timed alternately in three orders: all elements in order, with
//!   their histories streamed from memory; 1000 spread elements, in cache; the same 1000, each 16
//!   times in a row, with branches predicted;
//! - on the unloading class, a prototype of the plane work with the planes side by side. The
//!   history is laid out per quantity, plane after plane, and `if` becomes a select. It runs in
//!   `f64` and in `f32`, in the AVX2 build. The `f64` prototype is checked against the
//!   production stress: the difference must be the isotropic volumetric part the prototype
//!   leaves out. The `f32` one is checked against the `f64` one;
//! - on the unloading class again, the same plane work with four elements side by side instead
//!   of the planes (`microplane_replay/across_elements.rs`), checked bit for bit against the
//!   production's shear stresses and timed against the prototype above, with the share of
//!   groups of four neighbours that are all of the unloading class.
//!
//! `cargo run --release -p impact-solver --example microplane_replay [STEP]` (step 500 by
//! default; about 20 s)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::time::Instant;

use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::kinematics::green_lagrange_from_h;
use impact_solver::material::microplane::laws::ExponentialLaw;
use impact_solver::material::microplane::state;
use impact_solver::material::microplane::tabulated::DecayTable;
use impact_solver::material::microplane::{
    sym, CrackBand, MicroplaneConcrete, MicroplaneParameters, Sym, VolumetricStrain,
};
use impact_solver::material::MaterialModel;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, Scene};
use nalgebra::Matrix3;

/// Planes of the prototype: the 21 of the rule, padded to a multiple of 8 lanes.
const LANES_PLANES: usize = 24;
/// Values per plane of the history (`state::PER_PLANE`).
const QUANTITIES: usize = state::PER_PLANE;

/// One recorded update: the history before it, the model's strain, rate and crack band.
struct Update {
    history: Vec<f32>,
    strain: Sym,
    gamma_dot: f64,
    band: CrackBand,
}

/// The beam's parameters and the recorded updates of step `step`.
fn record(step: usize) -> (MicroplaneParameters, Vec<Update>) {
    let case = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/beam/drop-2ms.yaml");
    let scene = Scene::from_yaml_file_entry(&case, "scene").unwrap();
    let Analysis::Explicit(ExplicitAnalysis { settings, .. }) = &scene.analysis else {
        panic!("the drop test is an explicit analysis")
    };
    let beam = scene.bodies.iter().find(|b| b.name == "beam").unwrap();
    let MaterialModel::Microplane(parameters) = beam.material.model("beam").unwrap() else {
        panic!("the beam is microplane concrete")
    };
    let problem = build_problem(&scene).unwrap();
    let output = OutputSettings {
        dir: None,
        stem: "replay".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::new(&problem, settings.clone(), output).unwrap();
    for _ in 1..step {
        solver.step().unwrap();
    }
    let histories = solver.history().clone();
    let u_before = solver.whole(&solver.u).into_owned();
    solver.step().unwrap();
    let dt = solver.time_step();
    let u_now = solver.whole(&solver.u);
    let model = &problem.model;
    let body = model.bodies.iter().position(|b| b.name == "beam").unwrap();
    let beam_history = histories.bodies[body].as_ref().unwrap();
    let laws = MicroplaneConcrete::new(parameters).unwrap();
    let strain_of = |e: usize, u: &[nalgebra::Vector3<f64>]| {
        green_lagrange_from_h(&(model.deformation_gradient(e, u) - Matrix3::identity()))
    };
    let updates = model.bodies[body]
        .elements
        .clone()
        .enumerate()
        .map(|(local, e)| {
            let (now, before) = (strain_of(e, &u_now), strain_of(e, &u_before));
            let rate = (now - before) / dt;
            Update {
                history: beam_history.element(local).to_vec(),
                strain: parameters.volumetric_strain.measured(&sym(&now)),
                gamma_dot: (0.5 * rate.norm_squared()).sqrt(),
                band: laws
                    .crack_band(MicroplaneConcrete::element_size(model.volume(e)))
                    .unwrap(),
            }
        })
        .collect();
    (parameters, updates)
}

/// Nanoseconds per update of `model.update` over `order` (indices into `updates`), the best of
/// five passes, each from the recorded histories (restored outside the clock).
fn replay(model: &MicroplaneConcrete, updates: &[Update], order: &[usize]) -> f64 {
    let mut best = f64::INFINITY;
    let mut sink = 0.0;
    for _ in 0..5 {
        let mut histories: Vec<Vec<f32>> =
            order.iter().map(|&i| updates[i].history.clone()).collect();
        let start = Instant::now();
        for (history, &i) in histories.iter_mut().zip(order) {
            let u = &updates[i];
            sink += model.update(history, &u.strain, u.gamma_dot, &u.band).0[0];
        }
        best = best.min(start.elapsed().as_secs_f64() * 1e9 / order.len() as f64);
    }
    std::hint::black_box(sink);
    best
}

/// The median of the rounds `v`.
fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let step: usize = std::env::args()
        .nth(1)
        .map_or(500, |s| s.parse().expect("STEP is a step number"));
    let (mut parameters, updates) = record(step);
    // The recorded strains already carry the case's volumetric measure.
    parameters.volumetric_strain = VolumetricStrain::GreenLagrangeTrace;
    let model = MicroplaneConcrete::new(parameters).unwrap();
    let n = updates.len();

    // Classes, from one production update of each.
    let plane_values = state::HEADER..state::HEADER + state::PER_PLANE * model.planes().len();
    let (mut elastic, mut unloading) = (0, Vec::new());
    for (i, u) in updates.iter().enumerate() {
        let mut after = u.history.clone();
        let (stress, info) = model.update(&mut after, &u.strain, u.gamma_dot, &u.band);
        if after[state::ELASTIC_UPDATES] != u.history[state::ELASTIC_UPDATES] {
            elastic += 1;
        } else if after[plane_values.clone()] == u.history[plane_values.clone()] {
            unloading.push((i, stress, info.psi, info.rate_factor));
        }
    }
    let share = |k: usize| 100.0 * k as f64 / n as f64;
    println!("step {step}: {n} beam element updates");
    println!(
        "  elastic path {:.1} %, every branch below its turning point {:.1} %, some branch on \
         its virgin law {:.1} %",
        share(elastic),
        share(unloading.len()),
        share(n - elastic - unloading.len())
    );

    // The whole step, side by side against one by one: stresses and histories bit for bit.
    let one_by_one = model.clone().with_planes_one_by_one();
    let differing = updates
        .iter()
        .filter(|u| {
            let (mut a, mut b) = (u.history.clone(), u.history.clone());
            let (sa, _) = model.update(&mut a, &u.strain, u.gamma_dot, &u.band);
            let (sb, _) = one_by_one.update(&mut b, &u.strain, u.gamma_dot, &u.band);
            sa.map(f64::to_bits) != sb.map(f64::to_bits)
                || a.iter()
                    .map(|v| v.to_bits())
                    .ne(b.iter().map(|v| v.to_bits()))
        })
        .count();
    println!(
        "planes side by side ({}) against one by one: {differing} of {n} updates differ in a bit \
         of stress or history",
        if model.runs_planes_side_by_side() {
            "on"
        } else {
            "off: not the 21-direction rule"
        }
    );

    // The production update in three orders, side by side and one by one taken alternately,
    // ROUNDS times: the medians and their ratio.
    let all: Vec<usize> = (0..n).collect();
    let spread_of = |of: &[usize]| -> Vec<usize> {
        let count = of.len().min(1000);
        (0..count).map(|k| of[k * (of.len() / count)]).collect()
    };
    let spread = spread_of(&all);
    let repeated: Vec<usize> = spread.iter().flat_map(|&i| [i; 16]).collect();
    let unloading_class: Vec<usize> = unloading.iter().map(|u| u.0).collect();
    let virgin_class: Vec<usize> = (0..n)
        .filter(|i| unloading_class.binary_search(i).is_err())
        .collect();
    let orders = [
        (
            format!("all {n} in element order (histories streamed)"),
            all,
        ),
        ("1000 spread elements (in cache)".to_string(), spread),
        (
            "the same, each 16 times in a row (branches predicted)".to_string(),
            repeated,
        ),
        (
            "1000 spread of the unloading class (in cache)".to_string(),
            spread_of(&unloading_class),
        ),
        (
            "1000 spread of the virgin-loading class (in cache)".to_string(),
            spread_of(&virgin_class),
        ),
    ];
    const ROUNDS: usize = 7;
    let mut times = vec![[Vec::new(), Vec::new()]; orders.len()];
    for _ in 0..ROUNDS {
        for (o, (_, order)) in orders.iter().enumerate() {
            times[o][0].push(replay(&model, &updates, order));
            times[o][1].push(replay(&one_by_one, &updates, order));
        }
    }
    println!(
        "production update, one thread (best of 5 passes, median of {ROUNDS} rounds), planes \
         side by side against one by one:"
    );
    for ((name, _), [side, one]) in orders.iter().zip(&times) {
        let (side, one) = (median(side), median(one));
        println!(
            "  {name}: {side:.0} ns against {one:.0} ns ({:.2}x)",
            one / side
        );
    }

    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        side_by_side::compare(&model, &parameters, &updates, &unloading);
        across_elements::compare(&model, &parameters, &updates, &unloading);
    }
}

#[cfg(target_arch = "x86_64")]
#[path = "microplane_replay/across_elements.rs"]
mod across_elements;

/// The plane work of the unloading class with the planes side by side.
#[cfg(target_arch = "x86_64")]
mod side_by_side {
    use super::*;

    /// What the prototype needs of the model, planes padded with zero weights.
    pub struct Planes {
        pub(super) nn: [[f64; LANES_PLANES]; 6],
        pub(super) mn: [[f64; LANES_PLANES]; 6],
        pub(super) kn: [[f64; LANES_PLANES]; 6],
        /// `6 w`, the weight of the sum over the hemisphere (5.36).
        pub(super) weight: [f64; LANES_PLANES],
        /// `6 w N`, `6 w M`, `6 w K`.
        weighted: [[[f64; LANES_PLANES]; 6]; 3],
        /// The same four in `f32`.
        nn32: [[f32; LANES_PLANES]; 6],
        mn32: [[f32; LANES_PLANES]; 6],
        kn32: [[f32; LANES_PLANES]; 6],
        weighted32: [[[f32; LANES_PLANES]; 6]; 3],
        pub(super) e_d0: f64,
        pub(super) e_t0: f64,
        pub(super) alpha: f64,
        pub(super) beta: f64,
        pub(super) tension: ExponentialLaw,
        pub(super) compression: ExponentialLaw,
        pub(super) shear: ExponentialLaw,
        pub(super) scales: [f64; 4],
        pub(super) damage: DecayTable,
    }

    impl Planes {
        pub(super) fn new(model: &MicroplaneConcrete, p: &MicroplaneParameters) -> Self {
            let mut out = Planes {
                nn: [[0.0; LANES_PLANES]; 6],
                mn: [[0.0; LANES_PLANES]; 6],
                kn: [[0.0; LANES_PLANES]; 6],
                weight: [0.0; LANES_PLANES],
                weighted: [[[0.0; LANES_PLANES]; 6]; 3],
                nn32: [[0.0; LANES_PLANES]; 6],
                mn32: [[0.0; LANES_PLANES]; 6],
                kn32: [[0.0; LANES_PLANES]; 6],
                weighted32: [[[0.0; LANES_PLANES]; 6]; 3],
                e_d0: p.youngs_modulus / (1.0 + p.poisson_ratio),
                e_t0: p.youngs_modulus / (1.0 + p.poisson_ratio),
                alpha: p.alpha,
                beta: p.beta,
                tension: ExponentialLaw::with_hordijk_tail(p.m, p.hordijk_tail),
                compression: ExponentialLaw::new(p.n),
                shear: ExponentialLaw::new(p.k),
                scales: [p.e1, p.e2, p.e3, p.e4],
                damage: DecayTable::new(1.2, 1.1),
            };
            for (j, plane) in model.planes().iter().enumerate() {
                let w = 6.0 * plane.weight;
                out.weight[j] = w;
                for i in 0..6 {
                    out.nn[i][j] = plane.nn[i];
                    out.mn[i][j] = plane.mn[i];
                    out.kn[i][j] = plane.kn[i];
                    out.weighted[0][i][j] = w * plane.nn[i];
                    out.weighted[1][i][j] = w * plane.mn[i];
                    out.weighted[2][i][j] = w * plane.kn[i];
                }
            }
            let narrow = |a: &[[f64; LANES_PLANES]; 6]| a.map(|row| row.map(|v| v as f32));
            out.nn32 = narrow(&out.nn);
            out.mn32 = narrow(&out.mn);
            out.kn32 = narrow(&out.kn);
            out.weighted32 = out.weighted.map(|t| narrow(&t));
            out
        }
    }

    /// The history of the planes laid out per quantity, plane after plane; padding planes sit
    /// at a turning point of strain 1 and stress 0.
    pub(super) fn per_quantity(history: &[f32], planes: usize) -> Vec<f32> {
        let mut out = vec![0.0f32; QUANTITIES * LANES_PLANES];
        for q in 0..QUANTITIES {
            for p in 0..LANES_PLANES {
                out[q * LANES_PLANES + p] = if p < planes {
                    history[state::HEADER + p * QUANTITIES + q]
                } else if matches!(q, 0 | 2 | 4 | 6 | 9 | 11) {
                    1.0
                } else {
                    0.0
                };
            }
        }
        out
    }

    /// The unloading modulus of thesis (5.102)-(5.103), `UnloadingRule::modulus`, with both
    /// sides of its test computed and one selected, so that lanes of planes can run it at once.
    macro_rules! modulus {
        ($e:expr, $s:expr, $c0:expr, $ep:expr, $sp:expr, $alpha:expr, $beta:expr) => {{
            let (e, s, c0, ep, sp, alpha, beta) = ($e, $s, $c0, $ep, $sp, $alpha, $beta);
            let before = alpha * c0 + (1.0 - alpha) * (s / e);
            let before = if before < c0 { before } else { c0 };
            let residual = ((ep - sp / c0).max(0.0) + beta * (e - ep)).min(e);
            let towards = if e > residual { s / (e - residual) } else { c0 };
            let after = (alpha * c0 + (1.0 - alpha) * towards).max(s / e).min(c0);
            if e <= ep {
                before
            } else {
                after
            }
        }};
    }

    /// The plane kernel for one float type: the stress of the planes of an unloading update
    /// (every branch below its turning point) without the volumetric part.
    macro_rules! kernel {
        ($name:ident, $float:ty, $nn:ident, $mn:ident, $kn:ident, $weighted:ident) => {
            #[target_feature(enable = "avx2,fma")]
            #[allow(clippy::needless_range_loop)]
            pub unsafe fn $name(
                c: &Planes,
                h: &[f32],
                strain: &Sym,
                psi: f64,
                f: f64,
                band: &CrackBand,
            ) -> Sym {
                type F = $float;
                let e_v = (strain[0] + strain[1] + strain[2]) / 3.0;
                let [e1, e2, e3, e4] = c.scales;
                let e5 = f * if e_v >= 0.0 { e3 } else { e3 - e4 * e_v };
                let peak = |law: &ExponentialLaw, scale: f64, c0: f64| {
                    let (e, s) = law.peak(scale, c0);
                    (e as F, s as F)
                };
                let tension = peak(&c.tension, f * e1, c.e_d0);
                let compression = peak(&c.compression, f * e2, c.e_d0);
                let shear = peak(&c.shear, e5, c.e_t0);
                let monotonic = c.e_t0
                    * e5
                    * e5
                    * (c.shear.area_before_peak + c.shear.area_after_peak / band.shear);
                let (e_d0, e_t0) = (c.e_d0 as F, c.e_t0 as F);
                let (alpha, beta) = (c.alpha as F, c.beta as F);
                let q = |i: usize| &h[i * LANES_PLANES..(i + 1) * LANES_PLANES];
                let e: [F; 6] = std::array::from_fn(|i| strain[i] as F);
                let (e_v, psi) = (e_v as F, psi as F);
                let project = |t: &[[F; LANES_PLANES]; 6], p: usize| -> F {
                    t[0][p] * e[0]
                        + t[1][p] * e[1]
                        + t[2][p] * e[2]
                        + 2.0 * (t[3][p] * e[3] + t[4][p] * e[4] + t[5][p] * e[5])
                };
                let mut components = [[0.0 as F; LANES_PLANES]; 3];
                let (de, ds, ne, ns) = (q(0), q(1), q(2), q(3));
                for p in 0..LANES_PLANES {
                    let total = project(&c.$nn, p) - e_v;
                    let e_d = if total < 0.0 { total * psi } else { total };
                    let positive = e_d >= 0.0;
                    let (er, sr) = if positive {
                        (de[p] as F, ds[p] as F)
                    } else {
                        (ne[p] as F, ns[p] as F)
                    };
                    let (ep, sp) = if positive { tension } else { compression };
                    let modulus = modulus!(er, sr, e_d0, ep, sp, alpha, beta);
                    let s = (sr - modulus * (er - e_d.abs())).max(0.0);
                    components[0][p] = if positive { s } else { -s };
                }
                for (k, tensor, base) in [(1, &c.$mn, state::M), (2, &c.$kn, state::K)] {
                    let (pe, ps, me, ms) = (q(base), q(base + 1), q(base + 2), q(base + 3));
                    for p in 0..LANES_PLANES {
                        let strain = project(tensor, p) * psi;
                        let positive = strain >= 0.0;
                        let (er, sr) = if positive {
                            (pe[p] as F, ps[p] as F)
                        } else {
                            (me[p] as F, ms[p] as F)
                        };
                        let modulus = modulus!(er, sr, e_t0, shear.0, shear.1, alpha, beta);
                        let s = (sr - modulus * (er - strain.abs())).max(0.0);
                        // The sign of the strain, as `shear_stress` gives it (a crack's `-0.0`
                        // takes the positive branch and the negative sign).
                        components[k][p] = s.copysign(strain);
                    }
                    let lambda = q(base + 4);
                    for p in 0..LANES_PLANES {
                        if lambda[p] > 0.0 {
                            components[k][p] *= c.damage.eval(lambda[p] as f64 / monotonic) as F;
                        }
                    }
                }
                let mut sigma = [[0.0 as F; 8]; 6];
                for start in (0..LANES_PLANES).step_by(8) {
                    for lane in 0..8 {
                        let p = start + lane;
                        for i in 0..6 {
                            for k in 0..3 {
                                sigma[i][lane] += components[k][p] * c.$weighted[k][i][p];
                            }
                        }
                    }
                }
                std::array::from_fn(|i| sigma[i].iter().map(|&v| v as f64).sum())
            }
        };
    }

    kernel!(planes_f64, f64, nn, mn, kn, weighted);
    kernel!(planes_f32, f32, nn32, mn32, kn32, weighted32);

    /// Checks and times the two prototypes against the production update on `unloading`
    /// (index, production stress, `psi`, rate factor).
    pub fn compare(
        model: &MicroplaneConcrete,
        parameters: &MicroplaneParameters,
        updates: &[Update],
        unloading: &[(usize, Sym, f64, f64)],
    ) {
        let c = Planes::new(model, parameters);
        let planes = model.planes().len();
        let laid_out: Vec<Vec<f32>> = unloading
            .iter()
            .map(|&(i, ..)| per_quantity(&updates[i].history, planes))
            .collect();
        let (mut isotropic, mut single): (f64, f64) = (0.0, 0.0);
        for (&(i, stress, psi, f), h) in unloading.iter().zip(&laid_out) {
            let u = &updates[i];
            // SAFETY: the caller checked AVX2 and FMA.
            let (p64, p32) = unsafe {
                (
                    planes_f64(&c, h, &u.strain, psi, f, &u.band),
                    planes_f32(&c, h, &u.strain, psi, f, &u.band),
                )
            };
            let scale = stress.iter().fold(1e3f64, |a, v| a.max(v.abs()));
            let d: Vec<f64> = (0..6).map(|k| stress[k] - p64[k]).collect();
            let off = [d[3], d[4], d[5], d[0] - d[1], d[0] - d[2]];
            isotropic = isotropic.max(off.iter().fold(0.0f64, |a, v| a.max(v.abs())) / scale);
            for k in 0..6 {
                single = single.max((p64[k] - p32[k]).abs() / scale);
            }
        }
        let time = |kernel: unsafe fn(&Planes, &[f32], &Sym, f64, f64, &CrackBand) -> Sym| {
            let mut best = f64::INFINITY;
            let mut sink = 0.0;
            for _ in 0..5 {
                let start = Instant::now();
                for (&(i, _, psi, f), h) in unloading.iter().zip(&laid_out) {
                    let u = &updates[i];
                    // SAFETY: the caller checked AVX2 and FMA.
                    sink += unsafe { kernel(&c, h, &u.strain, psi, f, &u.band) }[0];
                }
                best = best.min(start.elapsed().as_secs_f64() * 1e9 / unloading.len() as f64);
            }
            std::hint::black_box(sink);
            best
        };
        let order: Vec<usize> = unloading.iter().map(|u| u.0).collect();
        println!(
            "the {} unloading updates: production update (whole) {:.0} ns; plane work side by \
             side, f64 {:.0} ns, f32 {:.0} ns",
            unloading.len(),
            replay(model, updates, &order),
            time(planes_f64),
            time(planes_f32)
        );
        println!(
            "  production less the f64 planes, off its isotropic part: {isotropic:.1e} of the \
             stress; f32 planes against f64: {single:.1e} of the stress"
        );
    }
}
