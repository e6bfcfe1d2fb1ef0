//! The per-step contact problem in algebraic form, FC(W, q, mu), shared by every contact solver
//! and by the recorded or external problem files (FORMULATION section 4; Acary, Bremond &
//! Huber 2018; format `contact-problem/1` of `references/contact-problems/README.md`).
//!
//! Unknowns are the contact multipliers `r`, three per contact in the contact's local frame,
//! ordered `[normal, tangent1, tangent2]`. With `u = W r + q`, the conditions are Signorini's
//! `0 <= u_N _|_ r_N >= 0` and Coulomb's law `r in K = {|r_T| <= mu r_N}`, written with the De
//! Saxce modified velocity `u_hat = u + [mu |u_T|, 0, 0]` as `K* ∋ u_hat _|_ r ∈ K`.
//!
//! For our own steps `q = -g` (the gap vector in the local frame) and `u = -d`, `d = g - W r` the
//! corrected gap: `u_N >= 0` means no penetration remains.

pub use super::local::{contact_natural_map, local_frame, project_on_coulomb_cone};
use nalgebra::{Matrix3, Vector3};

use super::gauss_seidel::ContactConstraint;

/// A square sparse matrix in compressed rows; duplicates of the triplets it was built from are
/// summed, and each row's columns are sorted, so products are deterministic.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseMatrix {
    /// Number of rows and of columns.
    pub size: usize,
    /// Start of each row in `columns` and `values`, `size + 1` entries (the last is the number
    /// of stored entries).
    pub row_start: Vec<usize>,
    /// Column of each stored entry, ascending within a row.
    pub columns: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
}

/// A triplet whose row or column lies outside the matrix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("triplet ({i}, {j}) lies outside the {size} x {size} matrix")]
pub struct TripletOutside {
    /// The row.
    pub i: usize,
    /// The column.
    pub j: usize,
    /// The matrix's size.
    pub size: usize,
}

impl SparseMatrix {
    /// From `(row, column, value)` triplets; an index out of range is an error naming it.
    pub fn from_triplets(
        size: usize,
        triplets: &[(usize, usize, f64)],
    ) -> Result<Self, TripletOutside> {
        let mut sorted = triplets.to_vec();
        if let Some(&(i, j, _)) = sorted.iter().find(|(i, j, _)| *i >= size || *j >= size) {
            return Err(TripletOutside { i, j, size });
        }
        sorted.sort_by_key(|&(i, j, _)| (i, j));
        let mut row_start = vec![0; size + 1];
        let mut columns = Vec::with_capacity(sorted.len());
        let mut values: Vec<f64> = Vec::with_capacity(sorted.len());
        let mut last: Option<(usize, usize)> = None;
        for (i, j, v) in sorted {
            if last == Some((i, j)) {
                *values.last_mut().expect("a previous entry") += v;
                continue;
            }
            last = Some((i, j));
            row_start[i + 1] += 1;
            columns.push(j);
            values.push(v);
        }
        for i in 0..size {
            row_start[i + 1] += row_start[i];
        }
        Ok(Self {
            size,
            row_start,
            columns,
            values,
        })
    }

    /// Number of stored entries.
    pub fn nonzeros(&self) -> usize {
        self.values.len()
    }

    /// The stored entries of row `i` as `(column, value)`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.row_start[i]..self.row_start[i + 1];
        self.columns[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// `(A x)_i`.
    pub fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        self.row(i).map(|(j, v)| v * x[j]).sum()
    }

    /// The product `A x`; `x` has `size` entries.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        (0..self.size).map(|i| self.row_dot(i, x)).collect()
    }

    /// Entry `(i, j)`, zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let range = self.row_start[i]..self.row_start[i + 1];
        match self.columns[range.clone()].binary_search(&j) {
            Ok(k) => self.values[range.start + k],
            Err(_) => 0.0,
        }
    }

    /// The 3x3 block of contacts `a` (rows) and `b` (columns).
    pub fn block(&self, a: usize, b: usize) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| self.get(3 * a + i, 3 * b + j))
    }

    /// All stored entries as `(row, column, value)`, row by row.
    pub fn triplets(&self) -> Vec<(usize, usize, f64)> {
        (0..self.size)
            .flat_map(|i| self.row(i).map(move |(j, v)| (i, j, v)))
            .collect()
    }

    /// `||A - A^T||_F` and `||A||_F`: the asymmetry a solver that reads one triangle removes.
    pub fn asymmetry(&self) -> (f64, f64) {
        let mut skew = 0.0;
        let mut norm = 0.0;
        for (i, j, v) in self.triplets() {
            norm += v * v;
            let d = v - self.get(j, i);
            skew += d * d;
        }
        (skew.sqrt(), norm.sqrt())
    }
}

