//! Crack friction (`docs/MICROPLANE.md` "Crack friction"): Coulomb sliders on the microplanes'
//! shear once their laws have softened, bounded by a coefficient times the plane's compressive
//! normal stress (the frictional shear boundary of M4, Bažant et al. 2000).
//!
//! The reference is the homogenisation itself, not the code's output: at a large shear strain
//! `g E_hat` under held compression every plane's shear laws have softened to nothing, its
//! normal stress is the mean stress `-p`, and its slider, loaded along the plane's shear strain,
//! carries `mu p` along it. The homogenised shear stress (5.36) is then
//! `sigma : E_hat = mu p 6 sum_planes w |E_hat n - (n . E_hat n) n|`, a sum over the rule's
//! directions computed here from the planes alone.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

/// The shipped material `cases/materials/<name>.yaml`, quasi-static.
fn concrete(name: &str) -> MicroplaneParameters {
    MicroplaneParameters {
        rate_effect: None,
        ..common::shipped_concrete(name)
    }
}

/// The thesis concrete with the given crack friction.
fn thesis_concrete(crack_friction: Option<f64>) -> MicroplaneParameters {
    MicroplaneParameters {
        crack_friction,
        ..concrete("thesis-concrete")
    }
}

/// All normal strains held at `-c`, then the shear `E_12` raised to `g`: the last shear stress
/// `S_12` and mean pressure `-tr(S)/3` (Pa), at the calibration size h_ref.
fn shear_under_held_compression(model: &MicroplaneConcrete, c: f64, g: f64) -> (f64, f64) {
    let mut point = MaterialPoint::new(model, model.parameters.h_ref).unwrap();
    let n = 200;
    for i in 1..=n {
        let e = -c * i as f64 / n as f64;
        point.strain_step([e, e, e, 0.0, 0.0, 0.0], 1.0);
    }
    let steps = 4000;
    let mut last = None;
    for i in 1..=steps {
        let q = point.strain_step([-c, -c, -c, 0.0, 0.0, g * i as f64 / steps as f64], 1.0);
        last = Some(q);
    }
    let s = last.unwrap().stress;
    (s[5], -(s[0] + s[1] + s[2]) / 3.0)
}

/// `6 sum_planes w |E_hat n - (n . E_hat n) n|` for `E_hat = sym(e_1 (x) e_2)`: the homogenised
/// shear stress per unit of plane shear traction along each plane's shear strain.
fn friction_factor(model: &MicroplaneConcrete) -> f64 {
    model
        .planes()
        .iter()
        .map(|plane| {
            let [n1, n2, n3] = plane.normal;
            let e_n = [0.5 * n2, 0.5 * n1, 0.0];
            let normal = n1 * n2;
            let t = [
                e_n[0] - normal * n1,
                e_n[1] - normal * n2,
                e_n[2] - normal * n3,
            ];
            6.0 * plane.weight * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt()
        })
        .sum()
}

/// Without friction the thesis' shear laws soften to nothing at any pressure (the material
/// point becomes a fluid: this is why a nail met almost no resistance); with it the shear
/// stress levels at the homogenised Coulomb limit, growing with the pressure.
#[test]
fn friction_holds_the_shear_of_crushed_concrete_at_its_coulomb_limit() {
    let thesis = MicroplaneConcrete::new(thesis_concrete(None)).unwrap();
    let mu = 0.73;
    let friction = MicroplaneConcrete::new(thesis_concrete(Some(mu))).unwrap();
    let factor = friction_factor(&friction);
    for c in [0.005, 0.02] {
        let (shear, pressure) = shear_under_held_compression(&thesis, c, 0.5);
        assert!(
            shear.abs() < 1e-3 * pressure,
            "c = {c}: the thesis' laws keep {shear:.3e} Pa of shear at {pressure:.3e} Pa"
        );
        let (shear, pressure) = shear_under_held_compression(&friction, c, 0.5);
        let limit = mu * pressure * factor;
        assert!(
            (shear - limit).abs() < 0.02 * limit,
            "c = {c}: shear {shear:.4e} Pa against the Coulomb limit {limit:.4e} Pa \
             (mu {mu}, pressure {pressure:.4e} Pa, factor {factor:.4})"
        );
    }
}

/// Before any law softens the sliders carry no more than the laws: the elastic response is the
/// thesis' to the last bit.
#[test]
fn friction_leaves_the_elastic_range_alone() {
    let thesis = MicroplaneConcrete::new(thesis_concrete(None)).unwrap();
    let friction = MicroplaneConcrete::new(thesis_concrete(Some(0.73))).unwrap();
    let strain = [-2e-5, 1e-5, 3e-6, 4e-6, -7e-6, 1.2e-5];
    let mut a = MaterialPoint::new(&thesis, 0.05).unwrap();
    let mut b = MaterialPoint::new(&friction, 0.05).unwrap();
    for i in 1..=20 {
        let e = strain.map(|x| x * i as f64 / 20.0);
        let (sa, sb) = (a.strain_step(e, 1.0).stress, b.strain_step(e, 1.0).stress);
        assert_eq!(sa, sb, "increment {i}");
    }
}

/// Friction raises the strength wherever planes past their peak are compressed: the thesis
/// concrete with it goes from an equal-biaxial ratio of 1.16 to 1.38 (target 1.1-1.25). The
/// concrete refitted around it (`thesis-concrete-crack-friction.yaml`) meets every target of the
/// thesis concrete again.
#[test]
fn the_concrete_refitted_with_friction_meets_the_thesis_targets() {
    use impact_solver::material::microplane::calibration::{Evaluation, Targets};
    let targets = Targets::thesis_concrete();
    let refitted = concrete("thesis-concrete-crack-friction");
    assert_eq!(refitted.crack_friction, Some(0.73));
    let evaluation = Evaluation::of(&refitted, &targets).unwrap();
    let missed: Vec<String> = evaluation
        .outcomes(&targets)
        .into_iter()
        .filter(|o| !o.met)
        .map(|o| {
            format!(
                "{}: {} {} (target {})",
                o.name, o.achieved, o.unit, o.target
            )
        })
        .collect();
    assert!(missed.is_empty(), "missed: {missed:#?}");
}

/// A scene sets the friction beside the parameter file (`crack_friction:` in
/// `material.microplane`); a coefficient that is not positive is refused by name.
#[test]
fn a_scene_sets_the_friction_and_a_bad_one_is_refused() {
    use impact_solver::material::MaterialModel;
    use impact_solver::scene::MaterialSpec;
    let file = format!(
        "{}/../cases/materials/thesis-concrete.yaml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = format!("microplane: {{ file: {file}, crack_friction: 0.5 }}");
    let spec: MaterialSpec = serde_norway::with::singleton_map_recursive::deserialize(
        serde_norway::Deserializer::from_str(&text),
    )
    .unwrap();
    let MaterialModel::Microplane(parameters) = spec.model("block").unwrap() else {
        panic!("a microplane body");
    };
    assert_eq!(parameters.crack_friction, Some(0.5));
    let bad = MicroplaneParameters {
        crack_friction: Some(0.0),
        ..parameters
    };
    let message = MicroplaneConcrete::new(bad).err().unwrap().to_string();
    assert!(message.contains("crack_friction"), "{message}");
}
