//! Reading the final fields for the field and stress measures: the boundary nodes, and the
//! largest entry of a tensor.

use impact_solver::problem::Problem;
use nalgebra::Matrix3;

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
