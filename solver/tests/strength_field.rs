//! The seeded strength field (`material/strength_field.rs`): an element of strength `s` peaks at
//! about `s` times the material's tensile strength and still dissipates the calibrated fracture
//! energy per unit crack area; a body's elements take the field at their centroids, and a scene
//! with the field runs the same bits on any thread count.
#![allow(clippy::unwrap_used)]

mod common;

use common::shipped_concrete;
use impact_solver::material::microplane::experiments::bonded_tension_with_strength;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};
use impact_solver::material::{MicroplaneMaterial, StrengthField, StrengthFieldSpec};

const QUASI_STATIC: f64 = 1e-6;

fn field_spec(seed: u64) -> StrengthFieldSpec {
    StrengthFieldSpec {
        coefficient_of_variation: 0.15,
        correlation_length: 0.1,
        seed,
    }
}

/// The element's tension law is scaled by `s` and its band refitted: the peak follows `s` and
/// the energy per unit crack area stays the material's. The peak is not exactly `s` times,
/// because the shear planes, whose laws the field leaves alone, carry part of the tension
/// (docs/MICROPLANE.md "Tension under lateral compression"); the bound states how far.
#[test]
fn element_strength_scales_the_peak_and_keeps_the_fracture_energy() {
    let model = MicroplaneConcrete::new(shipped_concrete("thesis-concrete")).unwrap();
    let h = 0.05;
    let (_, base) = bonded_tension_with_strength(&model, h, QUASI_STATIC, 1.0).unwrap();
    for s in [0.7, 0.85, 1.2, 1.4] {
        let (_, r) = bonded_tension_with_strength(&model, h, QUASI_STATIC, s).unwrap();
        let peak_ratio = r.peak_stress / base.peak_stress;
        let energy_ratio = r.fracture_energy / base.fracture_energy;
        println!("s {s}: peak ratio {peak_ratio:.4}, energy ratio {energy_ratio:.4}");
        assert!(
            (peak_ratio / s - 1.0).abs() < 0.05,
            "s = {s}: peak {peak_ratio} of the material's"
        );
        assert!(
            (energy_ratio - 1.0).abs() < 0.03,
            "s = {s}: fracture energy {energy_ratio} of the material's"
        );
    }
}

/// A strong element too large for its refitted band is refused with a message that names the
/// field.
#[test]
fn an_element_too_large_for_its_strength_is_refused() {
    let model = MicroplaneConcrete::new(shipped_concrete("thesis-concrete")).unwrap();
    // The shear law may bound the size before the tension law does: an element of half the
    // largest size is admitted, and three times stronger its band would be that of an element
    // 4.5 times the largest.
    let h = 0.5 * model.largest_element();
    assert!(model.crack_band_with_strength(h, 1.0).is_ok());
    let message = model
        .crack_band_with_strength(h, 3.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("strength_field"), "{message}");
}

/// A body's element takes the field at its reference centroid, and the field's sample over the
/// elements has about the mean and scatter asked for.
#[test]
fn a_body_takes_the_field_at_its_element_centroids() {
    let parameters = MicroplaneParameters {
        strength_field: Some(field_spec(3)),
        ..shipped_concrete("thesis-concrete")
    };
    // A 1 m cube of 20 mm cells: 50 correlation lengths of volume, sampled at 125 000 points.
    let n = 50;
    let centroids: Vec<[f64; 3]> = (0..n * n * n)
        .map(|i| {
            let (a, b, c) = (i % n, (i / n) % n, i / (n * n));
            [a, b, c].map(|k| (k as f64 + 0.5) * 0.02)
        })
        .collect();
    let volumes = vec![0.02f64.powi(3) / 6.0; centroids.len()];
    let material = MicroplaneMaterial::new("block", parameters, &volumes, &centroids, 0).unwrap();
    let field = StrengthField::new(&field_spec(3)).unwrap();
    for (band, x) in material.bands.iter().zip(&centroids).step_by(997) {
        assert_eq!(band.strength.to_bits(), field.factor(*x).to_bits());
    }
    let s: Vec<f64> = material.bands.iter().map(|b| b.strength).collect();
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    let sd = (s.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / s.len() as f64).sqrt();
    println!("mean {mean:.4}, coefficient of variation {:.4}", sd / mean);
    // One realisation over 10 correlation lengths a side: the sample statistics scatter by a
    // few per cent of the ensemble's.
    assert!((mean - 1.0).abs() < 0.05, "mean {mean}");
    assert!(
        (sd / mean - 0.15).abs() < 0.05,
        "coefficient of variation {}",
        sd / mean
    );
}

/// The field frame for ParaView carries the strength field, element by element, beside an
/// elastic body's 1; a model without a field has no such array.
#[test]
fn the_field_frame_shows_the_strength_field() {
    use impact_solver::material::MaterialModel;
    use impact_solver::model::Model;
    use impact_solver::output::field_frame;
    use impact_solver::output::FieldData;
    let concrete = MaterialModel::Microplane(MicroplaneParameters {
        strength_field: Some(field_spec(5)),
        ..shipped_concrete("thesis-concrete")
    });
    let steel = MaterialModel::LinearElastic(common::STEEL);
    let beam = common::box_body([0.4, 0.1, 0.1], [8, 2, 2], 0.0, 0);
    let mut plate = common::box_body([0.1, 0.1, 0.1], [1, 1, 1], 0.0, 0);
    for x in &mut plate.nodes {
        x.y += 0.2;
    }
    let model = Model::new(vec![
        ("beam".into(), beam, concrete),
        ("plate".into(), plate, steel),
    ])
    .unwrap();
    let u = vec![nalgebra::Vector3::zeros(); model.node_count()];
    let frame = field_frame(&model, &model.reference, &u, None, 0.0);
    let (_, data) = frame
        .cell_data
        .iter()
        .find(|(name, _)| name == "tensile_strength_factor")
        .expect("a strength field array");
    let FieldData::Scalar(values) = data else {
        panic!("a scalar array");
    };
    let concrete_elements = model.bodies[0].elements.len();
    assert_eq!(values.len(), model.element_count());
    let field = StrengthField::new(&field_spec(5)).unwrap();
    for (e, tet) in model.tets[0..concrete_elements].iter().enumerate() {
        let x = tet.map(|n| model.reference[n as usize]);
        let centroid = std::array::from_fn(|i| 0.25 * (x[0][i] + x[1][i] + x[2][i] + x[3][i]));
        assert_eq!(values[e], field.factor(centroid));
    }
    assert!(values[concrete_elements..].iter().all(|&v| v == 1.0));

    let plain = Model::new(vec![(
        "beam".into(),
        common::box_body([0.4, 0.1, 0.1], [8, 2, 2], 0.0, 0),
        MaterialModel::Microplane(shipped_concrete("thesis-concrete")),
    )])
    .unwrap();
    let u = vec![nalgebra::Vector3::zeros(); plain.node_count()];
    let frame = field_frame(&plain, &plain.reference, &u, None, 0.0);
    assert!(frame
        .cell_data
        .iter()
        .all(|(n, _)| n != "tensile_strength_factor"));
}
