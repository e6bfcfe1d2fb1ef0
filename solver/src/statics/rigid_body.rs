//! Whether the boundary conditions hold every loaded piece of the model against rigid-body
//! motion, checked before Newton's method starts.
//!
//! A connected piece of the mesh (its elements linked through shared nodes; regions of a body
//! belong to its piece) has six rigid-body motions, `m_k(x) = e_k` (translations) and
//! `m_{3+k}(x) = e_k x (x - c) / L` (rotations about its centroid `c`, scaled by its size `L`).
//! Its stiffness is singular unless its prescribed components restrain all six: the matrix
//! `C` with one row `[m_1(x_n)_d, ..., m_6(x_n)_d]` per prescribed component `(n, d)` must have
//! rank 6, i.e. the Gram matrix `G = C^T C` must have no (relatively) zero eigenvalue. Static
//! analyses model no contact, so contact restrains nothing here.
//!
//! Under a non-zero load such a piece has no static equilibrium, and the sparse LU factorises
//! its singular stiffness with round-off pivots anyway (the out-of-balance force then grows to
//! 1e33 N, read as non-convergence: fuzz finding U4). A piece that nothing loads keeps the zero
//! solution of its block (its right-hand side stays zero), so it is not refused.

use nalgebra::{Matrix6, Vector3, Vector6};

use crate::error::{Result, SolverError};
use crate::problem::Problem;

/// Eigenvalues of `G` below this fraction of its largest count as zero: a restrained slender
/// piece (a 1 m beam 1 cm thick clamped at one end) stays near `(0.01 / 1)^2 = 1e-4`, a free
/// motion at round-off (1e-16).
const ZERO_EIGENVALUE: f64 = 1e-10;

/// A connected piece of the mesh whose prescribed components leave some rigid-body motion free.
pub(super) struct FreePiece {
    /// Names of the model bodies (scene bodies or regions) whose elements form the piece.
    pub bodies: Vec<String>,
    /// Its nodes.
    pub nodes: Vec<usize>,
    /// How many of its six rigid-body motions are free (1 to 6).
    pub free_motions: usize,
}

impl FreePiece {
    /// The error for this piece under a load: names it and says what restrains it.
    pub fn error(&self) -> SolverError {
        let what = if self.free_motions == 6 {
            "no boundary condition acts on it".to_string()
        } else {
            format!(
                "its boundary conditions leave {} of its 6 rigid-body motions (3 translations, 3 \
                 rotations) free",
                self.free_motions
            )
        };
        SolverError::SingularStiffness(format!(
            "body `{}` is loaded but can move as a rigid body: {what}, and a static analysis \
             models no contact, so it has no static equilibrium; prescribe displacements that \
             hold all three translations and all three rotations",
            self.bodies.join("`, `")
        ))
    }
}

/// The connected pieces of `problem`'s mesh that its boundary conditions leave free to move as
/// a rigid body (`constraint_of` from [`Problem::constraint_map`]), in the order of their first
/// node.
pub(super) fn free_pieces(problem: &Problem, constraint_of: &[[Option<u16>; 3]]) -> Vec<FreePiece> {
    let model = &problem.model;
    let n = model.node_count();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for tet in &model.tets {
        let mut a = root(&mut parent, tet[0] as usize);
        for &node in &tet[1..] {
            let b = root(&mut parent, node as usize);
            // The smaller index is the root: the pieces do not depend on the element order.
            let (low, high) = (a.min(b), a.max(b));
            parent[high] = low;
            a = low;
        }
    }
    let mut piece_of = vec![usize::MAX; n];
    let mut pieces: Vec<Vec<usize>> = Vec::new();
    let mut index_of_root = std::collections::BTreeMap::new();
    for tet in &model.tets {
        for &node in tet {
            let node = node as usize;
            if piece_of[node] != usize::MAX {
                continue;
            }
            let r = root(&mut parent, node);
            let index = *index_of_root.entry(r).or_insert_with(|| {
                pieces.push(Vec::new());
                pieces.len() - 1
            });
            piece_of[node] = index;
            pieces[index].push(node);
        }
    }
    let mut free = Vec::new();
    for (index, nodes) in pieces.into_iter().enumerate() {
        let free_motions = free_motions(problem, constraint_of, &nodes);
        if free_motions == 0 {
            continue;
        }
        let bodies = model
            .bodies
            .iter()
            .filter(|b| {
                b.elements
                    .clone()
                    .any(|e| piece_of[model.tets[e][0] as usize] == index)
            })
            .map(|b| b.name.clone())
            .collect();
        free.push(FreePiece {
            bodies,
            nodes,
            free_motions,
        });
    }
    free
}

/// The number of rigid-body motions of the piece over `nodes` that its prescribed components
/// leave free: the eigenvalues of `G = C^T C` (module documentation) that are zero.
fn free_motions(problem: &Problem, constraint_of: &[[Option<u16>; 3]], nodes: &[usize]) -> usize {
    let x = &problem.model.reference;
    let centroid = nodes.iter().fold(Vector3::zeros(), |s, &i| s + x[i]) / nodes.len() as f64;
    let size = nodes
        .iter()
        .map(|&i| (x[i] - centroid).norm())
        .fold(0.0_f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut gram = Matrix6::zeros();
    for &i in nodes {
        let arm = (x[i] - centroid) / size;
        for d in 0..3 {
            if constraint_of[i][d].is_none() {
                continue;
            }
            let mut row = Vector6::zeros();
            row[d] = 1.0;
            for k in 0..3 {
                // Component d of e_k x arm.
                row[3 + k] = Vector3::ith(k, 1.0).cross(&arm)[d];
            }
            gram += row * row.transpose();
        }
    }
    let eigenvalues = gram.symmetric_eigenvalues();
    let largest = eigenvalues.iter().fold(0.0_f64, |a, &v| a.max(v));
    eigenvalues
        .iter()
        .filter(|&&v| v <= ZERO_EIGENVALUE * largest || largest == 0.0)
        .count()
}

/// Refuses a load on a piece that can move as a rigid body: `Err` naming the piece if any of
/// `pieces` carries a non-zero force in `f_ext`.
pub(super) fn check_loaded(pieces: &[FreePiece], f_ext: &[Vector3<f64>]) -> Result<()> {
    match pieces
        .iter()
        .find(|p| p.nodes.iter().any(|&i| f_ext[i] != Vector3::zeros()))
    {
        Some(piece) => Err(piece.error()),
        None => Ok(()),
    }
}
