//! The tabulated microplane update (`material/microplane/tabulated.rs`) against the same model
//! evaluating every law by `powf` and `exp` (`MicroplaneConcrete::with_exact_laws`): stresses
//! within `1e-6` of the exact update's along strain paths that visit every branch, and the
//! material-point experiments' strengths and fracture energies within `1e-6` relative.
#![allow(clippy::unwrap_used)]

mod common;

use common::{sym_norm, thesis_concrete};
use impact_solver::material::microplane::driver::{equivalent_rate, MaterialPoint};
use impact_solver::material::microplane::experiments::{
    bonded_tension, closed_strain_cycle, uniaxial_compression, uniaxial_tension,
};
use impact_solver::material::microplane::{MicroplaneConcrete, Sym};

/// Largest stress difference allowed, relative to the larger of the stress norm and `f_t`.
const RELATIVE: f64 = 1e-6;

/// A strain path through `corners` (straight legs of `steps` increments) at `rate`, run on both
/// models; returns the largest difference over `max(|sigma|, f_t)`.
fn path_difference(
    exact: &MicroplaneConcrete,
    tabulated: &MicroplaneConcrete,
    h: f64,
    corners: &[Sym],
    steps: usize,
    rate: f64,
) -> f64 {
    let mut a = MaterialPoint::new(exact, h).unwrap();
    let mut b = MaterialPoint::new(tabulated, h).unwrap();
    let scale = 2.7e6;
    let mut worst: f64 = 0.0;
    let mut from = [0.0; 6];
    for to in corners {
        for i in 1..=steps {
            let t = i as f64 / steps as f64;
            let strain: Sym = std::array::from_fn(|j| from[j] + t * (to[j] - from[j]));
            let dt = equivalent_rate(&a.strain, &strain, 1.0) / rate;
            let pa = a.strain_step(strain, dt.max(1e-12));
            let pb = b.strain_step(strain, dt.max(1e-12));
            let d: Sym = std::array::from_fn(|j| pa.stress[j] - pb.stress[j]);
            worst = worst.max(sym_norm(&d) / sym_norm(&pa.stress).max(scale));
        }
        from = *to;
    }
    worst
}

#[test]
fn tabulated_update_follows_the_exact_one_on_every_branch() {
    let parameters = thesis_concrete();
    let tabulated = MicroplaneConcrete::new(parameters).unwrap();
    let exact = tabulated.clone().with_exact_laws();
    let e = 1e-4;
    let paths: Vec<(&str, Vec<Sym>)> = vec![
        // Tension past the peak, unloading into compression, reloading past the first peak.
        (
            "uniaxial strain, tension-compression cycle",
            vec![
                [6.0 * e, 0.0, 0.0, 0.0, 0.0, 0.0],
                [-10.0 * e, 0.0, 0.0, 0.0, 0.0, 0.0],
                [12.0 * e, 0.0, 0.0, 0.0, 0.0, 0.0],
            ],
        ),
        // Compression past its peak with lateral expansion, then back.
        (
            "compression past the peak",
            vec![
                [-40.0 * e, 8.0 * e, 8.0 * e, 0.0, 0.0, 0.0],
                [-5.0 * e, e, e, 0.0, 0.0, 0.0],
            ],
        ),
        // Shear cycles: the cyclic damage (5.104) on both signs.
        (
            "shear cycles",
            vec![
                [0.0, 0.0, 0.0, 0.0, 0.0, 15.0 * e],
                [0.0, 0.0, 0.0, 0.0, 0.0, -15.0 * e],
                [0.0, 0.0, 0.0, 0.0, 0.0, 30.0 * e],
                [0.0, 0.0, 0.0, 0.0, 0.0, -30.0 * e],
            ],
        ),
        // A general rotating state with every component.
        (
            "mixed rotating strain",
            vec![
                [2.0 * e, -e, 0.5 * e, e, -0.5 * e, 0.7 * e],
                [-3.0 * e, 4.0 * e, -e, -2.0 * e, 1.5 * e, 0.3 * e],
                [5.0 * e, 2.0 * e, 3.0 * e, 0.5 * e, 2.0 * e, -e],
            ],
        ),
        // Hydrostatic compression into the stiffening range and back.
        (
            "hydrostatic",
            vec![
                [-100.0 * e, -100.0 * e, -100.0 * e, 0.0, 0.0, 0.0],
                [-20.0 * e, -20.0 * e, -20.0 * e, 0.0, 0.0, 0.0],
            ],
        ),
    ];
    for rate in [1e-5, 10.0] {
        for h in [0.025, 0.05] {
            for (name, corners) in &paths {
                let d = path_difference(&exact, &tabulated, h, corners, 200, rate);
                eprintln!("{name}, h = {h}, rate {rate}: largest difference {d:.2e}");
                assert!(d < RELATIVE, "{name}, h = {h}, rate {rate}: {d:.2e}");
            }
        }
    }
}

#[test]
fn tabulated_experiments_match_the_exact_ones() {
    let parameters = thesis_concrete();
    let tabulated = MicroplaneConcrete::new(parameters).unwrap();
    let exact = tabulated.clone().with_exact_laws();
    let close = |what: &str, a: f64, b: f64| {
        let r = (a - b).abs() / a.abs();
        eprintln!("{what}: exact {a:.9e}, tabulated {b:.9e}, relative {r:.2e}");
        assert!(r < RELATIVE, "{what}: {a} against {b}");
    };
    for h in [0.025, 0.05, 0.1] {
        let (_, a) = uniaxial_tension(&exact, h, 1e-5).unwrap();
        let (_, b) = uniaxial_tension(&tabulated, h, 1e-5).unwrap();
        close(&format!("f_t, h = {h}"), a.peak_stress, b.peak_stress);
        let (_, a) = bonded_tension(&exact, h, 1e-5).unwrap();
        let (_, b) = bonded_tension(&tabulated, h, 1e-5).unwrap();
        close(
            &format!("G_F bonded, h = {h}"),
            a.fracture_energy,
            b.fracture_energy,
        );
    }
    let (_, a) = uniaxial_compression(&exact, 0.05, 1e-5, 4e-3, 200).unwrap();
    let (_, b) = uniaxial_compression(&tabulated, 0.05, 1e-5, 4e-3, 200).unwrap();
    close("f_c", a.peak_stress, b.peak_stress);
    close("eps_c", a.peak_strain, b.peak_strain);
    let corners = [
        [2e-4, 0.0, 0.0, 0.0, 1e-4, 0.0],
        [-3e-4, 1e-4, 0.0, 0.0, -1e-4, 0.0],
    ];
    let (_, a, _) = closed_strain_cycle(&exact, 0.05, &corners, 100).unwrap();
    let (_, b, _) = closed_strain_cycle(&tabulated, 0.05, &corners, 100).unwrap();
    close("dissipation of a closed cycle", a, b);
}
