//! Implicit static analysis: Newton's method with a sparse LU factorisation (`faer`) and load
//! stepping (thesis 3.3.3, (3.64)-(3.68)). Used by patch tests and for elastic references.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Result, SolverError};
use crate::kinematics::deformation_gradient;
use crate::material::Material;
use crate::model::{Motion, Problem};
use crate::with_material;

/// Settings of a static analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticSettings {
    /// Load steps: prescribed displacements and loads are applied at load factors
    /// `k / load_steps`, evaluated as the time argument of their functions.
    #[serde(default = "default_steps")]
    pub load_steps: usize,
    /// Converged when the out-of-balance force (3.64) on the free components is below
    /// `tolerance` times the largest of the reaction and external force norms.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
}

fn default_steps() -> usize {
    1
}
fn default_tolerance() -> f64 {
    1e-12
}
fn default_iterations() -> usize {
    25
}

impl Default for StaticSettings {
    fn default() -> Self {
        Self {
            load_steps: default_steps(),
            tolerance: default_tolerance(),
            max_iterations: default_iterations(),
        }
    }
}

/// The equilibrium found, with the convergence record of each load step.
#[derive(Debug, Clone)]
pub struct StaticSolution {
    pub u: Vec<Vector3<f64>>,
    /// Reaction forces at prescribed components (N): the internal minus external force there.
    pub reaction: Vec<Vector3<f64>>,
    /// Newton iterations per load step.
    pub iterations: Vec<usize>,
    /// Final relative residual per load step.
    pub residuals: Vec<f64>,
}

impl StaticSolution {
    /// Reaction of constraint `c` of `problem`: the components it owns, summed over its nodes.
    pub fn constraint_reaction(&self, problem: &Problem, c: usize) -> Vector3<f64> {
        let owner = problem.constraint_map();
        let mut sum = Vector3::zeros();
        for &n in &problem.constraints[c].nodes {
            for d in 0..3 {
                if owner[n as usize][d] == Some(c as u16) {
                    sum[d] += self.reaction[n as usize][d];
                }
            }
        }
        sum
    }

    /// Sum of the reactions over `nodes`, all prescribed components.
    pub fn total_reaction(&self, nodes: &[u32]) -> Vector3<f64> {
        nodes
            .iter()
            .fold(Vector3::zeros(), |acc, &n| acc + self.reaction[n as usize])
    }
}

