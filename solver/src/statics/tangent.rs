//! The tangent stiffness of a static Newton iteration (3.66) and the solve with it.
//!
//! An element's stiffness is the consistent tangent of its material (3.68a) where the model has
//! one in closed form; otherwise the forward difference of its forces from the committed history,
//! `K_e[:, j] = (f_e(u_e + delta e_j) - f_e(u_e)) / delta` with `delta = 1e-10 h_e` (the module
//! documentation of `path` says why this step).

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::conjugate_gradient::{self, SymmetricCsr};
use crate::error::{Result, SolverError};
use crate::kinematics::deformation_gradient;
use crate::material::ElementState;
use crate::model::{BodyMaterial, MaterialHistory, Model};
use crate::problem::Problem;

/// Relative size of the forward-difference step of the element tangent, times the element size:
/// small enough not to cross the loading-unloading kinks of planes near their turning points,
/// large against the round-off of the forces (the module documentation of `path` says why).
const DIFFERENCE_STEP: f64 = 1e-10;

/// Whether a material has a closed-form consistent tangent (its derivative is defined at any
/// deformation, so asking at the reference one answers).
fn has_closed_form_tangent(material: &dyn BodyMaterial) -> bool {
    material
        .first_piola_derivative(&Matrix3::identity(), &Matrix3::zeros())
        .is_some()
}

/// The consistent stiffness of element `e` at `u`,
/// `K_{ai,bj} = V sum_{JL} grad N_aJ (dP_iJ/dF_jL) grad N_bL` (3.68a), as
/// `K[col * 12 + row]` (see [`ElementTangent`]); `None` without a closed-form tangent.
fn consistent_tangent(
    material: &dyn BodyMaterial,
    model: &Model,
    e: usize,
    u: &[Vector3<f64>],
) -> Option<ElementTangent> {
    let g = &model.grad_n(e);
    let f = deformation_gradient(&model.element_displacements(e, u), g);
    let mut k = [0.0; 144];
    for b in 0..4 {
        for j in 0..3 {
            let mut df = Matrix3::zeros();
            df.set_row(j, &g[b].transpose());
            let dp = material.first_piola_derivative(&f, &df)? * model.volume(e);
            for a in 0..4 {
                let force = dp * g[a];
                for i in 0..3 {
                    k[(3 * b + j) * 12 + 3 * a + i] = force[i];
                }
            }
        }
    }
    Some(k)
}

/// Forward-difference stiffness of every element of every body whose material has no
/// closed-form tangent (empty for the other bodies), from the `committed` history at
/// displacement `u`: each difference starts from the element's committed history, never from a
/// trial update.
pub(super) fn forward_difference_tangents(
    problem: &Problem,
    u: &[Vector3<f64>],
    committed: &MaterialHistory,
) -> Vec<Vec<ElementTangent>> {
    let model = &problem.model;
    model
        .bodies
        .iter()
        .zip(&committed.bodies)
        .map(|(body, history)| {
            let material = &*body.material;
            if has_closed_form_tangent(material) {
                return Vec::new();
            }
            let len = material.history_len();
            body.elements
                .clone()
                .into_par_iter()
                // One scratch history per worker, not one allocation per element.
                .map_init(
                    || vec![0.0_f32; len],
                    |state, e| {
                        let local = e - body.elements.start;
                        let forces = |state: &mut Vec<f32>, ue: &[Vector3<f64>; 4]| {
                            if let Some(h) = history {
                                state.copy_from_slice(h.element(local));
                            }
                            material
                                .static_element_forces(
                                    local,
                                    &model.grad_n(e),
                                    model.volume(e),
                                    ue,
                                    ElementState {
                                        history: state,
                                        cauchy: None,
                                    },
                                )
                                .forces
                        };
                        let ue = model.element_displacements(e, u);
                        let base = forces(state, &ue);
                        let delta = DIFFERENCE_STEP * model.element_size(e);
                        let mut k = [0.0; 144];
                        for col in 0..12 {
                            let mut moved = ue;
                            moved[col / 3][col % 3] += delta;
                            let f = forces(state, &moved);
                            for row in 0..12 {
                                k[col * 12 + row] =
                                    (f[row / 3][row % 3] - base[row / 3][row % 3]) / delta;
                            }
                        }
                        k
                    },
                )
                .collect()
        })
        .collect()
}

