//! Problem descriptors: the facts about FC(W, q, mu) that explain which solver family wins
//! (Acary, Bremond & Huber 2018, table "fclib": contacts, mu, rank ratio and condition number of
//! W, asymmetry `||W - W^T||`).

use impact_solver::contact::problem::ContactProblem;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::results::lenient;

/// Eigenvalues at or below this fraction of the largest count as zero for the rank.
pub const RANK_THRESHOLD: f64 = 1e-12;

/// What a contact problem looks like, independently of any solver.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProblemDescriptors {
    /// The file stem: the problem's name in tables and metrics.
    pub name: String,
    /// The file it was read from.
    pub file: String,
    /// Contacts `nc`.
    pub contacts: usize,
    /// Unknowns `3 nc`.
    pub unknowns: usize,
    /// Stored entries of `W`.
    pub nonzeros: usize,
    /// Smallest and largest finite Coulomb coefficient (NaN when every contact sticks).
    #[serde(deserialize_with = "lenient::f64")]
    pub mu_min: f64,
    /// Largest finite Coulomb coefficient (NaN when every contact sticks).
    #[serde(deserialize_with = "lenient::f64")]
    pub mu_max: f64,
    /// Contacts with `mu = inf` (stick) and with `mu = 0` (frictionless).
    pub stick_contacts: usize,
    /// Contacts with `mu = 0`.
    pub frictionless_contacts: usize,
    /// `||W - W^T||_F / ||W||_F`.
    #[serde(deserialize_with = "lenient::f64")]
    pub asymmetry: f64,
    /// Rank of the symmetric part `S = (W + W^T)/2`: eigenvalues above
    /// [`RANK_THRESHOLD`] times the largest.
    pub rank: usize,
    /// `lambda_max / lambda_min` over the eigenvalues of `S` counted in the rank.
    #[serde(deserialize_with = "lenient::f64")]
    pub condition: f64,
    /// Smallest and largest eigenvalue of `S` (a negative smallest one: `S` is indefinite).
    #[serde(deserialize_with = "lenient::f64")]
    pub eigenvalue_min: f64,
    /// Largest eigenvalue of `S`.
    #[serde(deserialize_with = "lenient::f64")]
    pub eigenvalue_max: f64,
    /// `||q||_2`, the normalisation of the error.
    #[serde(deserialize_with = "lenient::f64")]
    pub q_norm: f64,
}

impl ProblemDescriptors {
    /// `rank / unknowns`, the rank ratio of ABH 2018.
    pub fn rank_ratio(&self) -> f64 {
        self.rank as f64 / self.unknowns.max(1) as f64
    }
}

/// The descriptors of `problem`, read from `file` and named `name`.
///
/// Rank and condition number come from the eigenvalues of the dense symmetric part
/// `S = (W + W^T)/2` (nalgebra's `symmetric_eigen`, `O(n^3)`: about a second for the
/// 1212 unknowns of the largest stored problem). The rank counts eigenvalues above
/// `1e-12 lambda_max`; the condition number is `lambda_max` over the smallest of those, so a
/// rank-deficient `W` (rigid bodies) gets the condition number of its range.
pub fn describe(problem: &ContactProblem, name: &str, file: &str) -> ProblemDescriptors {
    let n = problem.w.size;
    let mut w = DMatrix::<f64>::zeros(n, n);
    for (i, j, v) in problem.w.triplets() {
        w[(i, j)] += v;
    }
    let (skew, norm) = problem.w.asymmetry();
    let s = (&w + w.transpose()) * 0.5;
    let eigenvalues: Vec<f64> = if n == 0 {
        Vec::new()
    } else {
        s.symmetric_eigen().eigenvalues.iter().copied().collect()
    };
    let spectrum = Spectrum::of(&eigenvalues);
    let finite_mu: Vec<f64> = problem
        .mu
        .iter()
        .copied()
        .filter(|m| m.is_finite())
        .collect();
    ProblemDescriptors {
        name: name.to_string(),
        file: file.to_string(),
        contacts: problem.contacts(),
        unknowns: n,
        nonzeros: problem.w.nonzeros(),
        mu_min: finite_mu
            .iter()
            .copied()
            .reduce(f64::min)
            .unwrap_or(f64::NAN),
        mu_max: finite_mu
            .iter()
            .copied()
            .reduce(f64::max)
            .unwrap_or(f64::NAN),
        stick_contacts: problem.mu.iter().filter(|m| m.is_infinite()).count(),
        frictionless_contacts: problem.mu.iter().filter(|m| **m == 0.0).count(),
        asymmetry: if norm > 0.0 { skew / norm } else { 0.0 },
        rank: spectrum.rank,
        condition: spectrum.condition,
        eigenvalue_min: spectrum.min,
        eigenvalue_max: spectrum.max,
        q_norm: problem.q.iter().map(|v| v * v).sum::<f64>().sqrt(),
    }
}

