//! The contact phase of the time stepper (thesis chapter 6, 7.2): per pair and pass, detection
//! turns the predicted positions into constraints, and the pair's solver, called through
//! [`ContactSolver`] (matrix-free where it can, on the assembled problem otherwise), corrects
//! them.

use nalgebra::Vector3;

use super::detection::{CcdCall, ContactSurface, DetectionSettings, DetectionStats, Detector};
use super::gauss_seidel::ContactConstraint;
use super::problem::ContactProblem;
use super::registry::SolverChoice;
use super::solver::{ContactSolver, PositionProblem};
use super::{ContactPair, ContactStep, RecordedCcdQuery, RecordedProblem};
use crate::model::Model;

/// The contact phase of a run: the pairs with their surfaces and solvers, made once.
pub struct ContactPhase {
    /// The contact pairs of the problem, in scene order.
    pub pairs: Vec<ContactPair>,
    surfaces: Vec<[ContactSurface; 2]>,
    /// Each pair's detection of its two passes, kept over the run (boxes refitted, not
    /// rebuilt).
    detectors: Vec<[Detector; 2]>,
    /// One solver per pair, built once from its [`SolverChoice`]: the stepper calls every
    /// algorithm through [`ContactSolver`]; one virtual call per solve, none per contact.
    solvers: Vec<Box<dyn ContactSolver + Send>>,
    /// Problems recorded so far (pairs with `record_every`).
    pub recorded: Vec<RecordedProblem>,
    /// CCD queries recorded so far (pairs with `record_ccd_every`).
    pub recorded_ccd: Vec<RecordedCcdQuery>,
    /// The nodes the last [`Self::resolve`] may have moved (those of its solved constraints),
    /// ascending and without repeats.
    touched: Vec<u32>,
}

/// Whether the face `f` (node ids into `x`) lies on a plane of symmetry: its normal is along an
/// axis `d` (within 1e-6 of its length), and every node is held along `d` and free along
/// another axis (a symmetry or roller boundary, not a clamped face, which stays a wall).
pub fn symmetry_face(x: &[Vector3<f64>], f: &[u32; 3], held: &[[bool; 3]]) -> bool {
    let [a, b, c] = f.map(|n| x[n as usize]);
    let n = (b - a).cross(&(c - a));
    let norm = n.norm();
    if !(norm > 0.0) {
        return false;
    }
    let Some(d) = (0..3).find(|&d| n[d].abs() > (1.0 - 1e-6) * norm) else {
        return false;
    };
    f.iter().all(|&i| {
        let h = held[i as usize];
        h[d] && (0..3).any(|e| e != d && !h[e])
    })
}

impl ContactPhase {
    /// Extracts each pair's two boundary surfaces from `model` and builds its solver.
    pub fn new(model: &Model, pairs: Vec<ContactPair>) -> Self {
        Self::with_held(model, pairs, &[])
    }

    /// As [`Self::new`], with `held[n][d]` whether component `d` of node `n` is prescribed
    /// (empty: none), which the pairs with `skip_symmetry_faces` read to leave out the faces
    /// on a plane of symmetry (`symmetry_face`).
    pub fn with_held(model: &Model, pairs: Vec<ContactPair>, held: &[[bool; 3]]) -> Self {
        let surfaces = pairs
            .iter()
            .map(|p| {
                p.bodies.map(|b| {
                    if p.skip_symmetry_faces && !held.is_empty() {
                        ContactSurface::with_faces(model, b, |f| {
                            !symmetry_face(&model.reference, f, held)
                        })
                    } else {
                        ContactSurface::new(model, b)
                    }
                })
            })
            .collect();
        let solvers = pairs.iter().map(|p| p.solver.kind.build()).collect();
        let detectors = pairs.iter().map(|_| Default::default()).collect();
        Self {
            pairs,
            surfaces,
            detectors,
            solvers,
            recorded: Vec::new(),
            recorded_ccd: Vec::new(),
            touched: Vec::new(),
        }
    }