/// Calls `add(e, K_e)` for every element `e` in order, with its consistent tangent (3.68a) where
/// its material has one, and otherwise the stiffness in `tangents[body]` (one [`ElementTangent`]
/// per element of the body, in its order; from [`forward_difference_tangents`]).
fn for_each_element_stiffness(
    problem: &Problem,
    u: &[Vector3<f64>],
    tangents: &[Vec<ElementTangent>],
    mut add: impl FnMut(usize, &ElementTangent),
) -> Result<()> {
    let model = &problem.model;
    for (b_index, body) in model.bodies.iter().enumerate() {
        let differences = tangents.get(b_index).filter(|t| !t.is_empty());
        if let Some(differences) = differences {
            if differences.len() != body.elements.len() {
                return Err(SolverError::SingularStiffness(format!(
                    "body `{}`: {} element tangents for {} elements",
                    body.name,
                    differences.len(),
                    body.elements.len()
                )));
            }
        }
        for e in body.elements.clone() {
            let local = e - body.elements.start;
            let closed_form;
            let k = match differences {
                Some(d) => &d[local],
                None => {
                    closed_form =
                        consistent_tangent(&*body.material, model, e, u).ok_or_else(|| {
                            SolverError::SingularStiffness(format!(
                            "body `{}`: its material ({}) has no closed-form tangent and none was \
                             differenced",
                            body.name,
                            body.material.name()
                        ))
                        })?;
                    &closed_form
                }
            };
            add(e, k);
        }
    }
    Ok(())
}

/// What a static iteration's system has besides the element stiffnesses.
#[derive(Default, Clone, Copy)]
pub(super) struct TangentTerms<'a> {
    /// Prescribed components that move together by one unknown (an
    /// [`super::OpeningControl`]), by node.
    pub moved: Option<&'a [[bool; 3]]>,
    /// A diagonal added on the free components, by equation (a relaxed step's `M / tau^2`,
    /// `relaxation.rs`).
    pub diagonal: Option<&'a [f64]>,
}

