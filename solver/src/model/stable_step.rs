//! The element eigenvalue bound of the stable time step of a linear tetrahedron with lumped mass.
//!
//! The central-difference scheme is stable for `dt <= 2 / omega_max`, and the highest frequency
//! of the assembled mesh is bounded by the highest element frequency (Irons & Treharne 1971;
//! Belytschko, Liu & Moran 2000, sec. 6.3.4): `omega_max <= max_e omega_e`. For a linear
//! tetrahedron of volume `V`, lumped mass `rho V / 4` per node and isotropic stiffness
//! `K_e = V B^T D B`, the Rayleigh quotient of `M_e^-1 K_e` at nodal displacements `U` (rows
//! `u_a`) is
//!
//! `omega^2 = 4 (lambda (tr eps)^2 + 2 mu eps:eps) / (rho |U|^2)`, `eps = sym(U^T G)`,
//!
//! with `G` the 4 x 3 matrix of the shape gradients `grad N_a`. With the singular values
//! `s_i` of `G` (`s_i^2` the eigenvalues of `S = sum_a grad N_a grad N_a^T`) and the
//! isotropy of the energy, the maximum over `U` splits into the normal strains, the largest
//! eigenvalue of `A = alpha s s^T + beta diag(s_i^2)`, and the shear pairs,
//! `beta (s_i^2 + s_j^2) / 2`, where `alpha = lambda / (lambda + 2 mu)` and
//! `beta = 2 mu / (lambda + 2 mu)`. So `omega_e^2 = 4 c_d^2 Lambda` with `Lambda` the larger
//! of the two, and the element's stable step is `2 / omega_e = L_eig / c_d` with the length
//! `L_eig = 1 / sqrt(Lambda)` ([`eigen_length`]).
//!
//! For the regular tetrahedron of altitude `h`, `L_eig = h sqrt(3 / (4 (3 alpha + beta)))`:
//! `0.71 h` at `nu = 0.2`. On every tetrahedron `L_eig <= h_min`, `h_min` its smallest altitude
//! (the length of FORMULATION 2): `alpha + beta = 1`, so the diagonal entry of
//! `A` at the largest `s_i` is `s_max^2 >= max_a |grad N_a|^2 = 1 / h_min^2`. For `nu >= 0` also
//! `L_eig >= h_min / 2`: `Lambda <= sum_i s_i^2 = sum_a |grad N_a|^2 <= 4 / h_min^2`. So `L_eig / c_d` is a bound where
//! `h_min / c_d` was not: on Kuhn meshes of box cells the assembled limit is 0.87 to 0.95 of
//! `h_min / c_d` and 1.17 to 1.37 of `L_eig / c_d` (docs/stable-time-step.md).

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use crate::kinematics::shape_gradients;
use crate::mesh::element_quality;

/// The length `L` of an element's stable step `L / c_d`: `min(h_min, L_eig)` for an element of
/// smallest altitude `altitude` (`h_min`) and shape gradients `grad_n` ([`eigen_length`];
/// `L_eig <= h_min`, the `min` only guards rounding). An inverted or flat element
/// (`altitude <= 0`) keeps its altitude, so that a caller sees its sign.
pub fn stable_length(altitude: f64, grad_n: &[Vector3<f64>; 4], lambda: f64, mu: f64) -> f64 {
    if altitude > 0.0 {
        altitude.min(eigen_length(grad_n, lambda, mu))
    } else {
        altitude
    }
}

/// [`stable_length`] of the tetrahedron with vertices `x`, and its signed volume.
pub fn stable_length_at(x: &[Vector3<f64>; 4], lambda: f64, mu: f64) -> (f64, f64) {
    let q = element_quality(x);
    let length = match shape_gradients(x) {
        Some((g, _)) => stable_length(q.min_altitude, &g, lambda, mu),
        None => q.min_altitude.min(0.0),
    };
    (length, q.volume)
}

