//! The plane work of the 21-direction rule with the planes side by side (`side_by_side.rs`)
//! against the same update with the planes one by one
//! (`MicroplaneConcrete::with_planes_one_by_one`): the same stresses and the same histories, bit
//! for bit, along random strain walks that visit every branch (virgin loading, unloading,
//! softening in tension with the Hordijk tail, compression and shear, the cyclic shear damage,
//! crack closure) at rates from quasi-static to impact, for each shipped concrete the kernel
//! serves (crack friction among them) and in both builds (AVX2 and portable).
#![allow(clippy::unwrap_used)]

mod common;

use common::{assert_same_updates, shipped_concrete, strain_walk, thesis_concrete};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters, Sym};
use impact_solver::rng::SplitMix64;

/// Walks and monotonic ramps through `model` side by side and one by one.
fn compare(model: &MicroplaneConcrete, name: &str) {
    assert!(model.runs_planes_side_by_side(), "{name}: 21 planes");
    let reference = model.clone().with_planes_one_by_one();
    assert!(!reference.runs_planes_side_by_side());
    let mut rng = SplitMix64::new(71);
    for w in 0..60 {
        let reach = [2e-6, 2e-5, 1e-4, 6e-4, 3e-3][w % 5];
        let drift = match w % 3 {
            0 => [0.0; 6],
            1 => [-2e-5, 4e-6, 4e-6, 3e-6, 0.0, 0.0],
            _ => [1e-5, -2e-6, -2e-6, 0.0, 2e-6, 0.0],
        };
        let path = strain_walk(&mut rng, 80, reach, drift);
        // Element sizes around the calibration's, where every crack band exists.
        let h = [0.5, 1.0, 1.5][w % 3] * model.parameters.h_ref;
        assert_same_updates(model, &reference, &path, h, &format!("{name} walk {w}"));
    }
    for (ramp, rate) in [
        ("uniaxial tension", [1.0, -0.18, -0.18, 0.0, 0.0, 0.0]),
        ("uniaxial compression", [-1.0, 0.3, 0.3, 0.0, 0.0, 0.0]),
        ("confined shear", [-0.5, -0.5, -0.5, 1.0, 0.0, 0.0]),
        ("shear reversals", [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
    ] {
        // Out to 4e-3 and, for the reversals, back and forth across zero.
        let path: Vec<(Sym, f64)> = (1..=400)
            .map(|i| {
                let s = if ramp == "shear reversals" {
                    ((i as f64) * 0.05).sin() * (i as f64) / 400.0 * 4e-3
                } else {
                    1e-5 * i as f64
                };
                (rate.map(|r| r * s), 1e-3)
            })
            .collect();
        let h = model.parameters.h_ref;
        assert_same_updates(model, &reference, &path, h, &format!("{name} {ramp}"));
    }
}

fn concretes() -> Vec<(&'static str, MicroplaneParameters)> {
    let mut out = vec![("thesis concrete", thesis_concrete())];
    for name in [
        "thesis-concrete-crack-friction",
        "thesis-concrete-tensile-relaxation",
        "gregoire-2013-concrete",
    ] {
        out.push((name, shipped_concrete(name)));
    }
    let mut exponential = thesis_concrete();
    exponential.hordijk_tail = 0.0;
    exponential.shear_cyclic_damage = false;
    exponential.dilatancy = 0.0;
    out.push(("exponential softening, no cyclic damage", exponential));
    out
}

#[test]
fn side_by_side_gives_the_bits_of_one_by_one() {
    for (name, parameters) in concretes() {
        compare(&MicroplaneConcrete::new(parameters).unwrap(), name);
    }
}

#[test]
fn portable_side_by_side_gives_the_bits_of_one_by_one() {
    for (name, parameters) in concretes() {
        let model = MicroplaneConcrete::new(parameters)
            .unwrap()
            .with_portable_code();
        compare(&model, &format!("{name}, portable build"));
    }
}

#[test]
fn exact_laws_side_by_side_give_the_bits_of_one_by_one() {
    let model = MicroplaneConcrete::new(thesis_concrete())
        .unwrap()
        .with_exact_laws();
    compare(&model, "thesis concrete, exact laws");
}
