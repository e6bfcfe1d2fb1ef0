//! The elastic path of the microplane update (`MicroplaneConcrete::update`) against the full
//! update over the planes (`MicroplaneConcrete::with_full_update`): on random strain states near
//! its limit the stresses agree to the `f32` rounding of the history, beyond the limit the path is
//! not taken, and along paths that start elastic and go on into softening the two stay together;
//! for the thesis concrete, the one with crack friction (whose sliders the elastic path leaves
//! untouched) and the one with the tensile-stress relaxation (whose crack opening both paths
//! advance).
#![allow(clippy::unwrap_used)]

mod common;

use common::{shipped_concrete, sym_norm, thesis_concrete};
use impact_solver::material::microplane::driver::{equivalent_rate, MaterialPoint};
use impact_solver::material::microplane::{state, MicroplaneConcrete, MicroplaneState, Sym};
use impact_solver::rng::SplitMix64;

/// The shipped concretes the elastic path serves: the thesis', the one with crack friction and
/// the one with the tensile-stress relaxation.
const CONCRETES: [&str; 3] = [
    "thesis-concrete",
    "thesis-concrete-crack-friction",
    "thesis-concrete-tensile-relaxation",
];

/// `f32` rounding: half an ulp at 1.
const F32_ROUNDING: f64 = 1.0 / (1u64 << 24) as f64;

/// A random strain whose deviator has Frobenius norm `size` and whose volumetric strain is
/// `volumetric`.
fn strain_with_deviator(rng: &mut SplitMix64, size: f64, volumetric: f64) -> Sym {
    let mut d: Sym = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
    let mean = (d[0] + d[1] + d[2]) / 3.0;
    for v in &mut d[..3] {
        *v -= mean;
    }
    let scale = size / sym_norm(&d);
    std::array::from_fn(|i| d[i] * scale + if i < 3 { volumetric } else { 0.0 })
}

#[test]
fn elastic_path_equals_the_full_update_to_f32_rounding() {
    for name in CONCRETES {
        elastic_path_equals_the_full_update_for(name);
    }
}

fn elastic_path_equals_the_full_update_for(name: &str) {
    let parameters = shipped_concrete(name);
    let fast = MicroplaneConcrete::new(parameters).unwrap();
    let full = fast.clone().with_full_update();
    let limit = fast.elastic_limit();
    let band = fast.crack_band(0.05).unwrap();
    let modulus = parameters.youngs_modulus;
    let mut rng = SplitMix64::new(17);
    let (mut taken, mut refused) = (0, 0);
    let mut worst: f64 = 0.0;
    for i in 0..4000 {
        // Deviators from half the limit to twice it, volumetric strains of either sign.
        let size = limit * rng.uniform(0.5, 2.0);
        let volumetric = limit * rng.uniform(-1.5, 1.5);
        let strain = strain_with_deviator(&mut rng, size, volumetric);
        let rate = if i % 2 == 0 {
            0.0
        } else {
            rng.uniform(0.0, 50.0)
        };
        let mut a = fast.initial_state();
        let mut b = full.initial_state();
        let (sa, _) = fast.update(&mut a.values, &strain, rate, &band);
        let (sb, _) = full.update(&mut b.values, &strain, rate, &band);
        let on_path = size <= limit && volumetric <= limit;
        if on_path {
            taken += 1;
            assert_eq!(a.values[state::ELASTIC_UPDATES], 1.0);
            assert_eq!(a.values[state::VIRGIN_PLANES], 1.0);
            // The scale of the stress: E |E|; the full update's plane laws differ from their
            // initial moduli by at most 2^-25, their f32 history by one rounding.
            let d: Sym = std::array::from_fn(|j| sa[j] - sb[j]);
            let relative = sym_norm(&d) / (modulus * sym_norm(&strain));
            worst = worst.max(relative);
            assert!(
                relative <= F32_ROUNDING,
                "elastic path off by {relative:.2e} of E|E| at {strain:?}"
            );
        } else {
            refused += 1;
            assert_eq!(a.values[state::ELASTIC_UPDATES], 0.0);
            assert_eq!(a.values[state::VIRGIN_PLANES], 0.0);
            assert_eq!(sa, sb, "beyond the limit the update is the full one");
            assert_eq!(a.values, b.values);
        }
    }
    eprintln!(
        "{name}: limit {limit:.3e}: {taken} states on the elastic path, largest difference \
         {worst:.2e} of E|E|; {refused} beyond it"
    );
    assert!(taken > 500 && refused > 500);
}

