//! Contact (thesis chapters 6 and 7).

pub mod broad_phase;
pub mod ccd;
pub mod conic;
pub mod detection;
pub mod gauss_seidel;
pub mod local;
pub mod nsgs;
pub mod normals;
pub mod problem;
pub mod problem_file;
pub mod solver;
#[cfg(test)]
mod test_blocks;

use nalgebra::Vector3;

use crate::model::Model;
use detection::{detect, ContactSurface, DetectionSettings, DetectionStats};
use gauss_seidel::{gauss_seidel, GaussSeidelSettings};
use normals::NormalSettings;

/// Two bodies that may touch, and how their contact is solved (FORMULATION section 4).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    pub name: String,
    pub bodies: [usize; 2],
    /// Coulomb coefficient; `f64::INFINITY` sticks, `0` is frictionless.
    pub friction: f64,
    /// `beta = beta_0 + 1/2` of the beta-2 corrections; 0 is exactly central differences.
    pub beta_0: f64,
    pub solver: GaussSeidelSettings,
    /// Tolerance on barycentric coordinates in detection.
    pub detection_tolerance: f64,
    /// Repeat detection and resolution with the slave and master roles swapped (7.2).
    pub two_pass: bool,
    pub normals: NormalSettings,
}

/// What the contact phase did in one step, per pair.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStep {
    pub active: usize,
    pub iterations: usize,
    pub converged: bool,
    pub unresolved: usize,
    /// Sum of the normal components of the contact multipliers `r`; the time stepper turns
    /// multipliers into forces (N).
    pub normal_force: f64,
    /// Sum of the magnitudes of the tangential components, as `normal_force`.
    pub tangential_force: f64,
    /// Contacts whose force lies on the Coulomb cone (sliding).
    pub sliding: usize,
}

/// The contact phase of a run: the pairs with their surfaces, computed once.
#[derive(Debug, Clone)]
pub struct ContactPhase {
    pub pairs: Vec<ContactPair>,
    surfaces: Vec<[ContactSurface; 2]>,
}

impl ContactPhase {
    pub fn new(model: &Model, pairs: Vec<ContactPair>) -> Self {
        let surfaces = pairs
            .iter()
            .map(|p| p.bodies.map(|b| ContactSurface::new(model, b)))
            .collect();
        Self { pairs, surfaces }
    }

    /// Detects and removes penetrations of the predicted positions `x1` (corrected in place)
    /// given the positions `x0` at the start of the step, pair by pair and pass by pass.
    ///
    /// `tangential` receives the part of the corrections made by the tangential (friction)
    /// components of the contact forces, so friction work can be told from normal work; the
    /// corrections are linear in the forces, so it is the correction of the final tangential
    /// forces.
    pub fn resolve(
        &self,
        model: &Model,
        inverse_mass: &[Vector3<f64>],
        dt: f64,
        x0: &[Vector3<f64>],
        x1: &mut [Vector3<f64>],
        tangential: &mut [Vector3<f64>],
    ) -> Vec<ContactStep> {
        self.pairs
            .iter()
            .zip(&self.surfaces)
            .map(|(pair, [a, b])| {
                let mut step = ContactStep {
                    converged: true,
                    ..Default::default()
                };
                let settings = DetectionSettings {
                    tolerance: pair.detection_tolerance,
                    friction: pair.friction,
                    normals: pair.normals,
                };
                let passes: &[(&ContactSurface, &ContactSurface)] = if pair.two_pass {
                    &[(a, b), (b, a)]
                } else {
                    &[(a, b)]
                };
                for (slave, master) in passes {
                    let (mut constraints, stats): (Vec<_>, DetectionStats) =
                        detect(model, slave, master, x0, x1, &settings);
                    step.unresolved += stats.unresolved;
                    // A contact whose normal no node can move along (all prescribed) cannot be
                    // enforced: reported with the unresolved ones, not dropped silently.
                    let before = constraints.len();
                    constraints.retain(|c| {
                        let w = c.delassus_diagonal(inverse_mass, 1.0);
                        c.normal.dot(&w.component_mul(&c.normal)) > 0.0
                    });
                    step.unresolved += before - constraints.len();
                    if constraints.is_empty() {
                        continue;
                    }
                    let beta_dt2 = (pair.beta_0 + 0.5) * dt * dt;
                    let solution =
                        gauss_seidel(&constraints, inverse_mass, beta_dt2, x1, &pair.solver);
                    step.iterations += solution.iterations;
                    step.converged &= solution.converged;
                    for (c, r) in constraints.iter().zip(&solution.forces) {
                        if *r != Vector3::zeros() {
                            step.active += 1;
                            let rn = r.dot(&c.normal);
                            let rt = r - c.normal * rn;
                            step.normal_force += rn;
                            step.tangential_force += rt.norm();
                            step.sliding += usize::from(c.slides(r));
                            c.apply(&rt, inverse_mass, beta_dt2, tangential);
                        }
                    }
                }
                step
            })
            .collect()
    }
}
