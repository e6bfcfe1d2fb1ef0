//! One-contact solvers: the local step of nonlinear Gauss-Seidel on FC(W, q, mu).
//!
//! Contact `a` sees the velocity `u = A r + b` of its own multiplier `r`, with `A = W_aa` its
//! diagonal block and `b = q_a + sum_{c != a} W_ac r_c` everything the other contacts do.
//! Components are local: `[normal, tangent1, tangent2]`.

use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

/// The thesis step (6.71)-(6.77) in local components: each component closes its own velocity
/// with the block's diagonal, `r - D^-1 u` (frictionless: the normal component alone), then the
/// result is released when tensile (6.74) or returned radially onto `|r_T| <= mu r_N` (6.77).
/// Exact when `A` is a multiple of the identity, as for our lumped masses; for a general block
/// it is one Jacobi step inside the block.
pub fn thesis_step(a: &Matrix3<f64>, r: &Vector3<f64>, u: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    let close = |k: usize| {
        if a[(k, k)] > 0.0 {
            r[k] - u[k] / a[(k, k)]
        } else {
            r[k]
        }
    };
    if mu == 0.0 {
        return Vector3::new(close(0).max(0.0), 0.0, 0.0);
    }
    cylinder_return(Vector3::new(close(0), close(1), close(2)), mu)
}

/// Release a tensile multiplier; return the tangential part radially onto `mu r_N`.
fn cylinder_return(r: Vector3<f64>, mu: f64) -> Vector3<f64> {
    if r.x <= 0.0 {
        return Vector3::zeros();
    }
    if mu.is_infinite() {
        return r;
    }
    let t = r.y.hypot(r.z);
    let limit = mu * r.x;
    if t <= limit {
        r
    } else {
        Vector3::new(r.x, r.y * limit / t, r.z * limit / t)
    }
}

/// How the exact local solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LocalCase {
    /// The free normal velocity opens the contact (`b_N >= 0`): no force.
    Separated,
    /// Closed contact without friction (`mu = 0`): a normal force only.
    Frictionless,
    /// Closed and sticking: no slip, the force inside the Coulomb cone (any force for
    /// `mu = inf`).
    Stick,
    /// Closed and sliding: the force lies on the Coulomb cone, opposing the slip.
    Slide,
    /// No slip direction satisfies the law (a singular or strongly non-symmetric block): the
    /// thesis step was taken instead.
    Fallback,
}

/// Slip directions sampled before bisection; roots closer than `2 pi / SAMPLES` may be missed,
/// which only matters for strongly non-symmetric blocks with several solutions.
const SAMPLES: usize = 360;

