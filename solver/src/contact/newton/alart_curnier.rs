//! The Alart-Curnier function of one contact and its generalized Jacobian (Alart & Curnier 1991;
//! the "standard" form of Siconos `fc3d_AlartCurnierFunction`, Acary, Bremond & Huber 2018,
//! section 3.3).
//!
//! With `u = W r + q` and positive weights `rho_N`, `rho_T`, contact `a` contributes
//!
//! ```text
//! Phi_N = r_N - max(0, r_N - rho_N u_N)                     (projection on R+)
//! Phi_T = r_T - P_D(r_T - rho_T u_T),  D = disk of radius mu max(0, r_N - rho_N u_N)
//! ```
//!
//! and `Phi(r) = 0` exactly at the solutions of Signorini's condition with Coulomb's law: the
//! normal line is the projected form of `0 <= u_N _|_ r_N >= 0`, and the tangential one says
//! that `r_T` is the projection on its disk of `r_T - rho_T u_T` (stick when inside, slip
//! opposite `u_T` on the rim). `Phi` is piecewise smooth; on each piece, the derivatives are
//! those of the piece's formula, which is an element of Clarke's generalized Jacobian (the
//! B-subdifferential), what a semismooth Newton method needs.
//!
//! `mu = inf` (stick) uses the infinite disk where the contact is active (`Phi_T = rho_T u_T`)
//! and the zero disk where it is not (`Phi_T = r_T`), as the natural map of `problem.rs` does.

use nalgebra::{Matrix3, Vector2, Vector3};

/// Which piece of the Alart-Curnier function a contact sits on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AlartCurnierBranch {
    /// `r_N - rho_N u_N <= 0`: no force, `Phi = r`.
    Separated,
    /// Active, `|r_T - rho_T u_T| <= mu (r_N - rho_N u_N)`: `Phi = rho u`.
    Stick,
    /// Active, outside the disk: the tangential force on its rim, opposing slip.
    Slip,
}

/// One contact's value of the function and its two partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlartCurnierPiece {
    /// `Phi_a(r_a, u_a)`.
    pub value: Vector3<f64>,
    /// `d Phi_a / d r_a` (the contact's own multipliers).
    pub d_r: Matrix3<f64>,
    /// `d Phi_a / d u_a`; the chain rule through `u = W r + q` gives `d_r + d_u W_a.` per row.
    pub d_u: Matrix3<f64>,
    /// The piece it was evaluated on.
    pub branch: AlartCurnierBranch,
}

/// `Phi_a` and an element of its generalized Jacobian at `(r, u)`, with weights
/// `rho = [rho_N, rho_T]` and Coulomb coefficient `mu` (`0`: frictionless, `inf`: stick).
pub fn alart_curnier(
    r: &Vector3<f64>,
    u: &Vector3<f64>,
    mu: f64,
    rho: [f64; 2],
) -> AlartCurnierPiece {
    let [rho_n, rho_t] = rho;
    let s = r.x - rho_n * u.x;
    if s <= 0.0 {
        return AlartCurnierPiece {
            value: *r,
            d_r: Matrix3::identity(),
            d_u: Matrix3::zeros(),
            branch: AlartCurnierBranch::Separated,
        };
    }
    // Active: Phi_N = rho_N u_N.
    let mut d_r = Matrix3::zeros();
    let mut d_u = Matrix3::zeros();
    d_u[(0, 0)] = rho_n;
    let mut value = Vector3::new(rho_n * u.x, 0.0, 0.0);
    if mu == 0.0 {
        // The disk is a point: Phi_T = r_T.
        value.y = r.y;
        value.z = r.z;
        d_r[(1, 1)] = 1.0;
        d_r[(2, 2)] = 1.0;
        return AlartCurnierPiece {
            value,
            d_r,
            d_u,
            branch: AlartCurnierBranch::Slip,
        };
    }
    let z = Vector2::new(r.y - rho_t * u.y, r.z - rho_t * u.z);
    let radius = mu * s;
    let norm = z.norm();
    if mu.is_infinite() || norm <= radius {
        value.y = rho_t * u.y;
        value.z = rho_t * u.z;
        d_u[(1, 1)] = rho_t;
        d_u[(2, 2)] = rho_t;
        return AlartCurnierPiece {
            value,
            d_r,
            d_u,
            branch: AlartCurnierBranch::Stick,
        };
    }
    // Slip: Phi_T = r_T - radius z / |z|. With P = (I - z z^T / |z|^2) radius / |z|:
    // d/dr_T = I - P, d/du_T = rho_T P, d/dr_N = -mu z/|z|, d/du_N = mu rho_N z/|z|.
    let unit = z / norm;
    let p = (nalgebra::Matrix2::identity() - unit * unit.transpose()) * (radius / norm);
    value.y = r.y - radius * unit.x;
    value.z = r.z - radius * unit.y;
    for i in 0..2 {
        for j in 0..2 {
            d_r[(1 + i, 1 + j)] = f64::from(u8::from(i == j)) - p[(i, j)];
            d_u[(1 + i, 1 + j)] = rho_t * p[(i, j)];
        }
        d_r[(1 + i, 0)] = -mu * unit[i];
        d_u[(1 + i, 0)] = mu * rho_n * unit[i];
    }
    AlartCurnierPiece {
        value,
        d_r,
        d_u,
        branch: AlartCurnierBranch::Slip,
    }
}