/// Paths that start on the elastic path and leave it into tensile and compressive softening and
/// shear cycles: the stresses of the two updates stay within `1e-6` of `max(|sigma|, f_t)`.
#[test]
fn paths_leaving_the_elastic_path_follow_the_full_update() {
    for name in CONCRETES {
        paths_leaving_the_elastic_path_follow_the_full_update_for(name);
    }
}

fn paths_leaving_the_elastic_path_follow_the_full_update_for(name: &str) {
    let parameters = shipped_concrete(name);
    let fast = MicroplaneConcrete::new(parameters).unwrap();
    let full = fast.clone().with_full_update();
    let limit = fast.elastic_limit();
    let mut rng = SplitMix64::new(5);
    for path in 0..40 {
        let mut a = MaterialPoint::new(&fast, 0.05).unwrap();
        let mut b = MaterialPoint::new(&full, 0.05).unwrap();
        // A wander below the limit, then a straight leg to a random strain of up to 4e-4
        // (tension, compression and shear past their peaks), and back halfway.
        let mut corners: Vec<Sym> = (0..3)
            .map(|_| {
                let volumetric = rng.uniform(-0.9, 0.9) * limit;
                strain_with_deviator(&mut rng, 0.9 * limit, volumetric)
            })
            .collect();
        let volumetric = rng.uniform(-1e-4, 1e-4);
        let far = strain_with_deviator(&mut rng, 4e-4, volumetric);
        corners.push(far);
        corners.push(far.map(|e| 0.5 * e));
        let mut from = a.strain;
        let mut worst: f64 = 0.0;
        for to in &corners {
            for i in 1..=100 {
                let t = i as f64 / 100.0;
                let strain: Sym = std::array::from_fn(|j| from[j] + t * (to[j] - from[j]));
                let dt = (equivalent_rate(&a.strain, &strain, 1.0) / 1.0).max(1e-9);
                let pa = a.strain_step(strain, dt);
                let pb = b.strain_step(strain, dt);
                let d: Sym = std::array::from_fn(|j| pa.stress[j] - pb.stress[j]);
                worst = worst.max(sym_norm(&d) / sym_norm(&pb.stress).max(2.7e6));
            }
            from = *to;
        }
        let elastic = a.state.elastic_updates();
        assert!(
            elastic >= 300.0,
            "{name} path {path}: {elastic} elastic updates"
        );
        assert!(
            worst < 1e-6,
            "{name} path {path}: stresses differ by {worst:.2e}"
        );
    }
}

#[test]
fn a_virgin_state_counts_no_elastic_update() {
    let model = MicroplaneConcrete::new(thesis_concrete()).unwrap();
    let state: MicroplaneState = model.initial_state();
    assert_eq!(state.elastic_updates(), 0.0);
    assert_eq!(state.values[state::VIRGIN_PLANES], 1.0);
    // The limit's defining property, checked with powf and exp: at the limit every virgin law's
    // secant factor exp(-(e / e_s)^m) rounds to 1 in f32, and at twice the limit the binding
    // law's (tension, e1 and m for this concrete) no longer does.
    let p = thesis_concrete();
    let limit = model.elastic_limit();
    let factor = |e: f64, scale: f64, m: f64| (-(e / scale).powf(m)).exp() as f32;
    for (scale, m) in [(p.e1, p.m), (p.e2, p.n), (p.e3, p.k)] {
        assert_eq!(
            factor(limit, scale, m),
            1.0,
            "scale {scale:e}, exponent {m}"
        );
    }
    assert!(factor(2.0 * limit, p.e1, p.m) < 1.0);
}
