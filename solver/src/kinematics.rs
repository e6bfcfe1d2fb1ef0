//! Geometry and kinematics of the linear tetrahedron (thesis 3.3, FORMULATION section 1).
//!
//! The element has constant shape-function gradients, so every quantity here is exact: there is
//! no quadrature. Gradients are taken in the reference configuration (total Lagrangian), and the
//! internal force `f_a = V P grad_X N_a` equals the updated-Lagrangian `v sigma grad_x N_a` of
//! (3.102) because `P = J sigma F^-T` and `grad_x N_a = F^-T grad_X N_a`.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// Signed volume of the tetrahedron `x` (3.40): positive when `x1-x0, x2-x0, x3-x0` is a
/// right-handed triple.
#[inline]
pub fn signed_volume(x: &[Vector3<f64>; 4]) -> f64 {
    (x[1] - x[0]).cross(&(x[2] - x[0])).dot(&(x[3] - x[0])) / 6.0
}

/// Gradients `grad N_a` of the four barycentric shape functions (3.44), with the volume.
///
/// With `J = [x1-x0 | x2-x0 | x3-x0]`, `N_i = (J^-1 (x - x0))_i` for `i = 1..3`, so `grad N_i`
/// is row `i` of `J^-1`, and `grad N_0 = -(grad N_1 + grad N_2 + grad N_3)` because the
/// functions sum to one. Returns `None` for a volume that is not positive.
pub fn shape_gradients(x: &[Vector3<f64>; 4]) -> Option<([Vector3<f64>; 4], f64)> {
    let e1 = x[1] - x[0];
    let e2 = x[2] - x[0];
    let e3 = x[3] - x[0];
    let det = e1.cross(&e2).dot(&e3);
    if !(det > 0.0) {
        return None;
    }
    // Rows of J^-1 are the scaled cross products of the columns of J.
    let g1 = e2.cross(&e3) / det;
    let g2 = e3.cross(&e1) / det;
    let g3 = e1.cross(&e2) / det;
    Some(([-(g1 + g2 + g3), g1, g2, g3], det / 6.0))
}

/// Displacement gradient `H = grad_X u = sum_a u_a (x) grad_X N_a`.
#[inline]
pub fn displacement_gradient(u: &[Vector3<f64>; 4], grad_n: &[Vector3<f64>; 4]) -> Matrix3<f64> {
    u[0] * grad_n[0].transpose()
        + u[1] * grad_n[1].transpose()
        + u[2] * grad_n[2].transpose()
        + u[3] * grad_n[3].transpose()
}

/// The gradient `sum_a w_a (x) grad_X N_a` of a nodal field `w` over one element: the
/// displacement gradient `H` for the displacements, `Fdot` for the velocities. This is the form
/// of the element loops, the innermost loop of every explicit step.
///
/// The four gradients sum to zero (`grad N_0 = -(grad N_1 + grad N_2 + grad N_3)`, see
/// [`shape_gradients`]), so the sum is computed as `sum_{a=1..3} (w_a - w_0) grad N_a^T`: the same
/// tensor with a quarter fewer products, exactly zero for a rigid translation, and, in the
/// assembly loop of the benchmark (480 000 elements, one thread), 20.5 instead of 27 ns per
/// linear-elastic element (the four-term sum, also written out by rows or by columns, compiled
/// to slower code). [`displacement_gradient`] keeps the four-term definition for the output and
/// the static tangents; the two agree to round-off.
#[inline(always)]
pub fn element_gradient(w: &[Vector3<f64>; 4], grad_n: &[Vector3<f64>; 4]) -> Matrix3<f64> {
    let [_, g1, g2, g3] = grad_n;
    (w[1] - w[0]) * g1.transpose() + (w[2] - w[0]) * g2.transpose() + (w[3] - w[0]) * g3.transpose()
}

/// `det F` as the triple product `F_0 . (F_1 x F_2)` of the columns of `F`, whose cross product is
/// also the first column of `cof F` in the linear-elastic stress (1.5 ns per element faster than
/// `determinant()` in the element loop).
#[inline(always)]
pub fn triple_product_determinant(f: &Matrix3<f64>) -> f64 {
    f.column(0).dot(&f.column(1).cross(&f.column(2)))
}

/// Deformation gradient `F = I + H` (2.47), from the displacements so that small strains keep
/// their significant digits.
#[inline]
pub fn deformation_gradient(u: &[Vector3<f64>; 4], grad_n: &[Vector3<f64>; 4]) -> Matrix3<f64> {
    Matrix3::identity() + displacement_gradient(u, grad_n)
}

/// Green-Lagrange strain `E = (F^T F - I)/2 = (H + H^T + H^T H)/2` (2.73), from `H` to keep
/// precision at small strain.
#[inline]
pub fn green_lagrange_from_h(h: &Matrix3<f64>) -> Matrix3<f64> {
    0.5 * (h + h.transpose() + h.transpose() * h)
}

/// Green-Lagrange strain `E = (F^T F - I)/2` (2.73).
#[inline]
pub fn green_lagrange(f: &Matrix3<f64>) -> Matrix3<f64> {
    0.5 * (f.transpose() * f - Matrix3::identity())
}

