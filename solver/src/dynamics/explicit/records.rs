//! What an explicit run records: the history columns and rows (energies, momenta, probes,
//! reactions) and the field frames, which it shows its observers.

use nalgebra::Vector3;

use super::ExplicitSolver;
use crate::dynamics::EnergyLedger;
use crate::error::Result;
use crate::output::field_frame_with_history;
use crate::output::ObserverSet;

impl<'p> ExplicitSolver<'p> {
    /// One line per decision the run takes, printed before it starts.
    pub fn plan(&self) -> String {
        let model = &self.problem.model;
        format!(
            "explicit dynamics: {} bodies, {} nodes, {} elements; dt = {:.4e} s ({:.3} of the \
             stable estimate {:.4e} s set by element {}); {} steps to t = {:.4e} s; {} constraints, \
             {} loads, gravity {}; damping a = {}; contact: {}",
            model.bodies.len(),
            model.node_count(),
            model.element_count(),
            self.dt,
            self.dt / self.dt_critical,
            self.dt_critical,
            self.critical_element,
            self.planned_steps(),
            self.settings.end_time,
            self.problem.constraints.len(),
            self.problem.loads.len(),
            if self.problem.gravity.is_some() { "on" } else { "off" },
            self.settings.damping,
            if self.problem.contact.is_empty() {
                "none".to_string()
            } else {
                self.problem
                    .contact
                    .iter()
                    .map(|p| format!("{} (mu {}, beta_0 {}, {} pass)", p.name, p.friction, p.beta_0, if p.two_pass { "two-" } else { "one-" }))
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        ) + &self.stop_plan()
            + &self.history_plan()
    }

    /// The run's own end before its end time (empty without `stop_when`).
    fn stop_plan(&self) -> String {
        match &self.settings.stop_when {
            Some(stop) => format!(
                "; the run ends earlier at the first history row where `{}` reaches {}",
                stop.column, stop.level
            ),
            None => String::new(),
        }
    }

    /// The bodies with history, their element sizes and the memory the history takes (empty
    /// without such bodies).
    pub(super) fn history_plan(&self) -> String {
        let model = &self.problem.model;
        let mut parts = Vec::new();
        for (body, history) in model.bodies.iter().zip(&self.history.bodies) {
            if let Some(h) = history {
                let summary = body.material.summary().unwrap_or_default();
                parts.push(format!(
                    "`{}` {} ({summary}; history {} B per element, {:.1} MB)",
                    body.name,
                    body.material.name(),
                    h.bytes_per_element(),
                    (h.bytes_per_element() * body.elements.len()) as f64 / 1e6
                ));
            }
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!("; materials with history: {}", parts.join(", "))
        }
    }

    /// Columns: time and step, the energies (`stored_energy` counts elastic bodies only; with
    /// microplane bodies, `microplane_internal_work`, their part of `internal_work`), then
    /// `<probe>_x/y/z` and `<constraint>_reaction_x/y/z`.
    pub fn history_columns(&self) -> Vec<String> {
        let mut c: Vec<String> = [
            "time",
            "step",
            "kinetic",
            "internal_work",
            "stored_energy",
            "external_work",
            "damping_work",
            "contact_work",
            "friction_work",
            "energy_error",
            "energy_error_relative",
            "momentum_x",
            "momentum_y",
            "momentum_z",
            "angular_momentum_x",
            "angular_momentum_y",
            "angular_momentum_z",
        ]
        .map(String::from)
        .to_vec();
        if !self.history_node.is_empty() {
            c.push("microplane_internal_work".into());
        }
        // Per body, when there are several: who holds the kinetic energy and the momentum
        // (the hammer's energy passing to the beam, thesis Figs. 10.11-10.14; (6.48)).
        if self.problem.model.bodies.len() > 1 {
            for b in &self.problem.model.bodies {
                c.push(format!("{}_kinetic", b.name));
                c.extend(["x", "y", "z"].map(|a| format!("{}_momentum_{a}", b.name)));
            }
        }
        c.extend(self.problem.probe_columns());
        for p in &self.problem.contact {
            c.extend(
                [
                    "force_x",
                    "force_y",
                    "force_z",
                    "normal",
                    "tangential",
                    "active",
                    "sliding",
                    "iterations",
                    "unresolved",
                ]
                .map(|q| format!("{}_{q}", p.name)),
            );
        }
        c
    }

    pub(super) fn history_row(&self, e: &EnergyLedger) -> Vec<f64> {
        let model = &self.problem.model;
        let mut row = vec![
            self.time,
            self.step as f64,
            e.kinetic,
            e.internal_work,
            self.stored_energy(),
            e.external_work,
            e.damping_work,
            e.contact_work,
            e.friction_work,
            e.balance_error(),
            e.relative_error(),
        ];
        let sums = self.node_sums();
        row.extend(&sums[..6]);
        if !self.history_node.is_empty() {
            row.push(e.history_work);
        }
        row.extend(&sums[6..]);
        match (&self.condition_reactions, &self.ranks) {
            (Some(reactions), Some(share)) => {
                let problem = self.problem;
                problem.push_probe_means(&mut row, &self.u, Some(&self.v_full), &self.reaction);
                reactions.push(problem, share.comm(), &self.reaction, &mut row);
            }
            _ => self.problem.push_probe_values(
                &mut row,
                &self.u,
                Some(&self.v_full),
                &self.reaction,
                &self.constraint_of,
            ),
        }
        for (i, pair) in self.problem.contact.iter().enumerate() {
            let s = self.contact_steps.get(i).copied().unwrap_or_default();
            // The force the first body exerts on the second: the rate of the momentum that
            // contact gave the second body's nodes (both passes together, counted once).
            let force = match &self.contact {
                Some(c) => model.bodies[pair.bodies[1]]
                    .nodes
                    .clone()
                    .fold(Vector3::zeros(), |acc, n| acc + c.force[n]),
                None => Vector3::zeros(),
            };
            row.extend(force.iter());
            row.extend([
                s.normal_force,
                s.tangential_force,
                s.active as f64,
                s.sliding as f64,
                s.iterations as f64,
                s.unresolved as f64,
            ]);
        }
        row
    }

    /// The sums over nodes of a history row, folded leaf by leaf across the ranks
    /// ([`crate::distributed::NodePlan::fold`], collective): the momentum, the angular momentum
    /// about the origin and, when there are several bodies, each body's kinetic energy and
    /// momentum (the hammer's energy passing to the beam, thesis Figs. 10.11-10.14; (6.48)).
    fn node_sums(&self) -> Vec<f64> {
        let model = &self.problem.model;
        let per_body = if model.bodies.len() > 1 {
            model.bodies.len()
        } else {
            0
        };
        let width = 6 + 4 * per_body;
        let plan = &self.nodes;
        let mut shares = Vec::with_capacity(width * plan.my_leaves().len());
        for &k in plan.my_leaves() {
            let mut leaf = vec![0.0; width];
            for i in plan.leaf_nodes(k) {
                let (m, v) = (model.mass[i], self.v_full[i]);
                let momentum = v * m;
                // With the full-step velocity: the average of two values leapfrog keeps exactly
                // for torque-free forces, `sum m x_n x v_(n+1/2) = sum m x_(n+1) x v_(n+1/2)`.
                let angular = (model.reference[i] + self.u[i]).cross(&v) * m;
                for d in 0..3 {
                    leaf[d] += momentum[d];
                    leaf[3 + d] += angular[d];
                }
                if per_body > 0 {
                    if let Some(b) = model.bodies.iter().position(|b| b.nodes.contains(&i)) {
                        let at = 6 + 4 * b;
                        leaf[at] += 0.5 * m * v.norm_squared();
                        for d in 0..3 {
                            leaf[at + 1 + d] += momentum[d];
                        }
                    }
                }
            }
            shares.extend(leaf);
        }
        plan.fold(self.ranks.as_ref().map(|r| r.comm()), width, &shares)
    }

    /// Shows the observers the field frame of the current state.
    pub(super) fn field_frame(&mut self, observers: &mut ObserverSet) -> Result<()> {
        let (u, v) = (self.whole(&self.u), self.whole(&self.v_full));
        let model = &self.problem.model;
        // A rank's piece holds its own elements and their nodes, which it stores.
        let points = model.positions_where_stored(&u);
        observers.field_frame(&field_frame_with_history(
            model,
            Some(&self.history),
            &points,
            &u,
            Some(&v),
            self.time,
        ))
    }
}