/// Rank and condition number from a symmetric matrix's eigenvalues.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Spectrum {
    rank: usize,
    condition: f64,
    min: f64,
    max: f64,
}

impl Spectrum {
    fn of(eigenvalues: &[f64]) -> Self {
        let max = eigenvalues
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let min = eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
        if !(max > 0.0) {
            return Spectrum {
                rank: 0,
                condition: f64::NAN,
                min: if eigenvalues.is_empty() {
                    f64::NAN
                } else {
                    min
                },
                max: if eigenvalues.is_empty() {
                    f64::NAN
                } else {
                    max
                },
            };
        }
        let kept: Vec<f64> = eigenvalues
            .iter()
            .copied()
            .filter(|&l| l > RANK_THRESHOLD * max)
            .collect();
        let smallest_kept = kept.iter().copied().fold(f64::INFINITY, f64::min);
        Spectrum {
            rank: kept.len(),
            condition: max / smallest_kept,
            min,
            max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(n: usize, triplets: &[(usize, usize, f64)], mu: Vec<f64>) -> ContactProblem {
        let q: Vec<f64> = (0..n)
            .map(|i| if i % 3 == 0 { -1.0 } else { 0.0 })
            .collect();
        crate::contact_compare::test_problem(triplets, &q, &mu)
    }

    /// `W = [[2, 1.5, 0], [0.5, 2, 0], [0, 0, 0]]`: symmetric part `[[2, 1, 0], [1, 2, 0], 0]`
    /// with eigenvalues 3, 1, 0 (rank 2, condition 3); `W - W^T` has two entries of size 1.
    #[test]
    fn descriptors_of_a_matrix_with_known_eigenvalues() {
        let p = problem(
            3,
            &[(0, 0, 2.0), (0, 1, 1.5), (1, 0, 0.5), (1, 1, 2.0)],
            vec![0.3],
        );
        let d = describe(&p, "p", "p.json");
        assert_eq!((d.contacts, d.unknowns, d.nonzeros), (1, 3, 4));
        assert_eq!(d.rank, 2);
        assert!((d.condition - 3.0).abs() < 1e-12, "{}", d.condition);
        assert!((d.eigenvalue_max - 3.0).abs() < 1e-12);
        assert!(d.eigenvalue_min.abs() < 1e-12);
        let expected = 2f64.sqrt() / (4.0 + 2.25 + 0.25 + 4.0f64).sqrt();
        assert!((d.asymmetry - expected).abs() < 1e-15, "{}", d.asymmetry);
        assert_eq!((d.mu_min, d.mu_max), (0.3, 0.3));
        assert_eq!(d.q_norm, 1.0);
        assert!((d.rank_ratio() - 2.0 / 3.0).abs() < 1e-15);
    }

    /// Diagonal `diag(1e-3, 1, 10, 4, 5, 6)` over two contacts: full rank, condition 1e4; one
    /// stick and one frictionless contact leave no finite non-zero mu but mu bounds of 0.
    #[test]
    fn a_diagonal_matrix_and_the_contact_counts() {
        let diag = [1e-3, 1.0, 10.0, 4.0, 5.0, 6.0];
        let t: Vec<_> = diag.iter().enumerate().map(|(i, &v)| (i, i, v)).collect();
        let d = describe(&problem(6, &t, vec![f64::INFINITY, 0.0]), "d", "d.json");
        assert_eq!(d.rank, 6);
        assert!((d.condition - 1e4).abs() < 1e-8);
        assert_eq!(d.asymmetry, 0.0);
        assert_eq!((d.stick_contacts, d.frictionless_contacts), (1, 1));
        assert_eq!((d.mu_min, d.mu_max), (0.0, 0.0));
        // Every contact sticking leaves no finite mu: NaN, not a made-up number.
        let all_stick = describe(&problem(3, &t[..3], vec![f64::INFINITY]), "s", "s.json");
        assert!(all_stick.mu_min.is_nan() && all_stick.mu_max.is_nan());
    }

    #[test]
    fn an_indefinite_symmetric_part_has_a_negative_smallest_eigenvalue() {
        // [[1, 0], [0, -2]] in the first two unknowns, zero elsewhere: eigenvalues 1, 0, -2.
        let d = describe(
            &problem(3, &[(0, 0, 1.0), (1, 1, -2.0)], vec![0.1]),
            "i",
            "i.json",
        );
        assert_eq!(d.rank, 1);
        assert_eq!(d.condition, 1.0);
        assert!((d.eigenvalue_min + 2.0).abs() < 1e-12);
    }
}