/// The exact solution of the one-contact Coulomb problem `u = A r + b` for a general 3x3 block,
/// by its three cases (Alart & Curnier 1991; the enumeration of Acary, Bremond & Huber 2018,
/// "EXACT" local solver):
/// 1. separation, `r = 0`, when `b_N >= 0`;
/// 2. stick, `u = 0`, `r = -A^-1 b`, when it lies in the cone;
/// 3. slip, `r = rho [1, mu c]`, `u_N = 0`, `u_T = -lambda c` (`lambda >= 0`, `|c| = 1`): with
///    `rho(c) = -b_N / (A_N . [1, mu c])` the law leaves one equation in the slip angle,
///    `u_T(c) x c = 0` with `u_T . c < 0`, whose roots are bracketed on a scan of the angle and
///    bisected to machine precision. Of several roots the one nearest `hint`'s direction wins
///    (continuity between sweeps).
///
/// Frictionless (`mu = 0`): `r_N = -b_N / A_NN`. Stick (`mu = inf`): `u = 0` with `r_N > 0`
/// (Schur complement on the normal component); in the rare block where that needs `r_N <= 0`
/// while the contact penetrates, the no-adhesion law has no solution and the closure of the
/// cone (the half-space, `r_N = 0`, `u_T = 0`) is returned.
pub fn exact_step(
    a: &Matrix3<f64>,
    b: &Vector3<f64>,
    mu: f64,
    hint: &Vector3<f64>,
) -> (Vector3<f64>, LocalCase) {
    if b.x >= 0.0 {
        return (Vector3::zeros(), LocalCase::Separated);
    }
    if is_isotropic(a) {
        // A multiple of the identity: the thesis step from zero is the exact solution, in
        // closed form (the scan below would find the same slip direction, 300 times slower).
        let r = thesis_step(a, &Vector3::zeros(), b, mu);
        let case = match (mu, r) {
            (0.0, _) => LocalCase::Frictionless,
            (m, r) if m.is_finite() && r.y.hypot(r.z) >= m * r.x * (1.0 - 1e-12) => {
                LocalCase::Slide
            }
            _ => LocalCase::Stick,
        };
        return (r, case);
    }
    if mu == 0.0 {
        return if a[(0, 0)] > 0.0 {
            (
                Vector3::new(-b.x / a[(0, 0)], 0.0, 0.0),
                LocalCase::Frictionless,
            )
        } else {
            fallback(a, b, mu, hint)
        };
    }
    if mu.is_infinite() {
        return stick_half_space(a, b).unwrap_or_else(|| fallback(a, b, mu, hint));
    }
    if let Some(r) = a.lu().solve(&(-b)) {
        if r.x > 0.0 && r.y.hypot(r.z) <= mu * r.x {
            return (r, LocalCase::Stick);
        }
    }
    match slide(a, b, mu, hint) {
        Some(r) => (r, LocalCase::Slide),
        None => fallback(a, b, mu, hint),
    }
}

/// Whether the block is a positive multiple of the identity (our lumped-mass blocks, rotated
/// into the local frame: equal to round-off, 1e-13 of the diagonal).
fn is_isotropic(a: &Matrix3<f64>) -> bool {
    let d = a[(0, 0)];
    let close = |v: f64, w: f64| (v - w).abs() <= 1e-13 * d;
    d > 0.0
        && close(a[(1, 1)], d)
        && close(a[(2, 2)], d)
        && (0..3).all(|i| (0..3).all(|j| i == j || close(a[(i, j)], 0.0)))
}

fn fallback(
    a: &Matrix3<f64>,
    b: &Vector3<f64>,
    mu: f64,
    hint: &Vector3<f64>,
) -> (Vector3<f64>, LocalCase) {
    let u = a * hint + b;
    (thesis_step(a, hint, &u, mu), LocalCase::Fallback)
}

/// `u_T = 0`, `0 <= r_N _|_ u_N >= 0`: eliminating `r_T = -A_TT^-1 (b_T + A_TN r_N)` leaves
/// `u_N = s r_N + e` with the Schur complement `s = A_NN - A_NT A_TT^-1 A_TN`.
fn stick_half_space(a: &Matrix3<f64>, b: &Vector3<f64>) -> Option<(Vector3<f64>, LocalCase)> {
    let att = Matrix2::new(a[(1, 1)], a[(1, 2)], a[(2, 1)], a[(2, 2)]);
    let inv = att.try_inverse()?;
    let atn = Vector2::new(a[(1, 0)], a[(2, 0)]);
    let ant = Vector2::new(a[(0, 1)], a[(0, 2)]);
    let bt = Vector2::new(b.y, b.z);
    let s = a[(0, 0)] - ant.dot(&(inv * atn));
    let e = b.x - ant.dot(&(inv * bt));
    let rn = if s > 0.0 {
        (-e / s).max(0.0)
    } else {
        return None;
    };
    let rt = -(inv * (bt + atn * rn));
    Some((Vector3::new(rn, rt.x, rt.y), LocalCase::Stick))
}

