//! The tensile-stress relaxation (`RelaxationDriver::TensileStress`, docs/MICROPLANE.md "Tension
//! under lateral compression"): compression alone never opens the element, a lateral
//! compression lowers the tensile peak instead of raising it, and in uniaxial stress the driver
//! is the thesis' `e_V` up to the opening.
#![allow(clippy::unwrap_used)]

mod common;

use common::shipped_concrete;
use impact_solver::material::microplane::experiments::{
    equal_biaxial_compression, tension_under_lateral_stress, uniaxial_compression,
};
use impact_solver::material::microplane::{
    state, MicroplaneConcrete, MicroplaneParameters, RelaxationDriver,
};

fn tensile_relaxation_concrete() -> MicroplaneParameters {
    let p = shipped_concrete("thesis-concrete-tensile-relaxation");
    assert_eq!(p.relaxation_driver, RelaxationDriver::TensileStress);
    p
}

/// Under uniaxial and equal-biaxial compression past the peak the lateral stress is zero, so
/// nothing opens the element, however far the compressed concrete expands laterally (its
/// apparent Poisson ratio passes 0.5 after the peak): the relaxation stays where the thesis'
/// `e_V` puts it. Checked through the model's own state on the calibration's paths.
#[test]
fn compression_alone_does_not_open_the_element() {
    let model = MicroplaneConcrete::new(tensile_relaxation_concrete()).unwrap();
    let thesis = MicroplaneConcrete::new(MicroplaneParameters {
        relaxation_driver: RelaxationDriver::Volumetric,
        ..tensile_relaxation_concrete()
    })
    .unwrap();
    for (name, tensile, volumetric) in [
        (
            "uniaxial",
            uniaxial_compression(&model, 0.05, 1e-8, 6e-3, 600)
                .unwrap()
                .0,
            uniaxial_compression(&thesis, 0.05, 1e-8, 6e-3, 600)
                .unwrap()
                .0,
        ),
        (
            "equal biaxial",
            equal_biaxial_compression(&model, 0.05, 6e-3, 600)
                .unwrap()
                .0,
            equal_biaxial_compression(&thesis, 0.05, 6e-3, 600)
                .unwrap()
                .0,
        ),
    ] {
        // The driver's lateral stress is zero to its tolerance, so any opening is rounding-sized
        // and the two relaxations give the same curve to far below a per mille of the peak.
        let peak = tensile.peak().stress[0].abs();
        for (a, b) in tensile.points.iter().zip(&volumetric.points) {
            assert!(
                (a.stress[0] - b.stress[0]).abs() < 1e-4 * peak,
                "{name} at E_11 = {:.3e}: {} against {}",
                a.strain[0],
                a.stress[0],
                b.stress[0]
            );
        }
    }
}

/// The element remembers the largest opening `o(s_I)` it reached: zero while compressed, and 1
/// once its largest principal stress has reached `|s_I,min|` (= `f_t` here).
#[test]
fn the_opening_is_remembered() {
    let model = MicroplaneConcrete::new(tensile_relaxation_concrete()).unwrap();
    let band = model.crack_band(0.05).unwrap();
    let mut state = model.initial_state();
    let e = model.parameters.youngs_modulus;
    let nu = model.parameters.poisson_ratio;
    // Uniaxial compression at 10 MPa: no tensile stress, no opening.
    let s = -10e6 / e;
    model.update(
        &mut state.values,
        &[s, -nu * s, -nu * s, 0.0, 0.0, 0.0],
        0.0,
        &band,
    );
    assert_eq!(state.values[state::OPENING], 0.0);
    // Uniaxial tension past the peak: open; back to zero strain: still open.
    for k in 1..=40 {
        let x = 4e-6 * f64::from(k);
        model.update(
            &mut state.values,
            &[x, -nu * x, -nu * x, 0.0, 0.0, 0.0],
            0.0,
            &band,
        );
    }
    assert_eq!(state.values[state::OPENING], 1.0);
    model.update(&mut state.values, &[0.0; 6], 0.0, &band);
    assert_eq!(state.values[state::OPENING], 1.0);
}

/// Kupfer, Hilsdorf & Rüsch (1969): a lateral compression lowers concrete's tensile strength
/// (Kupfer & Gerstle 1973: `1 + 0.8 sigma_2 / f_c`). With the tensile-stress relaxation the peak
/// falls monotonically with the lateral compression and stays below the uniaxial one; with the
/// thesis' relaxation it rises (docs/MICROPLANE.md: 1.45 times at `sigma_2 = -f_t`).
#[test]
fn a_lateral_compression_lowers_the_tensile_peak() {
    let peaks = |p: MicroplaneParameters| -> Vec<f64> {
        let model = MicroplaneConcrete::new(p).unwrap();
        [0.0, -1.35e6, -2.7e6, -5.4e6]
            .iter()
            .map(|&s| {
                let curve = tension_under_lateral_stress(&model, 0.05, s, 8e-4, 400).unwrap();
                curve.peak().stress[0]
            })
            .collect()
    };
    let tensile = peaks(tensile_relaxation_concrete());
    for pair in tensile.windows(2) {
        assert!(pair[1] < pair[0], "peaks {tensile:?} do not fall");
    }
    let thesis = peaks(MicroplaneParameters {
        relaxation_driver: RelaxationDriver::Volumetric,
        ..tensile_relaxation_concrete()
    });
    assert!(
        thesis[2] > 1.2 * thesis[0],
        "the thesis' relaxation no longer strengthens: {thesis:?}"
    );
}
