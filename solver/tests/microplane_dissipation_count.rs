//! The planes' dissipation is summed only where the dilatancy reads it (`dissipation.rs`): the
//! deferred count against the update that counts it in the plane loop of every update
//! (`MicroplaneConcrete::with_dissipation_always_counted`), bit for bit in stresses and
//! histories, on random strain walks and on monotonic paths in tension (where the sum is never
//! read) and in compression and shear (where the dilatant strain grows and the sum caps it).
#![allow(clippy::unwrap_used)]

mod common;

use common::thesis_concrete;
use impact_solver::material::microplane::{state, MicroplaneConcrete, SphereRule, Sym};
use impact_solver::rng::SplitMix64;

/// A random walk of `steps` strain increments of up to `reach` per component from zero, with a
/// drift `drift` per step added to every component (negative: towards compression), each step's
/// rate drawn from 1e-5 to 1e2 /s on a log scale.
fn walk(rng: &mut SplitMix64, steps: usize, reach: f64, drift: Sym) -> Vec<(Sym, f64)> {
    let mut strain = [0.0; 6];
    (0..steps)
        .map(|_| {
            for (e, d) in strain.iter_mut().zip(drift) {
                *e += d + rng.uniform(-reach, reach) / (steps as f64).sqrt();
            }
            (strain, 10f64.powf(rng.uniform(-5.0, 2.0)))
        })
        .collect()
}

/// Runs `path` through both models from the virgin state, asserting equal bits at every step;
/// returns the dilatant strain reached.
fn compare(deferred: &MicroplaneConcrete, path: &[(Sym, f64)], h: f64, label: &str) -> f64 {
    let always = deferred.clone().with_dissipation_always_counted();
    let band = deferred.crack_band(h).unwrap();
    let mut a = deferred.initial_state().values;
    let mut b = a.clone();
    for (step, (strain, rate)) in path.iter().enumerate() {
        let (sa, _) = deferred.update(&mut a, strain, *rate, &band);
        let (sb, _) = always.update(&mut b, strain, *rate, &band);
        let bits = |s: &Sym| s.map(f64::to_bits);
        assert_eq!(
            bits(&sa),
            bits(&sb),
            "{label} step {step}: {sa:?} vs {sb:?}"
        );
        let history_bits = |h: &[f32]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            history_bits(&a),
            history_bits(&b),
            "{label} step {step}: histories differ"
        );
    }
    a[state::DILATANCY] as f64
}

#[test]
fn deferred_count_gives_the_bits_of_counting_always() {
    for rule in [SphereRule::BazantOh21, SphereRule::Bazant37] {
        let mut parameters = thesis_concrete();
        parameters.rule = rule;
        assert!(parameters.dilatancy > 0.0, "the thesis concrete dilates");
        let model = MicroplaneConcrete::new(parameters).unwrap();
        let mut rng = SplitMix64::new(7);
        let mut grown = 0;
        for w in 0..90 {
            let reach = [2e-6, 2e-5, 1e-4, 6e-4, 3e-3][w % 5];
            let drift = match w % 3 {
                0 => [0.0; 6],
                // Uniaxial-like compression with shear, and tension: where the sum is read and where it is not.
                1 => [-2e-5, 4e-6, 4e-6, 3e-6, 0.0, 0.0],
                _ => [1e-5, -2e-6, -2e-6, 0.0, 2e-6, 0.0],
            };
            let path = walk(&mut rng, 80, reach, drift);
            let h = [0.025, 0.05, 0.1][w % 3];
            let dilatancy = compare(&model, &path, h, &format!("{rule:?} walk {w}"));
            grown += usize::from(dilatancy > 0.0);
        }
        // Monotonic ramps: tension (the sum is never read), confined and
        // unconfined compression past the peak (the dilatant strain grows under pressure).
        for (name, rate) in [
            ("uniaxial tension", [1.0, -0.18, -0.18, 0.0, 0.0, 0.0]),
            ("uniaxial compression", [-1.0, 0.3, 0.3, 0.0, 0.0, 0.0]),
            ("confined shear", [-0.5, -0.5, -0.5, 1.0, 0.0, 0.0]),
        ] {
            let path: Vec<(Sym, f64)> = (1..=400)
                .map(|i| (rate.map(|r| r * 1e-5 * i as f64), 1e-3))
                .collect();
            let dilatancy = compare(&model, &path, 0.05, &format!("{rule:?} {name}"));
            grown += usize::from(dilatancy > 0.0);
        }
        assert!(
            grown >= 20,
            "{rule:?}: the dilatant strain grew on {grown} paths only"
        );
    }
}
