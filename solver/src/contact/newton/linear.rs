//! The Newton system `J d = -Phi` with `J = A + B W` (`A`, `B` block diagonal, the per-contact
//! derivatives of the Alart-Curnier function in `r` and in `u`), solved by `faer`: a dense LU
//! with partial pivoting for small problems, a sparse LU otherwise.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

use super::alart_curnier::AlartCurnierPiece;
use crate::contact::problem::SparseMatrix;

/// Up to this many unknowns the system is solved dense: a dense LU of 300 unknowns costs about
/// 1e7 flops, below the symbolic analysis of a sparse one.
pub const DENSE_UP_TO: usize = 300;

/// The entries of `J = A + B W` as triplets: row `3a + i` holds `A_a[i, :]` on the contact's own
/// columns and `sum_k B_a[i, k] W[3a + k, :]`.
pub fn jacobian_triplets(
    w: &SparseMatrix,
    pieces: &[AlartCurnierPiece],
) -> Vec<Triplet<usize, usize, f64>> {
    let mut triplets = Vec::with_capacity(3 * w.nonzeros() + 9 * pieces.len());
    for (a, piece) in pieces.iter().enumerate() {
        for i in 0..3 {
            for j in 0..3 {
                let v = piece.d_r[(i, j)];
                if v != 0.0 {
                    triplets.push(Triplet::new(3 * a + i, 3 * a + j, v));
                }
            }
            for k in 0..3 {
                let b = piece.d_u[(i, k)];
                if b == 0.0 {
                    continue;
                }
                for (col, v) in w.row(3 * a + k) {
                    triplets.push(Triplet::new(3 * a + i, col, b * v));
                }
            }
        }
    }
    triplets
}

/// Solves `J d = rhs`; `J` from [`jacobian_triplets`] plus `shift` on its diagonal (a
/// Levenberg-Marquardt term, zero on the first try). `None` when the factorization fails or the
/// solution is not finite (a singular `J`).
pub fn solve(
    size: usize,
    triplets: &[Triplet<usize, usize, f64>],
    shift: f64,
    rhs: &[f64],
) -> Option<Vec<f64>> {
    let mut b = Mat::from_fn(size, 1, |i, _| rhs[i]);
    if size <= DENSE_UP_TO {
        let mut j = Mat::<f64>::zeros(size, size);
        for t in triplets {
            j[(t.row, t.col)] += t.val;
        }
        for i in 0..size {
            j[(i, i)] += shift;
        }
        j.partial_piv_lu().solve_in_place(b.as_mut());
    } else {
        let mut all = triplets.to_vec();
        if shift != 0.0 {
            all.extend((0..size).map(|i| Triplet::new(i, i, shift)));
        }
        let j = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &all).ok()?;
        let lu = j.sp_lu().ok()?;
        lu.solve_in_place(b.as_mut());
    }
    let d: Vec<f64> = (0..size).map(|i| b[(i, 0)]).collect();
    if !d.iter().all(|v| v.is_finite()) {
        return None;
    }
    // A nearly singular J gives a finite but wrong solution: keep only one that solves the
    // system to a relative 1e-8.
    let mut residual = rhs.to_vec();
    for t in triplets {
        residual[t.row] -= t.val * d[t.col];
    }
    residual
        .iter_mut()
        .zip(&d)
        .for_each(|(r, d)| *r -= shift * d);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    (norm(&residual) <= 1e-8 * norm(rhs)).then_some(d)
}
