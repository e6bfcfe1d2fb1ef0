//! Indirect displacement control of a static path: a loading condition moves as one by an
//! unknown displacement, and what the path prescribes is an opening between two node sets (the
//! crack mouth opening displacement, CMOD, of a notched beam test; the opening under the neutral
//! axis of a beam). The opening of a crack grows monotonically through the peak where the
//! load-point displacement turns back (snap-back), so the path goes on after the peak where
//! load-point control stops (de Borst 1987, "Computation of post-bifurcation and post-failure
//! behavior of strain-softening solids"; the servo control of the tests themselves, RILEM
//! TC 50-FMC 1985, Gregoire et al. 2013).
//!
//! The unknowns are the free components and the condition's displacement `delta`; the equations
//! are the out-of-balance forces of the free components and `g(u) - c(t) = 0`, with the opening
//! `g(u) = mean(u_to . e) - mean(u_from . e)`, linear in `u`. Newton's matrix is bordered by the
//! condition's columns summed (its nodes move together) and the row `dg/du`; it is solved by
//! bordering (Batoz & Dhatt 1979), two solves with the factorisation of the load-point
//! controlled tangent, which keeps its pivots away from the border's zero diagonal. The
//! condition's reaction is the load that the opening needs.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SolverError};
use crate::model::{Component, Motion, TimeFunction};
use crate::problem::Problem;

/// The settings: `{ condition, from, to, component, opening }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpeningControl {
    /// The displacement condition whose nodes move together by the unknown `delta` along its
    /// components (its own time function is not used).
    pub condition: String,
    /// Probes (node sets) whose mean displacements along `component` give the opening
    /// `to - from`.
    pub from: String,
    /// The probe on the far side of the opening: its mean displacement minus that of `from`.
    pub to: String,
    /// The displacement component along which the opening is measured.
    pub component: Component,
    /// The opening (m) against time (s; the load factor times `end_time`).
    pub opening: TimeFunction,
}

/// The control built on a problem.
#[derive(Debug, Clone)]
pub(super) struct Control {
    /// The node components the unknown `delta` moves.
    pub moved: Vec<(usize, usize)>,
    /// The same per node, for the assembly.
    pub moved_mask: Vec<[bool; 3]>,
    /// The terms of `g(u) = sum w u[node][component]`: (node, component, its equation, w);
    /// `dg/du` is `w` at each equation.
    pub terms: Vec<(usize, usize, usize, f64)>,
    pub opening: TimeFunction,
}

impl Control {
    /// Checks the settings against `problem` (the condition exists and prescribes a
    /// displacement, the probes exist, their components are free) and builds the control.
    pub fn new(
        settings: &OpeningControl,
        problem: &Problem,
        equation: &[[usize; 3]],
    ) -> Result<Self> {
        let entity = |what: &str| format!("static analysis opening_control.{what}");
        let index = problem
            .constraints
            .iter()
            .position(|c| c.name == settings.condition)
            .ok_or_else(|| SolverError::InvalidScene {
                entity: entity("condition"),
                message: format!(
                    "the scene has no boundary condition `{}`; it has {:?}",
                    settings.condition,
                    problem
                        .constraints
                        .iter()
                        .map(|c| &c.name)
                        .collect::<Vec<_>>()
                ),
            })?;
        let condition = &problem.constraints[index];
        let Motion::Displacement(dofs, _) = &condition.motion else {
            return Err(SolverError::InvalidScene {
                entity: entity("condition"),
                message: format!(
                    "condition `{}` must prescribe a displacement (`motion: {{ displacement: \
                     ... }}`), whose nodes the control then moves together",
                    condition.name
                ),
            });
        };
        let owner = problem.constraint_map();
        let mut moved = Vec::new();
        for &n in &condition.nodes {
            for d in 0..3 {
                if dofs[d] && owner[n as usize][d] == Some(index as u16) {
                    moved.push((n as usize, d));
                }
            }
        }
        let axis = settings.component as usize;
        let mut terms = Vec::new();
        for (name, sign) in [(&settings.to, 1.0), (&settings.from, -1.0)] {
            let probe = problem
                .probes
                .iter()
                .find(|p| &p.name == name)
                .ok_or_else(|| SolverError::InvalidScene {
                    entity: entity(if sign > 0.0 { "to" } else { "from" }),
                    message: format!(
                        "the scene has no probe `{name}`; it has {:?}",
                        problem.probes.iter().map(|p| &p.name).collect::<Vec<_>>()
                    ),
                })?;
            let weight = sign / probe.nodes.len().max(1) as f64;
            for &n in &probe.nodes {
                match equation[n as usize][axis] {
                    usize::MAX => {
                        return Err(SolverError::InvalidScene {
                            entity: entity(if sign > 0.0 { "to" } else { "from" }),
                            message: format!(
                                "node {n} of probe `{name}` has its {:?} component prescribed: \
                                 an opening between prescribed components cannot be controlled",
                                settings.component
                            ),
                        })
                    }
                    k => terms.push((n as usize, axis, k, weight)),
                }
            }
        }
        let mut moved_mask = vec![[false; 3]; equation.len()];
        for &(n, d) in &moved {
            moved_mask[n][d] = true;
        }
        Ok(Self {
            moved,
            moved_mask,
            terms,
            opening: settings.opening.clone(),
        })
    }

    /// The opening `g(u)`.
    pub fn opening_of(&self, u: &[Vector3<f64>]) -> f64 {
        self.terms.iter().map(|&(n, d, _, w)| w * u[n][d]).sum()
    }

    /// `G x = sum w x[equation]`: the opening's change for a change `x` of the free components.
    pub fn along(&self, x: &[f64]) -> f64 {
        self.terms.iter().map(|&(_, _, k, w)| w * x[k]).sum()
    }

    /// The displacement `delta` of the moved components (their mean).
    pub fn delta(&self, u: &[Vector3<f64>]) -> f64 {
        self.moved.iter().map(|&(n, d)| u[n][d]).sum::<f64>() / self.moved.len().max(1) as f64
    }

    /// Moves every moved component to `delta`.
    pub fn set_delta(&self, u: &mut [Vector3<f64>], delta: f64) {
        for &(n, d) in &self.moved {
            u[n][d] = delta;
        }
    }
}