/// The contact problem FC(W, q, mu) of one step and pass (or of an external file).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactProblem {
    /// Delassus matrix in the contacts' local frames, `3 nc x 3 nc`.
    pub w: SparseMatrix,
    /// Free velocity (here: minus the gap) in the local frames, `3 nc`.
    pub q: Vec<f64>,
    /// Coulomb coefficient per contact; `f64::INFINITY` sticks (r_T free), `0` is frictionless.
    pub mu: Vec<f64>,
    /// Rows `n, t1, t2` in global axes, for problems built from our own constraints.
    pub frames: Option<Vec<Matrix3<f64>>>,
    /// The multipliers' unit: `r = compliance * force`. Our problems are scaled by the mean
    /// diagonal of their Delassus matrix (m/N), so `W` is dimensionless with unit mean diagonal
    /// and `r`, `q`, `u` are all lengths (m): the natural-map residual, which adds `r` and `u`,
    /// is then meaningful. 1 for external problems (forces as given).
    pub compliance: f64,
    /// Where the problem comes from (file, run, step).
    pub source: String,
}

impl ContactProblem {
    /// Number of contacts `nc` (the problem has `3 nc` unknowns).
    pub fn contacts(&self) -> usize {
        self.mu.len()
    }

    /// `u = W r + q`.
    pub fn velocity(&self, r: &[f64]) -> Vec<f64> {
        let mut u = self.w.mul(r);
        u.iter_mut().zip(&self.q).for_each(|(u, q)| *u += q);
        u
    }

    /// Builds the problem of our node-to-face constraints (FORMULATION 4): with the force on
    /// contact `a` acting `+1` on its slave node and `-N_c` on its face nodes, the positions move
    /// by `dx_k = beta dt^2 M_k^-1 sum_b c_bk r_b`, so the gaps change by `-(W r)_a` with
    /// `W_ab = beta dt^2 sum_k c_ak c_bk M_k^-1` (diagonal in global axes, per component because
    /// prescribed components have zero inverse mass). In local frames `R_a` (rows n, t1, t2):
    /// `W^loc_ab = R_a W_ab R_b^T`, `q_a = -R_a g_a`.
    pub fn from_constraints(
        constraints: &[ContactConstraint],
        inverse_mass: &[Vector3<f64>],
        beta_dt2: f64,
        x: &[Vector3<f64>],
        source: String,
    ) -> Self {
        let frames: Vec<Matrix3<f64>> =
            constraints.iter().map(|c| local_frame(&c.normal)).collect();
        // Coefficients of each contact on its four nodes.
        let coefficients = |c: &ContactConstraint| {
            [
                (c.slave, 1.0),
                (c.face[0], -c.weights[0]),
                (c.face[1], -c.weights[1]),
                (c.face[2], -c.weights[2]),
            ]
        };
        // Contacts touching each node, to find the coupled pairs.
        let mut by_node: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
        for (a, c) in constraints.iter().enumerate() {
            for (node, _) in coefficients(c) {
                let list = by_node.entry(node).or_default();
                if list.last() != Some(&a) {
                    list.push(a);
                }
            }
        }
        let mut blocks: std::collections::BTreeMap<(usize, usize), Vector3<f64>> =
            Default::default();
        for (node, list) in &by_node {
            let m = inverse_mass[*node as usize] * beta_dt2;
            for &a in list {
                let ca: f64 = coefficients(&constraints[a])
                    .iter()
                    .filter(|(n, _)| n == node)
                    .map(|(_, c)| c)
                    .sum();
                for &b in list {
                    let cb: f64 = coefficients(&constraints[b])
                        .iter()
                        .filter(|(n, _)| n == node)
                        .map(|(_, c)| c)
                        .sum();
                    *blocks.entry((a, b)).or_insert_with(Vector3::zeros) += m * (ca * cb);
                }
            }
        }
        let mut triplets = Vec::with_capacity(9 * blocks.len());
        for ((a, b), diagonal) in blocks {
            let local = frames[a] * Matrix3::from_diagonal(&diagonal) * frames[b].transpose();
            for i in 0..3 {
                for j in 0..3 {
                    if local[(i, j)] != 0.0 {
                        triplets.push((3 * a + i, 3 * b + j, local[(i, j)]));
                    }
                }
            }
        }
        let n = 3 * constraints.len();
        let trace: f64 = triplets
            .iter()
            .filter(|(i, j, _)| i == j)
            .map(|t| t.2)
            .sum();
        let compliance = if trace > 0.0 { trace / n as f64 } else { 1.0 };
        triplets.iter_mut().for_each(|t| t.2 /= compliance);
        let q = constraints
            .iter()
            .zip(&frames)
            .flat_map(|(c, f)| {
                let g = f * c.gap(x);
                [-g.x, -g.y, -g.z]
            })
            .collect();
        Self {
            w: SparseMatrix::from_triplets(n, &triplets).expect("indices of our own contacts"),
            q,
            mu: constraints.iter().map(|c| c.friction).collect(),
            frames: Some(frames),
            compliance,
            source,
        }
    }

