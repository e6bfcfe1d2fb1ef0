//! A model together with what acts on it (conditions, loads, gravity, initial velocities, probes
//! and contact pairs): the complete input of an analysis. It sits above `model` and `contact`, so
//! that the model holds no contact configuration.

use nalgebra::Vector3;

use crate::contact::ContactPair;
use crate::model::{Constraint, Model, NodalLoad, NodeArray, Probe, ProbeQuantity};
use crate::nodal::{NodeStoreMut, NodeValues};

/// A model with its boundary conditions, loads and initial state.
#[derive(Debug)]
pub struct Problem {
    /// The meshes, materials and lumped masses.
    pub model: Model,
    /// Applied in order; where two constrain the same node component, the later one wins.
    pub constraints: Vec<Constraint>,
    /// Nodal loads, summed where several act on one node.
    pub loads: Vec<NodalLoad>,
    /// Gravitational acceleration (m/s^2), if any.
    pub gravity: Option<Vector3<f64>>,
    /// Initial velocity of every node (m/s): one rank's own nodes' during a distributed run
    /// without contact, as the model's nodal arrays ([`crate::model::NodeArray`]).
    pub initial_velocity: NodeArray<Vector3<f64>>,
    /// Quantities recorded in the history.
    pub probes: Vec<Probe>,
    /// Pairs of bodies that may touch.
    pub contact: Vec<ContactPair>,
}

impl Problem {
    /// A model at rest with nothing acting on it.
    pub fn new(model: Model) -> Self {
        let n = model.node_count();
        Self {
            model,
            constraints: Vec::new(),
            loads: Vec::new(),
            gravity: None,
            initial_velocity: vec![Vector3::zeros(); n].into(),
            probes: Vec::new(),
            contact: Vec::new(),
        }
    }

    /// For each node, the index of the last constraint acting on each component (if any).
    pub fn constraint_map(&self) -> Vec<[Option<u16>; 3]> {
        let mut map = vec![[None; 3]; self.model.node_count()];
        for (c, constraint) in self.constraints.iter().enumerate() {
            let dofs = constraint.motion.dofs();
            for &n in &constraint.nodes {
                for d in 0..3 {
                    if dofs[d] {
                        map[n as usize][d] = Some(c as u16);
                    }
                }
            }
        }
        map
    }

    /// History columns of the probes and the conditions, in the order of
    /// [`Self::push_probe_values`]: `<probe>_<x|y|z>`, then `<condition>_reaction_<x|y|z>`.
    pub fn probe_columns(&self) -> Vec<String> {
        let mut c = Vec::with_capacity(3 * (self.probes.len() + self.constraints.len()));
        for p in &self.probes {
            c.extend(["x", "y", "z"].map(|a| format!("{}_{a}", p.name)));
        }
        for k in &self.constraints {
            c.extend(["x", "y", "z"].map(|a| format!("{}_reaction_{a}", k.name)));
        }
        c
    }

    /// Appends the probes' values (the mean displacement or velocity of their nodes, or the sum
    /// of their reactions; velocities are zero where `v` is `None`, a static state) and each
    /// condition's reaction over the components it owns (`constraint_of`, from
    /// [`Self::constraint_map`]: a later condition on the same node component takes it over).
    pub fn push_probe_values<N, C>(
        &self,
        row: &mut Vec<f64>,
        u: &N,
        v: Option<&N>,
        reaction: &N,
        constraint_of: &C,
    ) where
        N: NodeValues<Vector3<f64>> + ?Sized,
        C: NodeValues<[Option<u16>; 3]> + ?Sized,
    {
        self.push_probe_means(row, u, v, reaction);
        self.push_condition_reactions(row, reaction, constraint_of);
    }

    /// The probes' part of [`Self::push_probe_values`].
    pub fn push_probe_means<N>(&self, row: &mut Vec<f64>, u: &N, v: Option<&N>, reaction: &N)
    where
        N: NodeValues<Vector3<f64>> + ?Sized,
    {
        for p in &self.probes {
            let (field, mean) = match (p.quantity, v) {
                (ProbeQuantity::Displacement, _) => (u, true),
                (ProbeQuantity::Velocity, Some(v)) => (v, true),
                (ProbeQuantity::Velocity, None) => {
                    row.extend([0.0; 3]);
                    continue;
                }
                (ProbeQuantity::Reaction, _) => (reaction, false),
            };
            let mut sum = p
                .nodes
                .iter()
                .fold(Vector3::zeros(), |acc, &n| acc + field[n as usize]);
            // After a remeshing `u` starts from the new reference: a displacement probe adds
            // the displacement carried from the original configuration.
            if let (ProbeQuantity::Displacement, Some(c)) = (p.quantity, &self.model.carried) {
                sum += p
                    .nodes
                    .iter()
                    .fold(Vector3::zeros(), |acc, &n| acc + c.displacement[n as usize]);
            }
            let count = if mean {
                p.nodes.len().max(1) as f64
            } else {
                1.0
            };
            row.extend((sum / count).iter());
        }
    }

    /// The conditions' part of [`Self::push_probe_values`]: each condition's reaction, summed
    /// over its nodes in their order. `reaction` and `constraint_of` are read at the conditions'
    /// nodes only.
    pub fn push_condition_reactions<R, C>(
        &self,
        row: &mut Vec<f64>,
        reaction: &R,
        constraint_of: &C,
    ) where
        R: NodeValues<Vector3<f64>> + ?Sized,
        C: NodeValues<[Option<u16>; 3]> + ?Sized,
    {
        for (c, k) in self.constraints.iter().enumerate() {
            let mut sum = Vector3::zeros();
            for &n in &k.nodes {
                for d in 0..3 {
                    if constraint_of[n as usize][d] == Some(c as u16) {
                        sum[d] += reaction[n as usize][d];
                    }
                }
            }
            row.extend(sum.iter());
        }
    }

    /// External nodal forces at time `t` (loads and gravity) into `f`; `false` when the problem
    /// has none, so the caller can skip the term.
    pub fn external_forces(
        &self,
        t: f64,
        f: &mut (impl NodeStoreMut<Vector3<f64>> + ?Sized),
    ) -> bool {
        if self.loads.is_empty() && self.gravity.is_none() {
            return false;
        }
        match self.gravity {
            Some(g) => f.for_each_stored(|a, fa| *fa = g * self.model.mass[a]),
            None => f.for_each_stored(|_, fa| *fa = Vector3::zeros()),
        }
        // A rank stores its own nodes only: a load on another's is that rank's.
        for load in &self.loads {
            let force = load.force_per_node * load.function.eval(t);
            for &n in &load.nodes {
                if let Some(fa) = f.stored_mut_at(n as usize) {
                    *fa += force;
                }
            }
        }
        true
    }
}