    /// The nodes the last [`Self::resolve`] may have moved, ascending: the slave nodes and
    /// master-face nodes of the constraints it solved. Every other node's `x1` and
    /// `tangential` are as they were passed in.
    pub fn touched_nodes(&self) -> &[u32] {
        &self.touched
    }

    /// The nodes whose predicted positions contact reads, ascending: those of the
    /// boundary-layer elements of every pair's surfaces (global detection tests slave nodes
    /// against these elements).
    pub fn layer_nodes(&self, model: &Model) -> Vec<u32> {
        let mut nodes: Vec<u32> = self
            .surfaces
            .iter()
            .flatten()
            .flat_map(|s| s.layer.iter().flat_map(|&e| model.tets[e as usize]))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The boundary nodes of every pair's surfaces, ascending: the only nodes whose start
    /// positions contact reads and the only ones its solvers move.
    pub fn surface_nodes(&self) -> Vec<u32> {
        let mut nodes: Vec<u32> = self
            .surfaces
            .iter()
            .flatten()
            .flat_map(|s| s.nodes.iter().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// Detects and removes penetrations of the predicted positions `x1` (corrected in place)
    /// given the positions `x0` at the start of the step, pair by pair and pass by pass. Only
    /// `x1` of [`Self::layer_nodes`] and `x0` of [`Self::surface_nodes`] are read, and only
    /// the surface nodes are moved.
    ///
    /// `tangential` receives the part of the corrections made by the tangential (friction)
    /// components of the contact forces, so friction work can be told from normal work; the
    /// corrections are linear in the forces, so it is the correction of the final tangential
    /// forces.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(
        &mut self,
        step_index: usize,
        model: &Model,
        inverse_mass: &[Vector3<f64>],
        dt: f64,
        x0: &[Vector3<f64>],
        x1: &mut [Vector3<f64>],
        tangential: &mut [Vector3<f64>],
    ) -> Vec<ContactStep> {
        let recorded = &mut self.recorded;
        let recorded_ccd = &mut self.recorded_ccd;
        let touched = &mut self.touched;
        touched.clear();
        let steps = self
            .pairs
            .iter()
            .zip(&self.surfaces)
            .zip(&mut self.solvers)
            .zip(&mut self.detectors)
            .map(|(((pair, [a, b]), solver), detectors)| {
                let mut step = ContactStep {
                    converged: true,
                    ..Default::default()
                };
                let settings = DetectionSettings {
                    tolerance: pair.detection_tolerance,
                    friction: pair.friction,
                    normals: pair.normals,
                    release: pair.penetration_release_speed * dt,
                };
                let passes: &[(&ContactSurface, &ContactSurface)] = if pair.two_pass {
                    &[(a, b), (b, a)]
                } else {
                    &[(a, b)]
                };
                let record = pair
                    .record_every
                    .is_some_and(|every| every > 0 && step_index % every == 0);
                let record_ccd = pair
                    .record_ccd_every
                    .is_some_and(|every| every > 0 && step_index % every == 0);
                let mut calls: Vec<CcdCall> = Vec::new();
                for ((pass, (slave, master)), detector) in
                    passes.iter().enumerate().zip(detectors.iter_mut())
                {
                    let (mut constraints, stats): (Vec<_>, DetectionStats) = detector.detect(
                        model,
                        slave,
                        master,
                        x0,
                        x1,
                        &settings,
                        record_ccd.then_some(&mut calls),
                    );
                    recorded_ccd.extend(calls.drain(..).map(|c| RecordedCcdQuery {
                        step: step_index,
                        pair: pair.name.clone(),
                        pass,
                        node: c.node,
                        face: c.face,
                        tolerance: c.tolerance,
                        hit: c.hit,
                    }));
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
                    touched.extend(
                        constraints
                            .iter()
                            .flat_map(|c| [c.slave, c.face[0], c.face[1], c.face[2]]),
                    );
                    let beta_dt2 = (pair.beta_0 + 0.5) * dt * dt;
                    let position_problem = PositionProblem {
                        constraints: &constraints,
                        inverse_mass,
                        beta_dt2,
                    };
                    // Assembled before any correction, from the predicted positions: the
                    // problem the solver sees is the one recorded.
                    let assemble = |x1: &[Vector3<f64>]| {
                        let source = format!("pair `{}` step {step_index} pass {pass}", pair.name);
                        ContactProblem::from_constraints(
                            &constraints,
                            inverse_mass,
                            beta_dt2,
                            x1,
                            source,
                        )
                    };
                    let mut assembled = record.then(|| assemble(x1));
                    let (forces, iterations, converged) = match solver.solve_matrix_free(
                        &position_problem,
                        x1,
                        &pair.solver.limits,
                    ) {
                        Some(s) => (s.forces, s.iterations, s.converged),
                        None => {
                            let problem = assembled.get_or_insert_with(|| assemble(x1));
                            let solved = assembled_forces(solver.as_mut(), problem, &pair.solver);
                            for (c, r) in constraints.iter().zip(&solved.0) {
                                c.apply(r, inverse_mass, beta_dt2, x1);
                            }
                            solved
                        }
                    };
                    step.solves += 1;
                    step.iterations += iterations;
                    step.converged &= converged;
                    step.not_converged += usize::from(!converged);
                    if let (true, Some(problem)) = (record, assembled) {
                        let r = problem.to_local(&forces).expect("our problems have frames");
                        recorded.push(RecordedProblem {
                            step: step_index,
                            pair: pair.name.clone(),
                            pass,
                            problem,
                            solver: pair.solver.kind.name().to_string(),
                            r,
                            converged,
                        });
                    }
                    tally(
                        &mut step,
                        &constraints,
                        &forces,
                        inverse_mass,
                        beta_dt2,
                        tangential,
                    );
                }
                step
            })
            .collect();
        touched.sort_unstable();
        touched.dedup();
        steps
    }
}

/// Adds the forces of one solved pass to the step's totals, and their tangential parts'
/// corrections to `tangential`.
fn tally(
    step: &mut ContactStep,
    constraints: &[ContactConstraint],
    forces: &[Vector3<f64>],
    inverse_mass: &[Vector3<f64>],
    beta_dt2: f64,
    tangential: &mut [Vector3<f64>],
) {
    // Interior-point multipliers of released contacts are tiny rather than zero.
    let floor = 1e-9 * forces.iter().fold(0.0f64, |m, r| m.max(r.norm()));
    for (c, r) in constraints.iter().zip(forces) {
        if r.norm() > floor {
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

/// Solves an assembled problem through the trait and returns the global forces, the
/// iterations and whether it converged. A solver that fails or cannot be set up leaves the
/// contacts without force: the step reports it as not converged, and the penetration stays
/// visible in the history instead of stopping the run.
fn assembled_forces(
    solver: &mut dyn ContactSolver,
    problem: &ContactProblem,
    choice: &SolverChoice,
) -> (Vec<Vector3<f64>>, usize, bool) {
    match solver.solve(problem, &choice.limits) {
        Ok(report) => (
            problem
                .to_global(&report.r)
                .expect("our problems have frames"),
            report.iterations,
            report.status.converged(),
        ),
        Err(_) => (vec![Vector3::zeros(); problem.contacts()], 0, false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face on the plane x = 0 whose nodes are held in x only is a symmetry face; held in
    /// every direction it is a clamped wall and stays; a node free in x, or a face not normal
    /// to an axis, makes it an ordinary face.
    #[test]
    fn symmetry_faces_are_those_held_along_their_axis_only() {
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.1, 0.0, 1.0),
        ];
        let roller = [true, false, false];
        let f = [0, 1, 2];
        assert!(symmetry_face(&x, &f, &[roller; 4]));
        assert!(!symmetry_face(&x, &f, &[[true; 3]; 4]), "clamped: a wall");
        assert!(!symmetry_face(
            &x,
            &f,
            &[roller, roller, [false; 3], roller]
        ));
        assert!(!symmetry_face(&x, &[0, 1, 3], &[roller; 4]), "tilted face");
    }
    use crate::contact::ccd;
    use crate::contact::solver::SolveLimits;
    use crate::contact::test_blocks::elastic_boxes;
    use crate::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
    use crate::mesh::BoxSpec;
    use crate::problem::Problem;

    /// A small block dropped at 2 m/s onto a larger one, 0.1 mm above it, non-matching meshes,
    /// with friction, two passes.
    fn falling_block(record_ccd_every: Option<usize>) -> Problem {
        let model = elastic_boxes(&[
            BoxSpec {
                origin: [0.0; 3],
                size: [0.1, 0.1, 0.05],
                divisions: [4, 4, 2],
                mirror: Vec::new(),
            },
            BoxSpec {
                origin: [0.013, 0.021, 0.0501],
                size: [0.07, 0.06, 0.05],
                divisions: [3, 3, 2],
                mirror: Vec::new(),
            },
        ]);
        let mut p = Problem::new(model);
        for n in p.model.bodies[1].nodes.clone() {
            p.initial_velocity[n] = Vector3::new(0.3, 0.0, -2.0);
        }
        p.contact.push(ContactPair {
            name: "drop".into(),
            bodies: [0, 1],
            friction: 0.3,
            beta_0: 0.0,
            solver: SolverChoice {
                kind: crate::contact::registry::SolverKind::GaussSeidelThesis,
                limits: SolveLimits {
                    tolerance: 1e-12,
                    max_iterations: 5000,
                    time_limit: None,
                },
            },
            record_every: None,
            record_ccd_every,
            detection_tolerance: 1e-9,
            two_pass: true,
            normals: Default::default(),
            skip_symmetry_faces: false,
            penetration_release_speed: f64::INFINITY,
        });
        p
    }

    fn run(p: &Problem) -> (Vec<Vector3<f64>>, Vec<RecordedCcdQuery>) {
        let mut settings = ExplicitSettings::new(2e-4);
        settings.safety = 0.6;
        let mut solver = ExplicitSolver::new(p, settings, OutputSettings::default()).unwrap();
        solver.run(&mut |_| {}).unwrap();
        (
            solver.whole(&solver.u).into_owned(),
            solver.take_recorded_ccd_queries(),
        )
    }

    #[test]
    fn recording_ccd_queries_changes_nothing_and_records_our_answers() {
        let (u_plain, none) = run(&falling_block(None));
        assert!(none.is_empty());
        let (u_every, all) = run(&falling_block(Some(1)));
        let (u_third, thirds) = run(&falling_block(Some(3)));
        let bits = |u: &[Vector3<f64>]| -> Vec<u64> {
            u.iter()
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .collect()
        };
        assert_eq!(bits(&u_plain), bits(&u_every), "recording changed the run");
        assert_eq!(bits(&u_plain), bits(&u_third), "recording changed the run");
        assert!(u_plain.iter().any(|x| x.z != 0.0));

        let hits = all.iter().filter(|q| q.hit.is_some()).count();
        eprintln!("{} CCD queries recorded, {hits} hits", all.len());
        assert!(hits > 0 && hits < all.len(), "{hits} of {}", all.len());
        assert!(all.iter().any(|q| q.pass == 1) && all.iter().any(|q| q.pass == 0));
        for q in &all {
            assert_eq!(q.pair, "drop");
            let again =
                ccd::vertex_face_ccd(&q.node, [&q.face[0], &q.face[1], &q.face[2]], q.tolerance);
            assert_eq!(
                again.map(|h| h.t.to_bits()),
                q.hit.map(f64::to_bits),
                "{q:?}"
            );
        }
        // Every third step: exactly the queries of those steps.
        let expected: Vec<&RecordedCcdQuery> = all.iter().filter(|q| q.step % 3 == 0).collect();
        assert!(!thirds.is_empty());
        assert_eq!(thirds.iter().collect::<Vec<_>>(), expected);
    }
}
