//! The planes' dissipation is summed only where the dilatancy reads it (`dissipation.rs`): the
//! deferred count against the update that counts it in the plane loop of every update
//! (`MicroplaneConcrete::with_dissipation_always_counted`), bit for bit in stresses and
//! histories, on random strain walks and on monotonic paths in tension (where the sum is never
//! read) and in compression and shear (where the dilatant strain grows and the sum caps it).
#![allow(clippy::unwrap_used)]

mod common;

use common::{assert_same_updates, strain_walk, thesis_concrete};
use impact_solver::material::microplane::{state, MicroplaneConcrete, SphereRule, Sym};
use impact_solver::rng::SplitMix64;

/// Runs `path` through the deferred count and the count in every update, asserting equal bits
/// at every step; returns the dilatant strain reached.
fn compare(deferred: &MicroplaneConcrete, path: &[(Sym, f64)], h: f64, label: &str) -> f64 {
    let always = deferred.clone().with_dissipation_always_counted();
    assert_same_updates(deferred, &always, path, h, label)[state::DILATANCY] as f64
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
            let path = strain_walk(&mut rng, 80, reach, drift);
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
