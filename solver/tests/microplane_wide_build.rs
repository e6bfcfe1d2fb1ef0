//! The AVX2 build of the microplane update (`MicroplaneConcrete::update` on a processor with AVX2
//! and FMA) against its portable build (`MicroplaneConcrete::with_portable_code`): the same
//! stresses and the same histories, bit for bit, along random strain walks that visit every
//! branch (virgin loading, unloading, softening in tension, compression and shear, crack closure)
//! at rates from quasi-static to impact. The runs of the solver are bitwise the same on every
//! x86-64 processor only if this holds.
#![allow(clippy::unwrap_used)]

mod common;

use common::{assert_same_updates, strain_walk, thesis_concrete};
use impact_solver::material::microplane::{MicroplaneConcrete, SphereRule};
use impact_solver::rng::SplitMix64;

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
            let path = strain_walk(&mut rng, 80, reach, [0.0; 6]);
            let label = format!("{rule:?} walk {walk_index}");
            assert_same_updates(&wide, &portable, &path, h, &label);
            updates += path.len();
        }
        assert_eq!(updates, 60 * 80);
    }
}
