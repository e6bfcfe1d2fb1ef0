//! The beam's frame (load strip, bottom face, height, supports, cell size) and its elements,
//! read from the problem; the conventions are in the `cracks` module documentation.

use impact_solver::problem::Problem;
use impact_solver::Vector3;

use super::{BeamSpec, CrackError, Side};

/// The geometry the classification works in (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamFrame {
    /// `x` of the load's centre line (m); mid-span by default.
    pub x_load: f64,
    /// Half width of the loaded strip (m); a quarter of the beam height by default.
    pub load_half_width: f64,
    /// `y` of the beam's bottom face (m).
    pub y_bottom: f64,
    /// Beam height (m).
    pub height: f64,
    /// Cell size (m).
    pub cell: f64,
    /// `[x_min, x_max]` of each support strip.
    pub supports: Vec<[f64; 2]>,
    /// Cracks (zone parts) of fewer elements are ignored.
    pub min_elements: usize,
}

/// An element of the beam: reference centroid and nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamElement {
    /// Centroid of the element in the reference configuration (m).
    pub centroid: Vector3<f64>,
    /// Its four global node indices.
    pub nodes: [u32; 4],
}

impl BeamFrame {
    /// The frame of `spec.body` in `problem`, with its elements (global ids `first..`).
    pub fn of(
        problem: &Problem,
        spec: &BeamSpec,
    ) -> Result<(BeamFrame, Vec<BeamElement>), CrackError> {
        let model = &problem.model;
        let b = model
            .body_index(&spec.body)
            .ok_or_else(|| CrackError::NoBody {
                body: spec.body.clone(),
            })?;
        let body = &model.bodies[b];
        let (mut lo, mut hi) = (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        );
        for n in body.nodes.clone() {
            lo = lo.inf(&model.reference[n]);
            hi = hi.sup(&model.reference[n]);
        }
        let elements: Vec<BeamElement> = body
            .elements
            .clone()
            .map(|e| {
                let nodes = model.tets[e];
                BeamElement {
                    centroid: nodes
                        .iter()
                        .map(|&n| model.reference[n as usize])
                        .sum::<Vector3<f64>>()
                        / 4.0,
                    nodes,
                }
            })
            .collect();
        if elements.is_empty() {
            return Err(CrackError::NoElements {
                body: spec.body.clone(),
            });
        }
        let mean_volume =
            body.elements.clone().map(|e| model.volume(e)).sum::<f64>() / elements.len() as f64;
        let cell = (6.0 * mean_volume).cbrt();
        let height = hi.y - lo.y;
        let on_bottom = |n: u32| (model.reference[n as usize].y - lo.y).abs() <= 1e-6 * height;
        let supports = problem
            .constraints
            .iter()
            .filter(|c| {
                !c.nodes.is_empty()
                    && c.nodes
                        .iter()
                        .all(|&n| body.nodes.contains(&(n as usize)) && on_bottom(n))
            })
            .map(|c| {
                c.nodes
                    .iter()
                    .fold([f64::INFINITY, f64::NEG_INFINITY], |[a, z], &n| {
                        let x = model.reference[n as usize].x;
                        [a.min(x), z.max(x)]
                    })
            })
            .collect();
        Ok((
            BeamFrame {
                x_load: spec.load_x.unwrap_or(0.5 * (lo.x + hi.x)),
                load_half_width: spec.load_half_width.unwrap_or(0.25 * height),
                y_bottom: lo.y,
                height,
                cell,
                supports,
                min_elements: spec.min_elements,
            },
            elements,
        ))
    }

    /// Within one cell of the loaded strip and in the top two layers of cells.
    pub fn in_loading_region(&self, c: &Vector3<f64>) -> bool {
        (c.x - self.x_load).abs() <= self.load_half_width + self.cell
            && c.y >= self.y_bottom + self.height - 2.0 * self.cell
    }

    /// Within one cell of a support strip and in the bottom two layers of cells.
    pub fn in_support_region(&self, c: &Vector3<f64>) -> bool {
        c.y <= self.y_bottom + 2.0 * self.cell
            && self
                .supports
                .iter()
                .any(|[a, z]| c.x >= a - self.cell && c.x <= z + self.cell)
    }

    pub(super) fn side(&self, c: &Vector3<f64>) -> Side {
        if c.x < self.x_load - self.load_half_width {
            Side::Left
        } else if c.x > self.x_load + self.load_half_width {
            Side::Right
        } else {
            Side::Under
        }
    }
}