/// The length `L_eig` with `2 / omega_e = L_eig / c_d`: `omega_e` the highest frequency of the
/// linear tetrahedron with shape gradients `grad_n` and lumped mass, `c_d` the dilatational
/// wave speed of its isotropic material of Lamé constants `lambda`, `mu` (module docs).
///
/// Zero where the gradients are not finite (a degenerate element).
pub fn eigen_length(grad_n: &[Vector3<f64>; 4], lambda: f64, mu: f64) -> f64 {
    let modulus = lambda + 2.0 * mu;
    let alpha = lambda / modulus;
    let beta = 2.0 * mu / modulus;
    let s: Matrix3<f64> = grad_n.iter().map(|g| g * g.transpose()).sum();
    if !s.iter().all(|x| x.is_finite()) {
        return 0.0;
    }
    let mut s2 = SymmetricEigen::new(s).eigenvalues.map(|x| x.max(0.0));
    // Ascending order, so that the shear pair of the two largest values is `s2[1], s2[2]` and
    // the result does not hang on the order the eigen solver returns them in.
    s2.as_mut_slice().sort_by(f64::total_cmp);
    let root = s2.map(f64::sqrt);
    let normal = alpha * root * root.transpose() + Matrix3::from_diagonal(&(beta * s2));
    let normal_max = SymmetricEigen::new(normal).eigenvalues.max();
    let shear_max = 0.5 * beta * (s2[1] + s2[2]);
    let largest = normal_max.max(shear_max);
    if largest > 0.0 {
        1.0 / largest.sqrt()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, SymmetricEigen as DenseEigen};

    /// The 12 x 12 `M_e^-1 K_e` of a linear tetrahedron assembled entry by entry from
    /// `K_e = V B^T D B` (Voigt, engineering shear strains), an independent reference.
    fn dense_omega_max_squared(x: &[Vector3<f64>; 4], rho: f64, lambda: f64, mu: f64) -> f64 {
        let (g, v) = shape_gradients(x).expect("positive volume");
        let mut b = DMatrix::<f64>::zeros(6, 12);
        for a in 0..4 {
            let [gx, gy, gz] = [g[a].x, g[a].y, g[a].z];
            let c = 3 * a;
            b[(0, c)] = gx;
            b[(1, c + 1)] = gy;
            b[(2, c + 2)] = gz;
            b[(3, c)] = gy;
            b[(3, c + 1)] = gx;
            b[(4, c + 1)] = gz;
            b[(4, c + 2)] = gy;
            b[(5, c)] = gz;
            b[(5, c + 2)] = gx;
        }
        let mut d = DMatrix::<f64>::zeros(6, 6);
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = lambda;
            }
            d[(i, i)] += 2.0 * mu;
            d[(i + 3, i + 3)] = mu;
        }
        let k = b.transpose() * d * b * v;
        let m = rho * v / 4.0;
        DenseEigen::new(k / m).eigenvalues.max()
    }

    #[test]
    fn matches_the_dense_element_eigenvalue() {
        let (rho, e, nu): (f64, f64, f64) = (2300.0, 30.0e9, 0.2);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let c_d = ((lambda + 2.0 * mu) / rho).sqrt();
        let shapes = [
            // Kuhn tetrahedra of a cube, of a 10:1 long cell and of a 1:10 flat one.
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0, 1.0, 1.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [10.0, 1.0, 0.0],
                [10.0, 1.0, 1.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [0.1, 0.0, 0.0],
                [0.1, 1.0, 0.0],
                [0.1, 1.0, 1.0],
            ],
            // A general one.
            [
                [0.1, -0.2, 0.0],
                [1.3, 0.1, 0.2],
                [0.4, 1.1, -0.3],
                [0.2, 0.3, 0.9],
            ],
        ];
        for shape in shapes {
            let x = shape.map(|p| Vector3::new(p[0], p[1], p[2]) * 0.01);
            let (g, _) = shape_gradients(&x).expect("positive volume");
            let dt_closed = eigen_length(&g, lambda, mu) / c_d;
            let dt_dense = 2.0 / dense_omega_max_squared(&x, rho, lambda, mu).sqrt();
            assert!(
                (dt_closed / dt_dense - 1.0).abs() < 1e-12,
                "{shape:?}: closed form {dt_closed:e}, dense {dt_dense:e}"
            );
        }
    }

    #[test]
    fn regular_tetrahedron_has_the_closed_form_ratio() {
        // Regular tetrahedron of edge sqrt(2) (alternate cube corners), altitude 2 / sqrt(3).
        let x = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::new(0.0, 1.0, 1.0),
            Vector3::new(1.0, 0.0, 1.0),
        ];
        let (g, _) = shape_gradients(&x).expect("positive volume");
        let (lambda, mu) = (1.0, 1.5); // nu = 0.2
        let (alpha, beta): (f64, f64) = (0.25, 0.75);
        let h = 2.0 / 3.0f64.sqrt();
        let expected = h * (3.0 / (4.0 * (3.0 * alpha + beta))).sqrt();
        let length = eigen_length(&g, lambda, mu);
        assert!(
            (length / expected - 1.0).abs() < 1e-12,
            "{length} {expected}"
        );
    }
}
