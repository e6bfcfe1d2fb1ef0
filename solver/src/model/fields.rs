//! Element and nodal fields of a state, packaged as a frame for the VTU writer.

use nalgebra::{Matrix3, Vector3};

use super::Model;
use crate::kinematics::{displacement_gradient, green_lagrange_from_h, principal_values, voigt};
use crate::material::Material;
use crate::output::vtu::{FieldData, FieldFrame};
use crate::with_material;

/// Cauchy stress, Green-Lagrange strain and its largest principal value per element.
pub struct ElementFields {
    pub cauchy: Vec<[f64; 6]>,
    pub green_lagrange: Vec<[f64; 6]>,
    pub max_principal_strain: Vec<f64>,
}

impl Model {
    /// Stress and strain of every element at displacement `u`.
    pub fn element_fields(&self, u: &[Vector3<f64>]) -> ElementFields {
        let n = self.element_count();
        let mut out = ElementFields {
            cauchy: Vec::with_capacity(n),
            green_lagrange: Vec::with_capacity(n),
            max_principal_strain: Vec::with_capacity(n),
        };
        for body in &self.bodies {
            with_material!(&body.material, |m| {
                for e in body.elements.clone() {
                    let h =
                        displacement_gradient(&self.element_displacements(e, u), &self.grad_n[e]);
                    let green = green_lagrange_from_h(&h);
                    out.cauchy
                        .push(voigt(&m.cauchy(&(Matrix3::identity() + h), &h)));
                    out.max_principal_strain.push(principal_values(&green)[2]);
                    out.green_lagrange.push(voigt(&green));
                }
            });
        }
        out
    }
}

/// The frame written for ParaView: displacement and velocity at the nodes; Cauchy stress,
/// Green-Lagrange strain, largest principal strain and body id on the elements.
pub fn field_frame<'a>(
    model: &'a Model,
    points: &'a [Vector3<f64>],
    u: &[Vector3<f64>],
    v: Option<&[Vector3<f64>]>,
    time: f64,
) -> FieldFrame<'a> {
    let fields = model.element_fields(u);
    let as_arrays = |x: &[Vector3<f64>]| x.iter().map(|a| [a.x, a.y, a.z]).collect();
    let mut point_data = vec![("displacement".to_string(), FieldData::Vector(as_arrays(u)))];
    if let Some(v) = v {
        point_data.push(("velocity".to_string(), FieldData::Vector(as_arrays(v))));
    }
    FieldFrame {
        time,
        points,
        tets: &model.tets,
        point_data,
        cell_data: vec![
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
                "body".into(),
                FieldData::Int(model.element_body.iter().map(|&b| b as i32).collect()),
            ),
        ],
    }
}