/// Solves `f_int(u) = f_ext` with the constraints of `problem` (velocity constraints are not
/// static conditions and are rejected, and so are bodies of materials with history).
pub fn solve_static(problem: &Problem, settings: &StaticSettings) -> Result<StaticSolution> {
    let model = &problem.model;
    if let Some(body) = model.bodies.iter().find(|b| b.material.has_history()) {
        // Newton's method evaluates the forces at trial displacements, which would advance the
        // history at each of them; it would need a commit per load step and a tangent of the
        // model, which it does not have.
        return Err(SolverError::InvalidScene {
            entity: format!("body `{}` material", body.name),
            message: format!(
                "the static solver does not support {} concrete, whose stress depends on its \
                 loading history. Fix: analyse the scene with `analysis: {{ explicit: ... }}` \
                 (a slow enough loading gives the quasi-static response)",
                body.material.name()
            ),
        });
    }
    let n = model.node_count();
    let constraint_of = problem.constraint_map();
    for c in &problem.constraints {
        if matches!(
            c.motion,
            Motion::Velocity(..) | Motion::AffineVelocity { .. }
        ) {
            return Err(SolverError::InvalidScene {
                entity: format!("constraint `{}`", c.name),
                message: "a velocity condition has no meaning in a static analysis; prescribe a \
                          displacement instead"
                    .into(),
            });
        }
    }
    // Free components get consecutive equation numbers.
    let mut equation = vec![[usize::MAX; 3]; n];
    let mut free = 0;
    for i in 0..n {
        for d in 0..3 {
            if constraint_of[i][d].is_none() {
                equation[i][d] = free;
                free += 1;
            }
        }
    }
    let mut u = vec![Vector3::zeros(); n];
    let mut f_int = vec![Vector3::zeros(); n];
    let mut f_ext = vec![Vector3::zeros(); n];
    let mut iterations = Vec::new();
    let mut residuals = Vec::new();
    let steps = settings.load_steps.max(1);
    for step in 1..=steps {
        let lambda = step as f64 / steps as f64;
        for i in 0..n {
            for d in 0..3 {
                if let Some(c) = constraint_of[i][d] {
                    let motion = &problem.constraints[c as usize].motion;
                    u[i][d] = motion.displacement(&model.reference[i], lambda).unwrap()[d];
                }
            }
        }
        if !problem.external_forces(lambda, &mut f_ext) {
            f_ext.iter_mut().for_each(|f| *f = Vector3::zeros());
        }
        let mut converged = None;
        let mut last_residual = f64::INFINITY;
        for iteration in 0..=settings.max_iterations {
            if let Some(e) = model.internal_forces(&u, &mut f_int) {
                return Err(SolverError::ElementInverted {
                    element: e,
                    det: model.deformation_gradient(e, &u).determinant(),
                });
            }
            let mut residual = vec![0.0; free];
            let (mut reaction_sq, mut external_sq) = (0.0, 0.0);
            for i in 0..n {
                for d in 0..3 {
                    let r = f_int[i][d] - f_ext[i][d];
                    external_sq += f_ext[i][d] * f_ext[i][d];
                    match equation[i][d] {
                        usize::MAX => reaction_sq += r * r,
                        k => residual[k] = r,
                    }
                }
            }
            let scale = reaction_sq.sqrt().max(external_sq.sqrt());
            let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            last_residual = if scale > 0.0 { norm / scale } else { norm };
            if norm <= settings.tolerance * scale || norm == 0.0 {
                converged = Some(iteration);
                break;
            }
            if iteration == settings.max_iterations {
                break;
            }
            let du = solve_tangent(problem, &u, &equation, free, &residual)?;
            for i in 0..n {
                for d in 0..3 {
                    if equation[i][d] != usize::MAX {
                        u[i][d] -= du[equation[i][d]];
                    }
                }
            }
        }
        match converged {
            Some(it) => {
                iterations.push(it);
                residuals.push(last_residual);
            }
            None => {
                return Err(SolverError::StaticNotConverged {
                    step,
                    steps,
                    iterations: settings.max_iterations,
                    residual: last_residual,
                    tolerance: settings.tolerance,
                })
            }
        }
    }
    let reaction = (0..n)
        .map(|i| {
            let mut r = Vector3::zeros();
            for d in 0..3 {
                if constraint_of[i][d].is_some() {
                    r[d] = f_int[i][d] - f_ext[i][d];
                }
            }
            r
        })
        .collect();
    Ok(StaticSolution {
        u,
        reaction,
        iterations,
        residuals,
    })
}

/// Solves `K du = r` on the free components, with the consistent tangent
/// `K_{ai,bj} = V sum_{JL} grad N_aJ (dP_iJ/dF_jL) grad N_bL` (3.68a).
fn solve_tangent(
    problem: &Problem,
    u: &[Vector3<f64>],
    equation: &[[usize; 3]],
    free: usize,
    residual: &[f64],
) -> Result<Vec<f64>> {
    let model = &problem.model;
    let mut triplets = Vec::with_capacity(144 * model.element_count());
    for body in &model.bodies {
        with_material!(&body.material, |m| {
            for e in body.elements.clone() {
                let g = &model.grad_n[e];
                let f = deformation_gradient(&model.element_displacements(e, u), g);
                let tet = model.tets[e];
                for b in 0..4 {
                    for j in 0..3 {
                        let col = equation[tet[b] as usize][j];
                        if col == usize::MAX {
                            continue;
                        }
                        let mut df = Matrix3::zeros();
                        df.set_row(j, &g[b].transpose());
                        let dp = m.first_piola_derivative(&f, &df) * model.volume[e];
                        for a in 0..4 {
                            let force = dp * g[a];
                            for i in 0..3 {
                                let row = equation[tet[a] as usize][i];
                                if row != usize::MAX {
                                    triplets.push(Triplet::new(row, col, force[i]));
                                }
                            }
                        }
                    }
                }
            }
        }, microplane(_) => unreachable!("solve_static refuses materials with history"));
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(free, free, &triplets)
        .map_err(|e| SolverError::SingularStiffness(format!("{e:?}")))?;
    let lu = k
        .sp_lu()
        .map_err(|e| SolverError::SingularStiffness(format!("{e:?}")))?;
    let mut rhs = Mat::from_fn(free, 1, |i, _| residual[i]);
    lu.solve_in_place(rhs.as_mut());
    let du: Vec<f64> = (0..free).map(|i| rhs[(i, 0)]).collect();
    if du.iter().any(|x| !x.is_finite()) {
        return Err(SolverError::SingularStiffness(
            "the solution of the tangent system is not finite".into(),
        ));
    }
    Ok(du)
}