/// The slip case of `exact_step`.
fn slide(a: &Matrix3<f64>, b: &Vector3<f64>, mu: f64, hint: &Vector3<f64>) -> Option<Vector3<f64>> {
    // For angle theta: the multiplier, and the law's residual `u_T x c` with `u_T . c`.
    let eval = |theta: f64| -> Option<(Vector3<f64>, f64, f64)> {
        let (s, c) = theta.sin_cos();
        let d = Vector3::new(1.0, mu * c, mu * s);
        let denominator = a.row(0).transpose().dot(&d);
        if denominator <= 0.0 {
            return None;
        }
        let r = d * (-b.x / denominator);
        let u = a * r + b;
        Some((r, u.y * s - u.z * c, u.y * c + u.z * s))
    };
    let step = std::f64::consts::TAU / SAMPLES as f64;
    let mut roots: Vec<Vector3<f64>> = Vec::new();
    let mut previous = eval(0.0).map(|v| (0.0, v));
    for k in 1..=SAMPLES {
        let theta = k as f64 * step;
        let current = eval(theta).map(|v| (theta, v));
        if let (Some((t0, (_, f0, s0))), Some((t1, (_, f1, s1)))) = (previous, current) {
            if (s0 < 0.0 || s1 < 0.0) && (f0 == 0.0 || f0.signum() != f1.signum()) {
                let (mut lo, mut hi, mut flo) = (t0, t1, f0);
                for _ in 0..64 {
                    let mid = 0.5 * (lo + hi);
                    let Some((_, fm, _)) = eval(mid) else { break };
                    if fm == 0.0 {
                        (lo, hi) = (mid, mid);
                        break;
                    }
                    if fm.signum() == flo.signum() {
                        (lo, flo) = (mid, fm);
                    } else {
                        hi = mid;
                    }
                }
                if let Some((r, _, s)) = eval(0.5 * (lo + hi)) {
                    if s < 0.0 {
                        roots.push(r);
                    }
                }
            }
        }
        previous = current;
    }
    let direction = |r: &Vector3<f64>| Vector2::new(r.y, r.z);
    let h = direction(hint);
    roots.into_iter().min_by(|x, y| {
        let dx = (direction(x).normalize() - h.try_normalize(0.0).unwrap_or_default()).norm();
        let dy = (direction(y).normalize() - h.try_normalize(0.0).unwrap_or_default()).norm();
        dx.total_cmp(&dy)
    })
}

/// Rows `n, t1, t2` of a right-handed frame; `t1` is `n` crossed with the global axis least
/// aligned with it, so the frame is a deterministic function of `n`.
pub fn local_frame(n: &Vector3<f64>) -> Matrix3<f64> {
    let axis = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
        Vector3::x()
    } else if n.y.abs() <= n.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let t1 = n.cross(&axis).normalize();
    let t2 = n.cross(&t1);
    Matrix3::from_rows(&[n.transpose(), t1.transpose(), t2.transpose()])
}

/// One contact's natural map `r - P_K(r - u_hat)` (local components).
pub fn contact_natural_map(r: &Vector3<f64>, u: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    if mu.is_infinite() {
        let normal = r.x - (r.x - u.x).max(0.0);
        return if r.x - u.x > 0.0 {
            Vector3::new(normal, u.y, u.z)
        } else {
            Vector3::new(normal, r.y, r.z)
        };
    }
    let ut = (u.y * u.y + u.z * u.z).sqrt();
    let z = r - Vector3::new(u.x + mu * ut, u.y, u.z);
    r - project_on_coulomb_cone(&z, mu)
}