/// The weights of contact `a` from its diagonal block of `W`: `rho_N = 1 / W_NN`,
/// `rho_T = 2 / (W_T1T1 + W_T2T2)`, so that `r - rho u` compares quantities of one unit and a
/// block that is a multiple of the identity makes the iteration a projected Jacobi step (the
/// "split spectral" choice of Siconos's rho strategies, taken on the diagonal). A non-positive
/// diagonal takes `fallback` (one over the mean diagonal of `W`).
pub fn weights(block: &Matrix3<f64>, fallback: f64) -> [f64; 2] {
    let n = if block[(0, 0)] > 0.0 {
        1.0 / block[(0, 0)]
    } else {
        fallback
    };
    let t = block[(1, 1)] + block[(2, 2)];
    let t = if t > 0.0 { 2.0 / t } else { n };
    [n, t]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `Phi` in `r` and in `u`, column by column.
    fn finite_differences(
        r: &Vector3<f64>,
        u: &Vector3<f64>,
        mu: f64,
        rho: [f64; 2],
    ) -> (Matrix3<f64>, Matrix3<f64>) {
        let h = 1e-6;
        let mut d_r = Matrix3::zeros();
        let mut d_u = Matrix3::zeros();
        for j in 0..3 {
            let mut e = Vector3::zeros();
            e[j] = h;
            let col_r = (alart_curnier(&(r + e), u, mu, rho).value
                - alart_curnier(&(r - e), u, mu, rho).value)
                / (2.0 * h);
            let col_u = (alart_curnier(r, &(u + e), mu, rho).value
                - alart_curnier(r, &(u - e), mu, rho).value)
                / (2.0 * h);
            d_r.set_column(j, &col_r);
            d_u.set_column(j, &col_u);
        }
        (d_r, d_u)
    }

    fn check(r: Vector3<f64>, u: Vector3<f64>, mu: f64, branch: AlartCurnierBranch) {
        let rho = [0.7, 1.3];
        let piece = alart_curnier(&r, &u, mu, rho);
        assert_eq!(piece.branch, branch, "{r} {u} {mu}");
        let (d_r, d_u) = finite_differences(&r, &u, mu, rho);
        assert!(
            (piece.d_r - d_r).norm() < 1e-8,
            "{mu} {branch:?}: {} vs {d_r}",
            piece.d_r
        );
        assert!(
            (piece.d_u - d_u).norm() < 1e-8,
            "{mu} {branch:?}: {} vs {d_u}",
            piece.d_u
        );
    }

    #[test]
    fn the_jacobian_is_the_finite_difference_one_away_from_the_kinks() {
        use AlartCurnierBranch::*;
        let mut rng = crate::rng::SplitMix64::new(11);
        let (mut seen_stick, mut seen_slip, mut seen_separated) = (0, 0, 0);
        for _ in 0..3000 {
            let r = Vector3::from_fn(|_, _| rng.uniform(-1.0, 2.0));
            let u = Vector3::from_fn(|_, _| rng.uniform(-2.0, 2.0));
            let mu = rng.uniform(0.05, 1.5);
            let rho = [0.7, 1.3];
            // Away from the kinks: the switching quantities at least 1e-3 from zero, far
            // beyond the difference step.
            let s = r.x - rho[0] * u.x;
            let z = Vector2::new(r.y - rho[1] * u.y, r.z - rho[1] * u.z);
            if s.abs() < 1e-3 || (z.norm() - mu * s).abs() < 1e-3 || z.norm() < 1e-3 {
                continue;
            }
            let branch = alart_curnier(&r, &u, mu, rho).branch;
            match branch {
                Stick => seen_stick += 1,
                Slip => seen_slip += 1,
                Separated => seen_separated += 1,
            }
            check(r, u, mu, branch);
        }
        assert!(seen_stick > 100 && seen_slip > 100 && seen_separated > 100);
        // Frictionless and sticking contacts.
        check(
            Vector3::new(1.0, 0.3, -0.2),
            Vector3::new(-0.5, 1.0, 2.0),
            0.0,
            Slip,
        );
        let inf = f64::INFINITY;
        check(
            Vector3::new(1.0, 0.3, -0.2),
            Vector3::new(-0.5, 1.0, 2.0),
            inf,
            Stick,
        );
        check(
            Vector3::new(-1.0, 0.3, -0.2),
            Vector3::new(0.5, 1.0, 2.0),
            inf,
            Separated,
        );
    }

    #[test]
    fn the_function_vanishes_exactly_at_the_three_kinds_of_solution() {
        let rho = [0.7, 1.3];
        let mu = 0.3;
        // Separation, stick inside the cone, slip on the cone opposite the slip velocity.
        let cases = [
            (Vector3::zeros(), Vector3::new(1.0, 5.0, -2.0)),
            (Vector3::new(1.0, 0.1, -0.1), Vector3::zeros()),
            (
                Vector3::new(1.0, 0.3 * 0.6, 0.3 * 0.8),
                Vector3::new(0.0, -1.2, -1.6),
            ),
        ];
        for (r, u) in cases {
            let phi = alart_curnier(&r, &u, mu, rho).value;
            assert!(phi.norm() < 1e-15, "{r} {u}: {phi}");
        }
        // Slip in the direction of the force, and a tensile force, are not solutions.
        let wrong = alart_curnier(
            &Vector3::new(1.0, 0.18, 0.24),
            &Vector3::new(0.0, 1.2, 1.6),
            mu,
            rho,
        );
        assert!(wrong.value.norm() > 0.1);
        let tensile = alart_curnier(&Vector3::new(-1.0, 0.0, 0.0), &Vector3::zeros(), mu, rho);
        assert!(tensile.value.norm() > 0.5);
    }
}