    /// The local multipliers of forces given in global axes (needs the frames), in the
    /// problem's unit (`compliance`).
    pub fn to_local(&self, forces: &[Vector3<f64>]) -> Option<Vec<f64>> {
        let frames = self.frames.as_ref()?;
        Some(
            frames
                .iter()
                .zip(forces)
                .flat_map(|(f, r)| {
                    let l = f * r * self.compliance;
                    [l.x, l.y, l.z]
                })
                .collect(),
        )
    }

    /// The global forces of local multipliers in the problem's unit (needs the frames).
    pub fn to_global(&self, r: &[f64]) -> Option<Vec<Vector3<f64>>> {
        let frames = self.frames.as_ref()?;
        Some(
            frames
                .iter()
                .enumerate()
                .map(|(a, f)| {
                    f.transpose() * Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2])
                        / self.compliance
                })
                .collect(),
        )
    }
}

/// The natural-map residual of FC(W, q, mu) at `r` (Acary, Bremond & Huber 2018, eq. error-1):
/// `F = r - P_K(r - (u + g(u)))`, `u = W r + q`, `g(u)` the De Saxce shift `[mu |u_T|, 0, 0]`
/// per contact, `P_K` the projection onto the product of Coulomb cones. `relative` is
/// `||F||_2 / ||q||_2` (the normalisation of that paper and of Siconos 2016-2020); when `q = 0`
/// it is `||F||_2`.
///
/// Stick (`mu = inf`) is the limit of Coulomb's law without adhesion: a contact that carries a
/// normal force does not slip (`u_T = 0`), one that is released carries no tangential force
/// either (`r_T = 0`, as Gauss-Seidel's release does). Its natural map is
/// `F_N = r_N - max(0, r_N - u_N)` and `F_T = u_T` where `r_N - u_N > 0` (active), `F_T = r_T`
/// elsewhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NaturalMapError {
    /// `||F||_2`, in the problem's units of `r` (lengths for our scaled problems).
    pub absolute: f64,
    /// `||F||_2 / ||q||_2`, dimensionless; `absolute` when `q = 0`.
    pub relative: f64,
}

