//! The contact phase of an explicit step: the buffers it keeps over a run and the correction
//! of the predicted velocities by the contact solvers (thesis chapter 6).

use std::ops::{Index, IndexMut};

use nalgebra::Vector3;

use crate::problem::Problem;

/// Buffers of the contact phase, allocated once per run.
pub(super) struct ContactScratch {
    pub(super) phase: crate::contact::ContactPhase,
    /// Inverse lumped mass per component; zero for prescribed components, which contact cannot
    /// move.
    inverse_mass: Vec<Vector3<f64>>,
    beta_0: f64,
    /// The nodes whose predicted positions contact reads
    /// ([`crate::contact::ContactPhase::layer_nodes`]) and the surface nodes, the only ones it
    /// moves: the loops of a step run over these only. Elsewhere the correction is zero, so the
    /// forces stay at the zeros they start with.
    layer_nodes: Vec<u32>,
    surface_nodes: Vec<u32>,
    x0: Vec<Vector3<f64>>,
    x1: Vec<Vector3<f64>>,
    /// Contact force on each node over the step, `m dv (1/h + alpha/2)` with `h` the velocity
    /// update's step and `alpha` the mass-proportional damping (N).
    pub(super) force: Vec<Vector3<f64>>,
    /// Position corrections made by the tangential parts of the contact forces; zero between
    /// steps.
    tangential_dx: Vec<Vector3<f64>>,
    /// The friction part of `force` (N).
    pub(super) friction_force: Vec<Vector3<f64>>,
    /// `dx - dt dv` of the beta-2 corrections (zero for `beta_0 = 0`).
    pub(super) position_surplus: Vec<Vector3<f64>>,
}

impl ContactScratch {
    pub(super) fn new(problem: &Problem) -> Self {
        let model = &problem.model;
        let n = model.node_count();
        let prescribed = problem.constraint_map();
        let inverse_mass = (0..n)
            .map(|i| {
                Vector3::from_fn(|d, _| match prescribed[i][d] {
                    Some(_) => 0.0,
                    None => 1.0 / model.mass[i],
                })
            })
            .collect();
        let held: Vec<[bool; 3]> = prescribed
            .iter()
            .map(|p| [p[0].is_some(), p[1].is_some(), p[2].is_some()])
            .collect();
        let phase = crate::contact::ContactPhase::with_held(model, problem.contact.clone(), &held);
        Self {
            layer_nodes: phase.layer_nodes(model),
            surface_nodes: phase.surface_nodes(),
            phase,
            inverse_mass,
            beta_0: problem.contact.iter().map(|p| p.beta_0).fold(0.0, f64::max),
            x0: vec![Vector3::zeros(); n],
            x1: vec![Vector3::zeros(); n],
            force: vec![Vector3::zeros(); n],
            tangential_dx: vec![Vector3::zeros(); n],
            friction_force: vec![Vector3::zeros(); n],
            position_surplus: vec![Vector3::zeros(); n],
        }
    }

    /// The nodes the contact phase reads or moves: in a distributed run, every rank integrates
    /// them alike and solves the whole contact problem.
    pub(super) fn replicated_nodes(&self) -> Vec<u32> {
        let mut nodes: Vec<u32> = self
            .layer_nodes
            .iter()
            .chain(&self.surface_nodes)
            .copied()
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// Corrects the predicted velocities `v_next` (and records forces) so that the positions
    /// `x + dt v` at the end of the step violate no contact (thesis 6.4.2.3, (6.58)-(6.61)).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn correct<U, V>(
        &mut self,
        step: usize,
        model: &crate::model::Model,
        dt: f64,
        force_per_dv: f64,
        u: &U,
        v_next: &mut V,
    ) -> Vec<crate::contact::ContactStep>
    where
        U: Index<usize, Output = Vector3<f64>> + ?Sized,
        V: IndexMut<usize, Output = Vector3<f64>> + ?Sized,
    {
        for &i in &self.layer_nodes {
            let i = i as usize;
            self.x1[i] = predicted_position(model, u, v_next, dt, i);
        }
        for &i in &self.surface_nodes {
            let i = i as usize;
            self.x0[i] = model.reference[i] + u[i];
        }
        // Until `resolve` runs, the phase reports the nodes the last step moved: the only ones
        // whose force, friction force and surplus are not zero.
        for &i in self.phase.touched_nodes() {
            let i = i as usize;
            self.force[i] = Vector3::zeros();
            self.friction_force[i] = Vector3::zeros();
            self.position_surplus[i] = Vector3::zeros();
        }
        let mut steps = self.phase.resolve(
            step,
            model,
            &self.inverse_mass,
            dt,
            &self.x0,
            &mut self.x1,
            &mut self.tangential_dx,
        );
        // A multiplier r moves a node by beta dt^2 r / m and changes its velocity by
        // gamma dt r / m, gamma = 1/2 (FORMULATION 4): the velocity takes gamma / beta of the
        // correction (all of it for beta_0 = 0) and the force is gamma dt r times force_per_dv.
        const GAMMA: f64 = 0.5;
        let velocity_share = GAMMA / (self.beta_0 + 0.5);
        let force_per_dx = velocity_share / dt * force_per_dv;
        // Only the nodes of solved constraints moved: elsewhere `x1` is the prediction, and the
        // correction, its force and its surplus are zero.
        for &i in self.phase.touched_nodes() {
            let i = i as usize;
            let dx = self.x1[i] - predicted_position(model, u, v_next, dt, i);
            let dv = dx * (velocity_share / dt);
            v_next[i] += dv;
            self.force[i] = dx * (model.mass[i] * force_per_dx);
            self.friction_force[i] = self.tangential_dx[i] * (model.mass[i] * force_per_dx);
            self.tangential_dx[i] = Vector3::zeros();
            self.position_surplus[i] = dx - dv * dt;
        }
        for step in &mut steps {
            step.normal_force *= GAMMA * dt * force_per_dv;
            step.tangential_force *= GAMMA * dt * force_per_dv;
        }
        steps
    }
}

/// The position `x + dt v` the step predicts for node `i` before contact; the correction is
/// measured from it, so it is formed the same way wherever it is read.
#[inline]
fn predicted_position<U, V>(
    model: &crate::model::Model,
    u: &U,
    v_next: &V,
    dt: f64,
    i: usize,
) -> Vector3<f64>
where
    U: Index<usize, Output = Vector3<f64>> + ?Sized,
    V: Index<usize, Output = Vector3<f64>> + ?Sized,
{
    (model.reference[i] + u[i]) + v_next[i] * dt
}
