//! The conic programs Clarabel solves: one contact law per contact (frictionless, stick,
//! associated, Tresca) and the data `P, c, A, b, K` they give (see the module documentation of
//! `conic`).

use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;

use crate::contact::problem::ContactProblem;

/// The constraint one contact gets in a conic program.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Law {
    /// `r_N >= 0`; `r_T` eliminated (zero).
    Frictionless,
    /// `r_N >= 0`; `r_T` free.
    Stick,
    /// `(mu r_N, r_T) ∈ SOC(3)`: the associated relaxation.
    Associated { mu: f64 },
    /// `r_N >= 0` and `|r_T| <= bound` (an SOC whose axis entry is the constant `bound`).
    Tresca { bound: f64 },
}

/// Laws of all contacts: `mu = 0` frictionless, `mu = inf` stick, otherwise `coulomb(mu)`.
pub(super) fn contact_laws(problem: &ContactProblem, coulomb: impl Fn(f64) -> Law) -> Vec<Law> {
    problem
        .mu
        .iter()
        .map(|&mu| {
            if mu == 0.0 {
                Law::Frictionless
            } else if mu.is_infinite() {
                Law::Stick
            } else {
                coulomb(mu)
            }
        })
        .collect()
}

/// Clarabel's data `P, c, A, b, K` for one set of contact laws, and how its variables map to `r`.
pub(super) struct ConicProgram {
    /// Index into `r` (length `3 nc`) of each Clarabel variable.
    variables: Vec<usize>,
    pub(super) p: CscMatrix<f64>,
    pub(super) c: Vec<f64>,
    pub(super) a: CscMatrix<f64>,
    pub(super) b: Vec<f64>,
    pub(super) cones: Vec<SupportedConeT<f64>>,
    /// Per contact, the row of `b` holding its Tresca bound (`None` for other laws).
    bound_rows: Vec<Option<usize>>,
    pub(super) size: usize,
}

impl ConicProgram {
    pub(super) fn build(problem: &ContactProblem, laws: &[Law]) -> Self {
        let size = problem.q.len();
        // Frictionless contacts keep only their normal component.
        let mut index_of = vec![None; size];
        let mut variables = Vec::with_capacity(size);
        for (a, law) in laws.iter().enumerate() {
            let kept = if *law == Law::Frictionless { 1 } else { 3 };
            for k in 0..kept {
                index_of[3 * a + k] = Some(variables.len());
                variables.push(3 * a + k);
            }
        }
        let p = build_p(problem, &index_of, variables.len());
        let c = variables.iter().map(|&i| problem.q[i]).collect();
        let rows = ConeRows::build(laws, &index_of);
        let a = CscMatrix::new_from_triplets(
            rows.b.len(),
            variables.len(),
            rows.rows,
            rows.columns,
            rows.values,
        );
        Self {
            variables,
            p,
            c,
            a,
            b: rows.b,
            cones: rows.cones,
            bound_rows: rows.bound_rows,
            size,
        }
    }

    /// `r` (local, `3 nc`) from Clarabel's `x`; eliminated components are zero.
    pub(super) fn r_of(&self, x: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.size];
        for (&i, &v) in self.variables.iter().zip(x) {
            r[i] = v;
        }
        r
    }

    /// `b` with new Tresca bounds (`bounds[a]` for contacts that have one).
    pub(super) fn b_with_bounds(&self, bounds: &[f64]) -> Vec<f64> {
        let mut b = self.b.clone();
        for (row, bound) in self.bound_rows.iter().zip(bounds) {
            if let Some(row) = row {
                b[*row] = *bound;
            }
        }
        b
    }
}

/// `P = (W + W^T)/2` restricted to the kept components, upper triangle in CSC: Clarabel reads
/// only that triangle, so the symmetrisation is made here, explicitly, rather than by omission.
fn build_p(problem: &ContactProblem, index_of: &[Option<usize>], n: usize) -> CscMatrix<f64> {
    let (mut rows, mut columns, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for (i, j, v) in problem.w.triplets() {
        let (Some(ki), Some(kj)) = (index_of[i], index_of[j]) else {
            continue;
        };
        // A diagonal entry counts once; W_ij and W_ji each add half to the upper entry.
        let (row, column, value) = if ki == kj {
            (ki, kj, v)
        } else {
            (ki.min(kj), ki.max(kj), 0.5 * v)
        };
        rows.push(row);
        columns.push(column);
        values.push(value);
    }
    CscMatrix::new_from_triplets(n, n, rows, columns, values)
}

/// The rows `A x + s = b`, `s ∈ K` of the contact laws: first one non-negative cone collecting
/// every `r_N >= 0` (`A = -1`, `b = 0`), then one `SOC(3)` per Coulomb contact (the first entry
/// of a Clarabel SOC is its axis).
struct ConeRows {
    rows: Vec<usize>,
    columns: Vec<usize>,
    values: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    bound_rows: Vec<Option<usize>>,
}

impl ConeRows {
    fn build(laws: &[Law], index_of: &[Option<usize>]) -> Self {
        let mut out = Self {
            rows: Vec::new(),
            columns: Vec::new(),
            values: Vec::new(),
            b: Vec::new(),
            cones: Vec::new(),
            bound_rows: vec![None; laws.len()],
        };
        let var = |a: usize, k: usize| index_of[3 * a + k].expect("kept component");
        // r_N >= 0 where the law needs it explicitly (the associated SOC implies it).
        let mut nonnegative = 0;
        for (a, law) in laws.iter().enumerate() {
            if !matches!(law, Law::Associated { .. }) {
                out.push_row(&[(var(a, 0), -1.0)], 0.0);
                nonnegative += 1;
            }
        }
        if nonnegative > 0 {
            out.cones
                .push(SupportedConeT::NonnegativeConeT(nonnegative));
        }
        for (a, law) in laws.iter().enumerate() {
            match *law {
                // s = (mu r_N, r_T): A = -diag(mu, 1, 1), b = 0.
                Law::Associated { mu } => {
                    out.push_row(&[(var(a, 0), -mu)], 0.0);
                    out.push_row(&[(var(a, 1), -1.0)], 0.0);
                    out.push_row(&[(var(a, 2), -1.0)], 0.0);
                }
                // s = (bound, r_T): the axis row has no entries, b = bound.
                Law::Tresca { bound } => {
                    out.bound_rows[a] = Some(out.b.len());
                    out.push_row(&[], bound);
                    out.push_row(&[(var(a, 1), -1.0)], 0.0);
                    out.push_row(&[(var(a, 2), -1.0)], 0.0);
                }
                Law::Frictionless | Law::Stick => continue,
            }
            out.cones.push(SupportedConeT::SecondOrderConeT(3));
        }
        out
    }

    fn push_row(&mut self, entries: &[(usize, f64)], b: f64) {
        let row = self.b.len();
        for &(column, value) in entries {
            self.rows.push(row);
            self.columns.push(column);
            self.values.push(value);
        }
        self.b.push(b);
    }
}