/// The natural-map residual of `problem` at the multipliers `r` (`3 nc` values, local
/// components), see [`NaturalMapError`].
pub fn natural_map_error(problem: &ContactProblem, r: &[f64]) -> NaturalMapError {
    let u = problem.velocity(r);
    let mut sum = 0.0;
    for (a, &mu) in problem.mu.iter().enumerate() {
        let ra = Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2]);
        let ua = Vector3::new(u[3 * a], u[3 * a + 1], u[3 * a + 2]);
        sum += contact_natural_map(&ra, &ua, mu).norm_squared();
    }
    let q = problem.q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let absolute = sum.sqrt();
    NaturalMapError {
        absolute,
        relative: if q > 0.0 { absolute / q } else { absolute },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triplets_are_summed_and_sorted() {
        let a = SparseMatrix::from_triplets(2, &[(1, 0, 1.0), (0, 1, 2.0), (1, 0, 3.0)]).unwrap();
        assert_eq!(a.get(1, 0), 4.0);
        assert_eq!(a.get(0, 0), 0.0);
        assert_eq!(a.mul(&[1.0, 1.0]), vec![2.0, 4.0]);
        assert_eq!(a.asymmetry().0, 2.0f64.sqrt() * 2.0);
        assert!(SparseMatrix::from_triplets(2, &[(2, 0, 1.0)]).is_err());
    }

    #[test]
    fn frames_are_orthonormal_and_right_handed() {
        for n in [
            Vector3::z(),
            Vector3::new(1.0, 2.0, -3.0).normalize(),
            -Vector3::x(),
        ] {
            let f = local_frame(&n);
            assert!((f * f.transpose() - Matrix3::identity()).norm() < 1e-15);
            assert!((f.determinant() - 1.0).abs() < 1e-15);
            assert_eq!(f.row(0).transpose(), n);
        }
    }

    #[test]
    fn the_natural_map_vanishes_at_solutions_and_not_elsewhere() {
        // Separation: r = 0, u_N > 0.
        let zero = Vector3::zeros();
        assert_eq!(
            contact_natural_map(&zero, &Vector3::new(1.0, 5.0, 0.0), 0.3),
            zero
        );
        // Stick inside the cone with u = 0.
        assert_eq!(
            contact_natural_map(&Vector3::new(1.0, 0.1, 0.0), &zero, 0.3),
            zero
        );
        // Slide: r on the cone, u_N = 0, u_T opposite r_T.
        let r = Vector3::new(1.0, 0.3, 0.0);
        let slide = contact_natural_map(&r, &Vector3::new(0.0, -2.0, 0.0), 0.3);
        assert!(slide.norm() < 1e-15, "{slide}");
        // Sliding the wrong way, and a tensile multiplier, are not solutions.
        assert!(contact_natural_map(&r, &Vector3::new(0.0, 2.0, 0.0), 0.3).norm() > 0.1);
        assert!(contact_natural_map(&Vector3::new(-1.0, 0.0, 0.0), &zero, 0.3).norm() > 0.1);
        // Stick: an active contact must not slip; a released one is free to, with r_T = 0.
        let stick = f64::INFINITY;
        assert_eq!(
            contact_natural_map(&Vector3::new(1.0, 7.0, 0.0), &zero, stick),
            zero
        );
        assert!(
            contact_natural_map(&Vector3::new(1.0, 7.0, 0.0), &Vector3::y(), stick).norm() > 0.5
        );
        assert_eq!(
            contact_natural_map(&zero, &Vector3::new(1.0, 3.0, 0.0), stick),
            zero
        );
        assert!(
            contact_natural_map(&Vector3::y(), &Vector3::new(1.0, 3.0, 0.0), stick).norm() > 0.5
        );
    }

    #[test]
    fn the_assembled_problem_predicts_the_gaps_gauss_seidel_leaves() {
        // W r + q from the assembly against the gaps after moving the nodes by the forces.
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.2, 0.2, -2e-3),
            Vector3::new(0.5, 0.3, -1e-3),
        ];
        let mut inverse_mass: Vec<Vector3<f64>> = [1.0, 0.5, 2.0, 1.0, 3.0]
            .iter()
            .map(|&m| Vector3::repeat(m))
            .collect();
        inverse_mass[1].y = 0.0;
        let normal = Vector3::new(0.1, -0.2, 1.0).normalize();
        let make = |slave: u32, weights: [f64; 3], friction| ContactConstraint {
            slave,
            face: [0, 1, 2],
            weights,
            normal,
            friction,
            allowance: 0.0,
        };
        let c = vec![make(3, [0.6, 0.2, 0.2], 0.3), make(4, [0.2, 0.5, 0.3], 0.0)];
        let beta_dt2 = 1e-2;
        let p = ContactProblem::from_constraints(&c, &inverse_mass, beta_dt2, &x, "test".into());
        let forces = vec![Vector3::new(0.3, -0.1, 0.7), Vector3::new(-0.2, 0.4, 0.5)];
        let mut moved = x.clone();
        for (ci, f) in c.iter().zip(&forces) {
            ci.apply(f, &inverse_mass, beta_dt2, &mut moved);
        }
        let u = p.velocity(&p.to_local(&forces).unwrap());
        for (a, ci) in c.iter().enumerate() {
            let d = p.frames.as_ref().unwrap()[a] * ci.gap(&moved);
            for k in 0..3 {
                assert!((u[3 * a + k] + d[k]).abs() < 1e-15, "{a} {k}");
            }
        }
        let (skew, norm) = p.w.asymmetry();
        assert!(skew < 1e-15 * norm);
    }
}