/// Solves `K du = r` on the free components by sparse LU (`faer`), `K` assembled from the
/// element stiffnesses of [`for_each_element_stiffness`] and the diagonal of `terms`. With its
/// `moved` components, also solves `K b = k` for the sum `k` of their columns, and returns `b`
/// second.
pub(super) fn solve_tangent(
    problem: &Problem,
    u: &[Vector3<f64>],
    equation: &[[usize; 3]],
    free: usize,
    residual: &[f64],
    tangents: &[Vec<ElementTangent>],
    terms: TangentTerms,
) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
    let TangentTerms { moved, diagonal } = terms;
    let model = &problem.model;
    let mut triplets = Vec::with_capacity(144 * model.element_count() + free);
    if let Some(shift) = diagonal {
        triplets.extend(
            shift
                .iter()
                .enumerate()
                .map(|(i, &s)| Triplet::new(i, i, s)),
        );
    }
    let mut moved_column = moved.map(|_| vec![0.0; free]);
    // Where column (node, component) goes: its equation, or the moved column, or nowhere.
    let is_moved = |node: usize, d: usize| moved.is_some_and(|m| m[node][d]);
    for_each_element_stiffness(problem, u, tangents, |e, k| {
        let tet = model.tets[e];
        for (col_dof, &node_b) in (0..12).zip(tet.iter().flat_map(|n| [n; 3])) {
            let col = equation[node_b as usize][col_dof % 3];
            let into_moved = col == usize::MAX && is_moved(node_b as usize, col_dof % 3);
            if col == usize::MAX && !into_moved {
                continue;
            }
            for (row_dof, &node_a) in (0..12).zip(tet.iter().flat_map(|n| [n; 3])) {
                let row = equation[node_a as usize][row_dof % 3];
                if row == usize::MAX {
                    continue;
                }
                let value = k[col_dof * 12 + row_dof];
                match (&mut moved_column, into_moved) {
                    (Some(column), true) => column[row] += value,
                    _ => triplets.push(Triplet::new(row, col, value)),
                }
            }
        }
    })?;
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(free, free, &triplets)
        .map_err(|e| SolverError::SingularStiffness(format!("{e:?}")))?;
    let lu = k
        .sp_lu()
        .map_err(|e| SolverError::SingularStiffness(format!("{e:?}")))?;
    let columns = 1 + usize::from(moved_column.is_some());
    let mut rhs = Mat::from_fn(free, columns, |i, j| match j {
        0 => residual[i],
        _ => moved_column.as_ref().map_or(0.0, |k| k[i]),
    });
    lu.solve_in_place(rhs.as_mut());
    if (0..columns).any(|j| (0..free).any(|i| !rhs[(i, j)].is_finite())) {
        return Err(SolverError::SingularStiffness(
            "the solution of the tangent system is not finite".into(),
        ));
    }
    let du = (0..free).map(|i| rhs[(i, 0)]).collect();
    let b = moved_column.map(|_| (0..free).map(|i| rhs[(i, 1)]).collect());
    Ok((du, b))
}

/// Stiffness of one element, `K[col * 12 + row] = d f_row / d u_col` with the element's degrees
/// of freedom numbered `3 a + i` (node `a` of the tetrahedron, component `i`).
pub type ElementTangent = [f64; 144];

/// Solves `K_s du = r` on the free components by conjugate gradients ([`conjugate_gradient`]),
/// to `|r - K_s du| <= tolerance |r|`, with `K_s = (K + K^T) / 2` the symmetric part of the
/// stiffness of [`for_each_element_stiffness`]: conjugate gradients need a symmetric matrix. The
/// tangent of a hyperelastic material is symmetric; that of the co-rotated linear elastic model
/// (Cauchy-elastic) differs from its symmetric part by terms of the order of the stress over the
/// modulus, so Newton's iteration with `K_s` still contracts by about that factor per iteration,
/// and its converged state, where the out-of-balance force vanishes, is the same. Returns the
/// iterations taken.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_tangent_spd(
    problem: &Problem,
    u: &[Vector3<f64>],
    equation: &[[usize; 3]],
    free: usize,
    residual: &[f64],
    tangents: &[Vec<ElementTangent>],
    tolerance: f64,
    max_iterations: usize,
) -> Result<(Vec<f64>, usize)> {
    let model = &problem.model;
    let mut k_s = SymmetricCsr::element_pattern(&model.tets, equation, free);
    for_each_element_stiffness(problem, u, tangents, |e, k| {
        let dofs = model.tets[e].map(|n| equation[n as usize]);
        for col_dof in 0..12 {
            let col = dofs[col_dof / 3][col_dof % 3];
            if col == usize::MAX {
                continue;
            }
            for row_dof in 0..12 {
                let row = dofs[row_dof / 3][row_dof % 3];
                if row != usize::MAX {
                    let symmetric = 0.5 * (k[col_dof * 12 + row_dof] + k[row_dof * 12 + col_dof]);
                    k_s.add(row, col, symmetric);
                }
            }
        }
    })?;
    let (mut x, iterations) =
        conjugate_gradient::solve(&k_s, &[residual], tolerance, max_iterations)?;
    let du = x.pop().expect("one solution per right-hand side");
    if du.iter().any(|v| !v.is_finite()) {
        return Err(SolverError::SingularStiffness(
            "the solution of the tangent system is not finite".into(),
        ));
    }
    Ok((du, iterations))
}
