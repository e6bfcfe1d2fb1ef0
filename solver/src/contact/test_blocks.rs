//! Unit-test fixture: elastic box-meshed bodies for detection and normal tests.

use crate::material::{IsotropicElastic, MaterialModel};
use crate::mesh::{box_mesh, BoxSpec};
use crate::model::Model;

/// One linear elastic body per box (rho 1000, E 1 GPa, nu 0.3), named `body0`, `body1`, ...
pub fn elastic_boxes(boxes: &[BoxSpec]) -> Model {
    let material = MaterialModel::LinearElastic(IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1e9,
        poisson_ratio: 0.3,
    });
    Model::new(
        boxes
            .iter()
            .enumerate()
            .map(|(i, b)| (format!("body{i}"), box_mesh(b), material))
            .collect(),
    )
    .unwrap()
}
