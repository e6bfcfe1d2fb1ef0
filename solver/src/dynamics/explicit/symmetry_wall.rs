//! Symmetry planes as walls for the whole body (`motion: { symmetry: axis }`).
//!
//! A model cut by a symmetry plane holds the nodes on the cut normal to it. A node that was not
//! on the plane can still reach it: under a penetrator the cavity's surface is pushed sideways,
//! and in the nail run a surface node near the plane z = 0 crossed it by 0.1 mm and another the
//! plane x = 0 by 1.5 mm, into the space of the mirror half. In the whole body the node would
//! meet its mirror image there, so the plane is a frictionless wall for every node of the body:
//! a node that would cross it in the step is put on it, by the velocity that lands it there,
//! the forward-increment Lagrange multiplier of a node against a fixed plane (thesis 6.3, with
//! the plane as the master). The wall's force is a reaction like the plane nodes' (the same
//! dynamic balance, in the energy ledger as external work); the node is free again the next
//! step, so it can leave the plane when the body pulls it back.

use std::ops::Range;

use nalgebra::Vector3;

use crate::nodal::NodeField;

use crate::model::Motion;

use crate::problem::Problem;

/// One symmetry plane `x[axis] = value` and the nodes of the body it bounds, which lies on the
/// side `side` (+1 or -1) of it.
#[derive(Debug, Clone)]
struct Wall {
    axis: usize,
    value: f64,
    side: f64,
    nodes: Range<usize>,
}

/// The symmetry planes of a problem's constraints, and the components they held in the last
/// step.
#[derive(Debug, Clone, Default)]
pub(crate) struct SymmetryWalls {
    walls: Vec<Wall>,
    /// Per node, the components a wall held in the last step (empty when there is no wall).
    pub held: Vec<[bool; 3]>,
}

impl SymmetryWalls {
    /// The walls of `problem`'s symmetry constraints, each over the body of the constraint's
    /// first node. The side is where the body's nodes lie (their mean against the plane).
    pub fn new(problem: &Problem) -> Self {
        let model = &problem.model;
        let mut walls = Vec::new();
        for c in &problem.constraints {
            let Motion::Symmetry { axis, value } = c.motion else {
                continue;
            };
            let Some(&first) = c.nodes.first() else {
                continue;
            };
            let Some(body) = model
                .bodies
                .iter()
                .find(|b| b.nodes.contains(&(first as usize)))
            else {
                continue;
            };
            let nodes = body.nodes.clone();
            let mean = nodes.clone().map(|i| model.reference[i][axis]).sum::<f64>()
                / nodes.len().max(1) as f64;
            walls.push(Wall {
                axis,
                value,
                side: if mean >= value { 1.0 } else { -1.0 },
                nodes,
            });
        }
        let held = if walls.is_empty() {
            Vec::new()
        } else {
            vec![[false; 3]; model.node_count()]
        };
        Self { walls, held }
    }

    /// Puts on its plane every node that `v_next` would carry across it in the step `dt` from
    /// `x_now` (plus the contact's position surplus `dx_extra`), where no constraint already
    /// prescribes that component; records which components were held.
    pub fn hold(
        &mut self,
        x_now: impl Fn(usize) -> Vector3<f64>,
        dx_extra: impl Fn(usize) -> Vector3<f64>,
        dt: f64,
        constrained: impl Fn(usize, usize) -> bool,
        v_next: &mut NodeField<Vector3<f64>>,
    ) {
        if self.walls.is_empty() {
            return;
        }
        self.held.iter_mut().for_each(|h| *h = [false; 3]);
        for w in &self.walls {
            for i in w.nodes.clone() {
                let d = w.axis;
                // A rank holds the nodes it stores; another rank holds the others.
                if v_next.get(i).is_none() || constrained(i, d) {
                    continue;
                }
                let start = x_now(i)[d] + dx_extra(i)[d];
                if w.side * (start + dt * v_next[i][d] - w.value) < 0.0 {
                    v_next[i][d] = (w.value - start) / dt;
                    self.held[i][d] = true;
                }
            }
        }
    }

    /// Whether a wall held component `d` of node `i` in the last step.
    pub fn holds(&self, i: usize, d: usize) -> bool {
        self.held.get(i).is_some_and(|h| h[d])
    }
}
