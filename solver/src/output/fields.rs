//! The field frame of a model's state, as the writers take it: the nodal fields and the element
//! fields of [`crate::model::Model::element_fields_with_history`].

use nalgebra::Vector3;

use super::vtu::{FieldData, FieldFrame};
use crate::model::{MaterialHistory, Model};

/// The frame written for ParaView: displacement and velocity at the nodes; Cauchy stress,
/// Green-Lagrange strain, largest principal strain, crack indicator, microplane rate factor and
/// body id on the elements, and the tensile strength factor where a body has a random strength
/// field. For models without history (see [`field_frame_with_history`]).
pub fn field_frame<'a>(
    model: &'a Model,
    points: &'a [Vector3<f64>],
    u: &[Vector3<f64>],
    v: Option<&[Vector3<f64>]>,
    time: f64,
) -> FieldFrame<'a> {
    field_frame_with_history(model, None, points, u, v, time)
}

/// [`field_frame`] with the stresses and rate factors of bodies with history read from `history`.
pub fn field_frame_with_history<'a>(
    model: &'a Model,
    history: Option<&MaterialHistory>,
    points: &'a [Vector3<f64>],
    u: &[Vector3<f64>],
    v: Option<&[Vector3<f64>]>,
    time: f64,
) -> FieldFrame<'a> {
    let fields = model.element_fields_with_history(u, history);
    let as_arrays = |x: &[Vector3<f64>]| x.iter().map(|a| [a.x, a.y, a.z]).collect();
    // After a remeshing `u` runs from the remeshing: the frame gives the displacement from the
    // original configuration, as before it (the points are the current ones either way).
    let displacement = match &model.carried {
        Some(c) => c
            .displacement
            .iter()
            .zip(u)
            .map(|(d, u)| [d.x + u.x, d.y + u.y, d.z + u.z])
            .collect(),
        None => as_arrays(u),
    };
    let mut point_data = vec![("displacement".to_string(), FieldData::Vector(displacement))];
    if let Some(v) = v {
        point_data.push(("velocity".to_string(), FieldData::Vector(as_arrays(v))));
    }
    let mut cell_data = vec![
        (
            "cauchy_stress".into(),
            FieldData::SymmetricTensor(fields.cauchy),
        ),
        (
            "green_lagrange_strain".into(),
            FieldData::SymmetricTensor(fields.green_lagrange),
        ),
        (
            "max_principal_strain".into(),
            FieldData::Scalar(fields.max_principal_strain),
        ),
        (
            "crack_indicator".into(),
            FieldData::Scalar(fields.crack_indicator),
        ),
        ("rate_factor".into(), FieldData::Scalar(fields.rate_factor)),
        (
            "body".into(),
            FieldData::Int(
                (model.bodies.iter().enumerate())
                    .flat_map(|(b, body)| body.elements.clone().map(move |_| b as i32))
                    .collect(),
            ),
        ),
    ];
    // The strength field, where a body has one (1 on the other bodies' elements).
    let has_field = |b: &crate::model::Body| b.material.strength_factor(0).is_some();
    if model
        .bodies
        .iter()
        .any(|b| !b.elements.is_empty() && has_field(b))
    {
        let mut factors = Vec::with_capacity(model.element_count());
        for body in &model.bodies {
            let material = &body.material;
            factors.extend(
                (0..body.elements.len()).map(|e| material.strength_factor(e).unwrap_or(1.0)),
            );
        }
        cell_data.push(("tensile_strength_factor".into(), FieldData::Scalar(factors)));
    }
    FieldFrame {
        time,
        points,
        tets: model.tets.stored(),
        first_cell: model.tets.stored_range().start,
        point_data,
        cell_data,
    }
}