/// Euclidean projection onto `{|z_T| <= mu z_N}` (Siconos `projectionOnCone`).
pub fn project_on_coulomb_cone(z: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    let t = (z.y * z.y + z.z * z.z).sqrt();
    if mu * t <= -z.x {
        Vector3::zeros()
    } else if t <= mu * z.x {
        *z
    } else {
        let n = (mu * t + z.x) / (mu * mu + 1.0);
        Vector3::new(n, mu * n * z.y / t, mu * n * z.z / t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::problem::contact_natural_map;

    fn residual(a: &Matrix3<f64>, b: &Vector3<f64>, mu: f64, r: &Vector3<f64>) -> f64 {
        contact_natural_map(r, &(a * r + b), mu).norm()
    }

    #[test]
    fn on_a_multiple_of_the_identity_both_steps_agree() {
        let a = Matrix3::identity() * 2.0;
        for (b, mu) in [
            (Vector3::new(-1.0, 0.1, 0.0), 0.3),  // stick
            (Vector3::new(-1.0, 2.0, -1.0), 0.3), // slide
            (Vector3::new(0.5, 2.0, -1.0), 0.3),  // separate
            (Vector3::new(-1.0, 2.0, -1.0), 0.0), // frictionless
            (Vector3::new(-1.0, 2.0, -1.0), f64::INFINITY),
        ] {
            let zero = Vector3::zeros();
            let thesis = thesis_step(&a, &zero, &b, mu);
            let (exact, _) = exact_step(&a, &b, mu, &zero);
            assert!(
                (thesis - exact).norm() < 1e-12 * (1.0 + thesis.norm()),
                "{b} {mu}"
            );
            assert!(residual(&a, &b, mu, &exact) < 1e-12, "{b} {mu}");
        }
    }

    #[test]
    fn the_exact_step_solves_general_blocks_where_the_thesis_step_does_not() {
        // Symmetric positive definite with strong normal-tangential coupling.
        let a = Matrix3::new(2.0, 0.6, -0.3, 0.6, 1.0, 0.2, -0.3, 0.2, 0.5);
        let b = Vector3::new(-1.0, 0.8, 0.3);
        let zero = Vector3::zeros();
        for mu in [0.1, 0.5, 2.0] {
            let (r, case) = exact_step(&a, &b, mu, &zero);
            assert!(residual(&a, &b, mu, &r) < 1e-12, "mu {mu}: {case:?} {r}");
            // One thesis step from zero is not a solution here.
            let t = thesis_step(&a, &zero, &b, mu);
            assert!(residual(&a, &b, mu, &t) > 1e-3, "mu {mu}");
        }
        let (r, case) = exact_step(&a, &b, 0.1, &zero);
        assert_eq!(case, LocalCase::Slide, "{r}");
        let (_, case) = exact_step(&a, &b, 2.0, &zero);
        assert_eq!(case, LocalCase::Stick);
    }

    #[test]
    fn random_blocks_are_solved_to_machine_precision() {
        let mut rng = crate::rng::SplitMix64::new(7);
        let mut fallbacks = 0;
        for _ in 0..2000 {
            let m = Matrix3::from_fn(|_, _| rng.uniform(-1.0, 1.0));
            let a = m * m.transpose() + Matrix3::identity() * 0.05;
            let b = Vector3::from_fn(|_, _| rng.uniform(-1.0, 1.0));
            let mu = rng.uniform(0.0, 1.5);
            let (r, case) = exact_step(&a, &b, mu, &Vector3::zeros());
            if case == LocalCase::Fallback {
                fallbacks += 1;
                continue;
            }
            let scale = 1.0 + b.norm() + r.norm();
            assert!(
                residual(&a, &b, mu, &r) < 1e-10 * scale,
                "{case:?} {a} {b} {mu} {r}"
            );
        }
        println!("fallbacks {fallbacks} of 2000");
        assert_eq!(fallbacks, 0);
    }

    #[test]
    fn stick_leaves_the_tangential_force_free() {
        let a = Matrix3::new(2.0, 0.6, -0.3, 0.6, 1.0, 0.2, -0.3, 0.2, 0.5);
        let b = Vector3::new(-1.0, 5.0, 3.0);
        let (r, case) = exact_step(&a, &b, f64::INFINITY, &Vector3::zeros());
        assert_eq!(case, LocalCase::Stick);
        assert!((a * r + b).norm() < 1e-12);
    }
}
