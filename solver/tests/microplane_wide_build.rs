//! The AVX2 build of the microplane update (`MicroplaneConcrete::update` on a processor with AVX2
//! and FMA) against its portable build (`MicroplaneConcrete::with_portable_code`): the same
//! stresses and the same histories, bit for bit, along random strain walks that visit every
//! branch (virgin loading, unloading, softening in tension, compression and shear, crack closure)
//! at rates from quasi-static to impact. The runs of the solver are bitwise the same on every
//! x86-64 processor only if this holds.
#![allow(clippy::unwrap_used)]

mod common;

use common::thesis_concrete;
use impact_solver::material::microplane::{MicroplaneConcrete, SphereRule, Sym};
use impact_solver::rng::SplitMix64;

/// A random walk of `steps` strain increments of up to `reach` per component from zero, each
/// step's rate drawn from 1e-5 to 1e2 /s on a log scale: `(strain, rate)` per step.
fn random_walk(rng: &mut SplitMix64, steps: usize, reach: f64) -> Vec<(Sym, f64)> {
    let mut strain = [0.0; 6];
    let mut walk = Vec::with_capacity(steps);
    for _ in 0..steps {
        for e in &mut strain {
            *e += rng.uniform(-reach, reach) / (steps as f64).sqrt();
        }
        let rate = 10f64.powf(rng.uniform(-5.0, 2.0));
        walk.push((strain, rate));
    }
    walk
}

#[test]
fn wide_build_gives_the_portable_builds_bits() {
    for rule in [SphereRule::BazantOh21, SphereRule::Bazant37] {
        let mut parameters = thesis_concrete();
        parameters.rule = rule;
        let wide = MicroplaneConcrete::new(parameters).unwrap();
        if !wide.runs_wide_vectors() {
            eprintln!("skipped: this processor has no AVX2 and FMA, only the portable build runs");
            return;
        }
        let portable = wide.clone().with_portable_code();
        let mut rng = SplitMix64::new(20);
        let mut updates = 0;
        for walk_index in 0..60 {
            // Reaches from well inside the elastic range to ten times the tensile peak strain.
            let reach = [2e-6, 2e-5, 1e-4, 6e-4, 3e-3][walk_index % 5];
            let h = [0.025, 0.05, 0.1][walk_index % 3];
            let band = wide.crack_band(h).unwrap();
            let mut a = wide.initial_state().values;
            let mut b = a.clone();
            for (step, (strain, rate)) in random_walk(&mut rng, 80, reach).iter().enumerate() {
                let (sa, _) = wide.update(&mut a, strain, *rate, &band);
                let (sb, _) = portable.update(&mut b, strain, *rate, &band);
                let bits = |s: &Sym| s.map(f64::to_bits);
                assert_eq!(
                    bits(&sa),
                    bits(&sb),
                    "{rule:?} walk {walk_index} step {step}: {sa:?} vs {sb:?}"
                );
                let history_bits = |h: &[f32]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    history_bits(&a),
                    history_bits(&b),
                    "{rule:?} walk {walk_index} step {step}: histories differ"
                );
                updates += 1;
            }
        }
        assert_eq!(updates, 60 * 80);
    }
}
