//! Reading the final fields for the field and stress measures: boundary nodes, Voigt stresses
//! and the elements in a box.

use impact_solver::problem::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;

use super::{MeasureError, TensorComponent};
use impact_solver::analysis::Execution;

pub(super) fn boundary_node_flags(problem: &Problem) -> Vec<bool> {
    let mut flags = vec![false; problem.model.node_count()];
    // Bodies share no nodes, so the faces of all elements at once are the bodies' boundaries.
    for f in impact_solver::mesh::boundary_faces_of(&problem.model.tets) {
        for n in f.nodes {
            flags[n as usize] = true;
        }
    }
    flags
}

pub(super) fn max_abs(m: &Matrix3<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// One Cauchy stress component of every element whose reference centroid lies in `[min, max]`.
pub(super) fn element_stress_in_box(
    problem: &Problem,
    run: &Execution,
    component: TensorComponent,
    min: &[f64; 3],
    max: &[f64; 3],
) -> Result<Vec<f64>, MeasureError> {
    let fields = run.element_fields(&problem.model);
    let values: Vec<f64> = problem
        .model
        .tets
        .iter()
        .enumerate()
        .filter(|(_, tet)| {
            let centroid = tet
                .iter()
                .map(|&n| problem.model.reference[n as usize])
                .sum::<Vector3<f64>>()
                / 4.0;
            (0..3).all(|a| centroid[a] >= min[a] && centroid[a] <= max[a])
        })
        .map(|(e, _)| fields.cauchy[e][component as usize])
        .collect();
    if values.is_empty() {
        return Err(MeasureError::EmptyBox {
            min: *min,
            max: *max,
        });
    }
    Ok(values)
}