/// Cofactor `cof F = det(F) F^-T`, written out so that it exists for every `F` and needs no
/// division. It maps reference area to current area (Nanson) and is the bridge `P = sigma cof F`.
#[inline]
pub fn cofactor(f: &Matrix3<f64>) -> Matrix3<f64> {
    let c0 = f.column(0);
    let c1 = f.column(1);
    let c2 = f.column(2);
    // Columns of cof F are the cross products of the other two columns of F.
    Matrix3::from_columns(&[c1.cross(&c2), c2.cross(&c0), c0.cross(&c1)])
}

/// Polar decomposition `F = R U` (2.2.3), with `U` from the eigen-decomposition of `C = F^T F`.
///
/// Exact to round-off for any `F` with `det F > 0`; returns `None` when `det F <= 0` (an
/// inverted element) instead of producing NaN.
pub fn polar_decomposition(f: &Matrix3<f64>) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
    if !(f.determinant() > 0.0) {
        return None;
    }
    let eig = SymmetricEigen::new(f.transpose() * f);
    let q = eig.eigenvectors;
    let stretches = eig.eigenvalues.map(f64::sqrt);
    let u = q * Matrix3::from_diagonal(&stretches) * q.transpose();
    let u_inv = q * Matrix3::from_diagonal(&stretches.map(|s| 1.0 / s)) * q.transpose();
    Some((f * u_inv, u))
}

/// The rotation `R` of the polar decomposition `F = R U`, by Newton's iteration
/// `X <- (g X + X^-T / g) / 2` from `X = F` (Higham 1986), with the scaling
/// `g = (|X^-1| / |X|)^(1/2)` (Frobenius norms) while far from convergence.
///
/// The iteration converges quadratically to the orthogonal polar factor for every `F` with
/// `det F > 0`: every iterate is `R U_k` with `U_{k+1} = (U_k + U_k^-1) / 2`, so an iterate
/// `R (I + e)` moves by `|e|` and lands at an error of `|e|^2 / 2`. It stops after a move below
/// 1e-8, whose iterate is then within 5e-17 of `R`, below the rounding of its entries: two
/// iterations at the strains of a vibrating concrete beam (1e-4), three at 1e-3, a handful at
/// large stretches; about a tenth of the cost of [`polar_decomposition`]'s eigen-decomposition.
/// `X^-T = cof X / det X`, with the determinant from the cofactor's first column
/// (`det X = x_0 . (x_1 x x_2)`) and one division. Returns `None` for `det F <= 0`, and falls
/// back to [`polar_decomposition`] if the iteration has not converged after 30 steps.
pub fn polar_rotation(f: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let mut x = *f;
    let mut cof = cofactor(&x);
    let mut det = x.column(0).dot(&cof.column(0));
    if !(det > 0.0 && det.is_finite()) {
        return None;
    }
    for _ in 0..30 {
        let inverse_transpose = cof * (1.0 / det);
        let change = inverse_transpose - x;
        // Scaling speeds up the first steps at large stretch; near convergence it is 1 to
        // round-off and is left out, so that the last steps are the plain quadratic ones.
        let next = if change.norm_squared() > 1e-4 {
            let g = (inverse_transpose.norm() / x.norm()).sqrt();
            0.5 * (g * x + inverse_transpose / g)
        } else {
            0.5 * (x + inverse_transpose)
        };
        let moved = (next - x).norm_squared();
        x = next;
        if moved < 1e-16 {
            return Some(x);
        }
        cof = cofactor(&x);
        det = x.column(0).dot(&cof.column(0));
    }
    polar_decomposition(f).map(|(r, _)| r)
}

/// Principal values of a symmetric tensor, in ascending order.
pub fn principal_values(a: &Matrix3<f64>) -> Vector3<f64> {
    let mut v = SymmetricEigen::new(*a).eigenvalues;
    v.as_mut_slice().sort_by(|x, y| x.total_cmp(y));
    v
}

/// The symmetric matrix of Voigt order `[xx, yy, zz, xy, yz, xz]`, the inverse of [`voigt`] (the
/// order of the stress and strain fields of a frame).
#[inline]
pub fn matrix_from_voigt(v: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2])
}

/// Symmetric tensor in Voigt order `[xx, yy, zz, xy, yz, xz]`.
#[inline]
pub fn voigt(a: &Matrix3<f64>) -> [f64; 6] {
    [
        a[(0, 0)],
        a[(1, 1)],
        a[(2, 2)],
        a[(0, 1)],
        a[(1, 2)],
        a[(0, 2)],
    ]
}

#[cfg(test)]
mod voigt_tests {
    use super::{matrix_from_voigt, voigt};

    /// `[xx, yy, zz, xy, yz, xz]` lands where its names say, and `voigt` reads it back.
    #[test]
    fn matrix_from_voigt_places_each_component_and_inverts_voigt() {
        let v = [1.0, 2.0, 3.0, 12.0, 23.0, 13.0];
        let m = matrix_from_voigt(&v);
        for (i, j, value) in [
            (0, 0, 1.0),
            (1, 1, 2.0),
            (2, 2, 3.0),
            (0, 1, 12.0),
            (1, 2, 23.0),
            (0, 2, 13.0),
        ] {
            assert_eq!(m[(i, j)], value);
            assert_eq!(m[(j, i)], value);
        }
        assert_eq!(voigt(&m), v);
    }
}
