//! The element a trial displacement of the static path inverts, named with where it sits and how
//! far the trial moved its nodes from the committed state, so that a path that stops on one says
//! whether Newton's iterate overshot (a trial move far above the step's size) or the element
//! itself collapsed.

use nalgebra::Vector3;

use crate::problem::Problem;

/// An element whose deformation gradient has `det F <= 0` at a trial displacement.
#[derive(Debug, Clone, Copy)]
pub(super) struct Inverted {
    /// The element's index in the model.
    pub element: usize,
    /// `det F` at the trial displacement.
    pub det: f64,
}

impl Inverted {
    /// Its body, centroid in the reference configuration (mm), size `(6 V)^(1/3)`, `det F`, and
    /// the largest move of its nodes from `committed` to `trial`.
    pub fn describe(
        &self,
        problem: &Problem,
        trial: &[Vector3<f64>],
        committed: &[Vector3<f64>],
    ) -> String {
        let model = &problem.model;
        let e = self.element;
        let tet = model.tets[e];
        let centroid = tet
            .iter()
            .map(|&n| model.reference[n as usize])
            .sum::<Vector3<f64>>()
            / 4.0;
        let moved = tet
            .iter()
            .map(|&n| (trial[n as usize] - committed[n as usize]).norm())
            .fold(0.0, f64::max);
        let body = &model.bodies[model.body_of(e)].name;
        format!(
            "body {body}, centroid ({:.3}, {:.3}, {:.3}) mm, size {:.3} mm, det F {:.3e}, \
             its nodes moved up to {:.3e} m from the committed state",
            centroid.x * 1e3,
            centroid.y * 1e3,
            centroid.z * 1e3,
            model.element_size(e) * 1e3,
            self.det,
            moved
        )
    }
}
