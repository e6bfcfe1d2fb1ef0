//! Pseudo-transient continuation of a load step at a fold of its branch: Newton's iteration
//! with the mass over a pseudo time step squared on the diagonal,
//! `(K + M / tau_k^2) du = -r(u)` (Kelley & Keyes 1998), the pseudo time step growing as the
//! residual falls, `tau_k = tau_0 |r_0| / |r_k|` (switched evolution relaxation, Mulder &
//! van Leer 1985), from `tau_0` the critical time step of the mesh, where `M / tau_0^2` is of the
//! order of the stiffness' diagonal.
//!
//! The first iterations are an overdamped motion of the mesh at the fixed load factor, away from
//! the state where the branch folded and towards a balanced one; as the residual falls the shift
//! vanishes and the iteration becomes Newton's, which converges there quadratically. A
//! servo-controlled test meets such a fold the same way: at the held opening the specimen moves
//! (dynamically) to a state that balances it. Where `r` is the gradient of an incremental energy
//! the motion descends that energy, and it does not stop at a least value of `|r|` that is not
//! zero, where Newton's iteration with a line search on `|r|` stalls.

/// The shift of a relaxed step's tangent: the lumped mass of each free component and the
/// pseudo time step.
pub(super) struct Relaxation {
    /// Lumped mass of each free component (kg), by equation.
    mass: Vec<f64>,
    /// The first pseudo time step (s).
    tau_0: f64,
    /// The residual norm of the first iteration.
    first: Option<f64>,
}

/// The most iterations of a relaxed step: the gripped one-cell prism of
/// `solver/tests/static_path.rs` crosses its fold in 27.
pub(super) const RELAXATION_ITERATIONS: usize = 200;

/// The largest growth of the pseudo time step over `tau_0`: by then the shift is below the
/// round-off of the stiffness.
const LARGEST_GROWTH: f64 = 1e12;

impl Relaxation {
    /// The relaxation of the free components numbered by `equation` (`usize::MAX` where
    /// prescribed) of nodes with lumped masses `mass`, from the pseudo time step `tau_0`.
    pub(super) fn new(equation: &[[usize; 3]], free: usize, mass: &[f64], tau_0: f64) -> Self {
        let mut by_equation = vec![0.0; free];
        for (eq, &m) in equation.iter().zip(mass) {
            for &k in eq.iter().filter(|&&k| k != usize::MAX) {
                by_equation[k] = m;
            }
        }
        Self {
            mass: by_equation,
            tau_0,
            first: None,
        }
    }

    /// The diagonal `M / tau_k^2` for an iteration whose residual norm is `norm`.
    pub(super) fn shift(&mut self, norm: f64) -> Vec<f64> {
        let first = *self.first.get_or_insert(norm);
        let growth = if norm > 0.0 {
            (first / norm).min(LARGEST_GROWTH)
        } else {
            LARGEST_GROWTH
        };
        let tau = self.tau_0 * growth;
        self.mass.iter().map(|m| m / (tau * tau)).collect()
    }
}
