//! The per-step contact problem solved by Gauss-Seidel with Coulomb friction (thesis 6.5, 6.6;
//! Carpenter, Taylor & Katona 1991; FORMULATION section 4).

use nalgebra::Vector3;

use super::local::{contact_natural_map, local_frame};

/// The fraction of the largest diagonal Delassus entry below which a direction counts as locked
/// in [`ContactConstraint::trial`]: `|P e|^2 < 1/100`, a normal within 6 degrees of the
/// prescribed axes. A block node held on a quarter model's plane of symmetry, meeting a face of
/// the nail's faceted tip almost parallel to that plane, was thrown at 57 km/s to close a gap
/// of a fraction of a micrometre.
pub const LOCKED_DIRECTION: f64 = 1e-2;

/// One node-to-face constraint: slave node `s` against the point `sum_c N_c x_c` of the master
/// face `(a, b, c)` (thesis 6.4.1.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactConstraint {
    /// Global index of the slave node `s`.
    pub slave: u32,
    /// Global indices of the master face's nodes `(a, b, c)`, counter-clockwise seen from
    /// outside the master body.
    pub face: [u32; 3],
    /// Barycentric weights `N_c` of the contact point on the face.
    pub weights: [f64; 3],
    /// Outward unit normal of the master face: a compressive force has `r . n >= 0`.
    pub normal: Vector3<f64>,
    /// Coulomb coefficient `mu`; `f64::INFINITY` is stick, `0` frictionless.
    pub friction: f64,
    /// The penetration along `normal` the step may leave (m, `>= 0`; 0 for a contact made in
    /// the step): a penetration left from an earlier step is removed at a bounded rate
    /// ([`super::ContactPair::penetration_release_speed`]), not in one step.
    pub allowance: f64,
}

impl ContactConstraint {
    /// Gap vector `g = sum_c N_c x_c - x_s - a n`, from the slave node to its target point, the
    /// contact point moved into the master by the allowance `a`: a penetration is closed when
    /// `g . n <= 0`.
    #[inline]
    pub fn gap(&self, x: &[Vector3<f64>]) -> Vector3<f64> {
        let [a, b, c] = self.face.map(|n| x[n as usize]);
        a * self.weights[0] + b * self.weights[1] + c * self.weights[2]
            - x[self.slave as usize]
            - self.normal * self.allowance
    }

    /// Diagonal Delassus block `w_ii = beta dt^2 (M_s^-1 + sum_c N_c^2 M_c^-1)` (thesis (6.71b)),
    /// as its diagonal in global axes. The mass is lumped, so it is a multiple of the identity
    /// unless a node has prescribed components: those have a zero inverse mass, because contact
    /// cannot move them.
    #[inline]
    pub fn delassus_diagonal(&self, inverse_mass: &[Vector3<f64>], beta_dt2: f64) -> Vector3<f64> {
        let face = (0..3).fold(Vector3::zeros(), |sum, k| {
            sum + inverse_mass[self.face[k] as usize] * self.weights[k].powi(2)
        });
        (inverse_mass[self.slave as usize] + face) * beta_dt2
    }

    /// Moves the slave and face nodes as the force change `dr` demands:
    /// `dx_s = beta dt^2 M_s^-1 dr`, `dx_c = -beta dt^2 N_c M_c^-1 dr` (thesis (6.71d)).
    #[inline]
    pub fn apply(
        &self,
        dr: &Vector3<f64>,
        inverse_mass: &[Vector3<f64>],
        beta_dt2: f64,
        x: &mut [Vector3<f64>],
    ) {
        let s = self.slave as usize;
        x[s] += dr.component_mul(&inverse_mass[s]) * beta_dt2;
        for k in 0..3 {
            let c = self.face[k] as usize;
            x[c] -= dr.component_mul(&inverse_mass[c]) * (beta_dt2 * self.weights[k]);
        }
    }

    /// The force that would close the gap `g` from the force `r` with the diagonal block `w`,
    /// before projection. Frictionless, only the normal force acts: `r_n + n.g / n.w n`.
    /// Otherwise, where `w` is isotropic (every node of the contact free, the lumped-mass case
    /// of the thesis), every component closes its own gap, `r + g / w`. Where prescribed
    /// components make it anisotropic, the same is done in the contact's frame (normal and two
    /// tangents `e`, each with its own `e.w e`): in global axes a component that only a face
    /// node of small weight `N` can move has `w_d ~ N^2 / m`, its trial force grows as `1 / N^2`
    /// and, through a tilted normal, becomes a normal force of the same size. A slave held on a
    /// plane of symmetry at a nail's tip had its gap closed by a force 1e16 times too large
    /// (thesis (6.71) assumes the isotropic lumped block). Directions nothing can move
    /// (`e.w e = 0`) keep their force.
    ///
    /// A direction the nodes reach only through components of weight below
    /// [`LOCKED_DIRECTION`] times the block's largest (`e.w e < LOCKED_DIRECTION max w_d`) counts
    /// as one nothing moves: closing a gap `g` along it would move the nodes by `g / |P e|`
    /// (`P` onto their free components) along the face, ten times the gap or more.
    #[inline]
    pub fn trial(&self, r: &Vector3<f64>, g: &Vector3<f64>, w: &Vector3<f64>) -> Vector3<f64> {
        let movable = |we: f64| we > LOCKED_DIRECTION * w.max();
        if self.friction == 0.0 {
            let wn = self.normal.dot(&w.component_mul(&self.normal));
            let rn = r.dot(&self.normal);
            return if movable(wn) {
                self.normal * (rn + self.normal.dot(g) / wn)
            } else {
                self.normal * rn
            };
        }
        if w.x == w.y && w.y == w.z {
            return r + Vector3::from_fn(|d, _| if w[d] > 0.0 { g[d] / w[d] } else { 0.0 });
        }
        let frame = local_frame(&self.normal);
        let mut trial = Vector3::zeros();
        for k in 0..3 {
            let e: Vector3<f64> = frame.row(k).transpose();
            let we = e.dot(&w.component_mul(&e));
            let re = r.dot(&e);
            trial += e * if movable(we) { re + e.dot(g) / we } else { re };
        }
        trial
    }

    /// Whether the admissible force `r` lies on the Coulomb cone (the contact slides); never for
    /// frictionless or sticking contacts. Within 1e-6 of the cone counts as on it: an
    /// interior-point solution approaches the cone from inside.
    #[inline]
    pub fn slides(&self, r: &Vector3<f64>) -> bool {
        if self.friction == 0.0 || self.friction.is_infinite() {
            return false;
        }
        let rn = r.dot(&self.normal);
        (r - self.normal * rn).norm() >= self.friction * rn * (1.0 - 1e-6)
    }

    /// The admissible force nearest `r`: released when tensile (6.74), returned radially onto the
    /// Coulomb cone `|r_t| <= mu r_n` when it slides (6.77).
    #[inline]
    pub fn project(&self, r: Vector3<f64>) -> Vector3<f64> {
        let rn = r.dot(&self.normal);
        if rn <= 0.0 {
            return Vector3::zeros();
        }
        if self.friction.is_infinite() {
            return r;
        }
        let normal = self.normal * rn;
        let tangential = r - normal;
        let limit = self.friction * rn;
        let t = tangential.norm();
        if t <= limit {
            r
        } else {
            normal + tangential * (limit / t)
        }
    }
}

/// Stopping rule of the iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussSeidelSettings {
    /// Converged when `||dr|| <= tolerance ||r||` over a sweep (6.72) and the natural-map
    /// residual of the contact problem (`problem::natural_map_error`, in the problem's scaled
    /// units) is at most `tolerance` too: the change of a sweep alone can be small long before
    /// the law holds, on stiffly coupled contacts.
    pub tolerance: f64,
    /// Most sweeps over the contacts before the iteration stops unconverged (default 500).
    pub max_iterations: usize,
}

impl Default for GaussSeidelSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 500,
        }
    }
}

/// Forces found and how the iteration ended.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSolution {
    /// Force `r_i` on each slave node (and `-N_c r_i` on its face nodes).
    pub forces: Vec<Vector3<f64>>,
    /// Sweeps made.
    pub iterations: usize,
    /// Whether both stopping tests held before `max_iterations`.
    pub converged: bool,
    /// `||dr|| / ||r||` of the last sweep.
    pub residual: f64,
}

/// Gauss-Seidel over the constraints in their given order (thesis Box 6.1): each one recomputes
/// its gap from the positions corrected so far, takes the force change that closes it,
/// projects the total force onto the admissible set, and applies only the change. Positions `x`
/// are corrected in place; `beta_dt2 = (beta_0 + 1/2) dt^2` (6.4.2.4).
pub fn gauss_seidel(
    constraints: &[ContactConstraint],
    inverse_mass: &[Vector3<f64>],
    beta_dt2: f64,
    x: &mut [Vector3<f64>],
    settings: &GaussSeidelSettings,
) -> ContactSolution {
    let w: Vec<Vector3<f64>> = constraints
        .iter()
        .map(|c| c.delassus_diagonal(inverse_mass, beta_dt2))
        .collect();
    let mut forces = vec![Vector3::zeros(); constraints.len()];
    let mut residual = 0.0;
    let law = LawCheck::new(constraints, &w, x);
    for iteration in 1..=settings.max_iterations {
        let (mut change, mut total) = (0.0, 0.0);
        for (i, c) in constraints.iter().enumerate() {
            let r = c.project(c.trial(&forces[i], &c.gap(x), &w[i]));
            let dr = r - forces[i];
            if dr != Vector3::zeros() {
                c.apply(&dr, inverse_mass, beta_dt2, x);
            }
            forces[i] = r;
            change += dr.norm_squared();
            total += r.norm_squared();
        }
        residual = if total > 0.0 {
            (change / total).sqrt()
        } else {
            change.sqrt()
        };
        if (residual <= settings.tolerance
            && law.error(constraints, &forces, x) <= settings.tolerance)
            || (total == 0.0 && change == 0.0)
        {
            return ContactSolution {
                forces,
                iterations: iteration,
                converged: true,
                residual,
            };
        }
    }
    ContactSolution {
        forces,
        iterations: settings.max_iterations,
        converged: false,
        residual,
    }
}

/// The natural-map residual of the problem Gauss-Seidel is solving, read from the positions:
/// the same number as `problem::natural_map_error` on the assembled problem (local frames, the
/// multipliers scaled by the mean Delassus diagonal, `u = -d` the corrected gap).
struct LawCheck {
    frames: Vec<nalgebra::Matrix3<f64>>,
    compliance: f64,
    /// `||q||`: the gaps before any correction.
    q_norm: f64,
}

impl LawCheck {
    fn new(constraints: &[ContactConstraint], w: &[Vector3<f64>], x: &[Vector3<f64>]) -> Self {
        let trace: f64 = w.iter().map(|d| d.sum()).sum();
        let n = 3 * constraints.len();
        Self {
            frames: constraints.iter().map(|c| local_frame(&c.normal)).collect(),
            compliance: if trace > 0.0 { trace / n as f64 } else { 1.0 },
            q_norm: constraints
                .iter()
                .map(|c| c.gap(x).norm_squared())
                .sum::<f64>()
                .sqrt(),
        }
    }

    fn error(
        &self,
        constraints: &[ContactConstraint],
        forces: &[Vector3<f64>],
        x: &[Vector3<f64>],
    ) -> f64 {
        let sum: f64 = constraints
            .iter()
            .zip(forces)
            .zip(&self.frames)
            .map(|((c, r), frame)| {
                let r = frame * r * self.compliance;
                let u = -(frame * c.gap(x));
                contact_natural_map(&r, &u, c.friction).norm_squared()
            })
            .sum();
        if self.q_norm > 0.0 {
            sum.sqrt() / self.q_norm
        } else {
            sum.sqrt()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slave node 1 mm inside a face of three nodes, all of unit mass.
    fn single(
        friction: f64,
        slave_offset: Vector3<f64>,
    ) -> (Vec<ContactConstraint>, Vec<Vector3<f64>>) {
        let x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.25, 0.25, 0.0) + slave_offset,
        ];
        let c = ContactConstraint {
            slave: 3,
            face: [0, 1, 2],
            weights: [0.5, 0.25, 0.25],
            normal: Vector3::z(),
            friction,
            allowance: 0.0,
        };
        (vec![c], x)
    }

    #[test]
    fn a_penetration_is_closed_in_one_step_with_momentum_kept() {
        let (c, mut x) = single(0.0, Vector3::new(0.0, 0.0, -1e-3));
        let inv = vec![Vector3::repeat(1.0); 4];
        let before: Vector3<f64> = x.iter().sum();
        let s = gauss_seidel(&c, &inv, 0.5, &mut x, &GaussSeidelSettings::default());
        assert!(s.converged);
        assert!(c[0].gap(&x).norm() < 1e-15);
        assert!(s.forces[0].z > 0.0, "compressive");
        // Equal masses: the corrections sum to zero, so the centre of mass does not move.
        let after: Vector3<f64> = x.iter().sum();
        assert!((after - before).norm() < 1e-15);
    }

    /// A slave held in x and z (on two planes of symmetry, as a nail's tip on the axis of a
    /// quarter model) 1 um inside a face tilted 56 degrees from the horizontal, whose point
    /// lies almost on the held corner `a` (weights 1 - 2e-6, 1e-6, 1e-6; `a` held in x and z
    /// too). Only the y components of the slave and `a`, and the far corners with tiny weight,
    /// can move. With friction the gap is closed by moves of the order of the gap: the largest
    /// move stays below 10 um. (The per-component trial in global axes gave x a force of order
    /// `g_x / (N^2 / m)`, which the tilted normal turned into a normal force 1e12 times too
    /// large: the nodes moved by 4.7e4 m.)
    #[test]
    fn a_held_slave_near_a_held_corner_is_corrected_by_the_size_of_its_gap() {
        let n = Vector3::new(0.83, -0.55, 0.0).normalize();
        let x0 = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 1.5, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::zeros(),
        ];
        let eps = 1e-6;
        let weights = [1.0 - 2.0 * eps, eps, eps];
        let point = x0[0] * weights[0] + x0[1] * weights[1] + x0[2] * weights[2];
        let mut x = x0.clone();
        x[3] = point - n * 1e-6; // 1 um inside the master, against its outward normal
        let c = ContactConstraint {
            slave: 3,
            face: [0, 1, 2],
            weights,
            normal: n,
            friction: 0.5,
            allowance: 0.0,
        };
        let held = Vector3::new(0.0, 1.0, 0.0);
        let inv = vec![held, Vector3::repeat(1.0), Vector3::repeat(1.0), held];
        let before = x.clone();
        let s = gauss_seidel(&[c], &inv, 0.5, &mut x, &GaussSeidelSettings::default());
        let largest = x
            .iter()
            .zip(&before)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(
            largest < 1e-5,
            "largest move {largest:e} m, forces {:?}",
            s.forces
        );
        assert!(c.gap(&x).dot(&n) <= 1e-12, "the normal gap is closed");
    }

    /// A slave 10 um inside a frictionless face with an allowance of 9 um (a penetration left
    /// from an earlier step, released at a bounded rate): the solve takes it out by 1 um only,
    /// and leaves it 9 um inside. Without the allowance the whole 10 um is closed.
    #[test]
    fn an_allowance_leaves_that_much_penetration() {
        let x0 = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.25, 0.25, -10e-6),
        ];
        let inv = vec![Vector3::repeat(1.0); 4];
        let depth = |c: &ContactConstraint, x: &[Vector3<f64>]| {
            let free = ContactConstraint {
                allowance: 0.0,
                ..*c
            };
            free.gap(x).dot(&c.normal)
        };
        for (allowance, left) in [(9e-6, 9e-6), (0.0, 0.0)] {
            let c = ContactConstraint {
                slave: 3,
                face: [0, 1, 2],
                weights: [0.5, 0.25, 0.25],
                normal: Vector3::z(),
                friction: 0.0,
                allowance,
            };
            let mut x = x0.clone();
            assert!((depth(&c, &x) - 10e-6).abs() < 1e-18);
            gauss_seidel(&[c], &inv, 0.5, &mut x, &GaussSeidelSettings::default());
            assert!((depth(&c, &x) - left).abs() < 1e-15, "{}", depth(&c, &x));
        }
    }

    /// A slave held in x (on a plane of symmetry x = 0) 1 um inside a face almost parallel to
    /// that plane (normal 3.6 degrees from x), whose two heavy-weight nodes are held in x too:
    /// only moves along the face, by `g / |P n|`, could close the gap. The direction is locked
    /// (`LOCKED_DIRECTION`): nothing moves by more than the gap. Without the lock a node
    /// moved 40 times the gap along the face (at a nail's tip, with a step of 5e-10 s, such a
    /// move threw a node at 57 km/s).
    #[test]
    fn a_gap_only_closable_along_a_plane_of_symmetry_is_left_alone() {
        let n = Vector3::new(1.0, 0.045, 0.045).normalize();
        let mut x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.05, 0.0, 1.0),
            Vector3::zeros(),
        ];
        let weights = [0.4995, 0.4995, 0.001];
        let point = x[0] * weights[0] + x[1] * weights[1] + x[2] * weights[2];
        let gap = 1e-6;
        x[3] = point - n * gap;
        let c = ContactConstraint {
            slave: 3,
            face: [0, 1, 2],
            weights,
            normal: n,
            friction: 0.5,
            allowance: 0.0,
        };
        let held = Vector3::new(0.0, 1.0, 1.0);
        let inv = vec![held, held, Vector3::repeat(1.0), held];
        let w = c.delassus_diagonal(&inv, 1.0);
        assert!(n.dot(&w.component_mul(&n)) < LOCKED_DIRECTION * w.max());
        let before = x.clone();
        gauss_seidel(&[c], &inv, 1.0, &mut x, &GaussSeidelSettings::default());
        let largest = x
            .iter()
            .zip(&before)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(
            largest <= gap,
            "a node moved {largest:.3e} m for a gap of {gap:.0e} m"
        );
    }

    #[test]
    fn a_slave_held_along_the_normal_leaves_the_face_to_move() {
        // The slave's z is prescribed (inverse mass 0 in z): the face alone closes the gap, and
        // the slave keeps its place.
        let (c, mut x) = single(0.0, Vector3::new(0.0, 0.0, -1e-3));
        let mut inv = vec![Vector3::repeat(1.0); 4];
        inv[3].z = 0.0;
        let slave = x[3];
        let s = gauss_seidel(&c, &inv, 0.5, &mut x, &GaussSeidelSettings::default());
        assert!(s.converged);
        assert!(c[0].gap(&x).z.abs() < 1e-15);
        assert_eq!(x[3], slave);
        // Only the face moves: the whole gap goes to it, w = beta dt^2 sum N_c^2 / m_c.
        let w = 0.5 * (0.5f64.powi(2) + 2.0 * 0.25f64.powi(2));
        assert!((s.forces[0].z - 1e-3 / w).abs() < 1e-12 * 1e-3 / w);
    }

    #[test]
    fn a_separating_node_is_released() {
        let (c, mut x) = single(0.0, Vector3::new(0.0, 0.0, 1e-3));
        let s = gauss_seidel(
            &c,
            &[Vector3::repeat(1.0); 4],
            0.5,
            &mut x,
            &GaussSeidelSettings::default(),
        );
        assert_eq!(s.forces[0], Vector3::zeros());
    }

    #[test]
    fn friction_is_returned_onto_the_coulomb_cone() {
        let (c, _) = single(0.3, Vector3::zeros());
        let r = c[0].project(Vector3::new(4.0, 3.0, 10.0));
        assert!((Vector3::new(r.x, r.y, 0.0).norm() - 3.0).abs() < 1e-12);
        assert!((r.z - 10.0).abs() < 1e-15);
        // Inside the cone: untouched; stick: untouched.
        assert_eq!(
            c[0].project(Vector3::new(1.0, 1.0, 10.0)),
            Vector3::new(1.0, 1.0, 10.0)
        );
        let (stick, _) = single(f64::INFINITY, Vector3::zeros());
        assert_eq!(
            stick[0].project(Vector3::new(40.0, 30.0, 1.0)),
            Vector3::new(40.0, 30.0, 1.0)
        );
    }

    #[test]
    fn coupled_contacts_converge_to_the_exact_solution_of_w_r_equals_g() {
        // Two slaves pressing on one shared face: the off-diagonal Delassus blocks couple them.
        let mut x = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.2, 0.2, -2e-3),
            Vector3::new(0.5, 0.3, -1e-3),
        ];
        let inv_scalar = [1.0, 0.5, 2.0, 1.0, 3.0];
        let inv: Vec<Vector3<f64>> = inv_scalar.iter().map(|&m| Vector3::repeat(m)).collect();
        let make = |slave: u32, w: [f64; 3]| ContactConstraint {
            slave,
            face: [0, 1, 2],
            weights: w,
            normal: Vector3::z(),
            friction: 0.0,
            allowance: 0.0,
        };
        let c = vec![make(3, [0.6, 0.2, 0.2]), make(4, [0.2, 0.5, 0.3])];
        let beta_dt2 = 1e-2;
        // Frictionless and both active: the normal forces solve the 2x2 system W r = g exactly,
        // with W_ij = beta dt^2 sum_k c_ik c_jk / m_k (FORMULATION 4).
        let coeff = |con: &ContactConstraint| {
            let mut v = [0.0; 5];
            v[con.slave as usize] = -1.0;
            for k in 0..3 {
                v[con.face[k] as usize] += con.weights[k];
            }
            v
        };
        let (c0, c1) = (coeff(&c[0]), coeff(&c[1]));
        let dot = |a: &[f64; 5], b: &[f64; 5]| {
            (0..5).map(|k| a[k] * b[k] * inv_scalar[k]).sum::<f64>() * beta_dt2
        };
        let (w00, w01, w11) = (dot(&c0, &c0), dot(&c0, &c1), dot(&c1, &c1));
        let (g0, g1) = (c[0].gap(&x).z, c[1].gap(&x).z);
        let det = w00 * w11 - w01 * w01;
        let exact = [(w11 * g0 - w01 * g1) / det, (w00 * g1 - w01 * g0) / det];
        let s = gauss_seidel(
            &c,
            &inv,
            beta_dt2,
            &mut x,
            &GaussSeidelSettings {
                tolerance: 1e-14,
                max_iterations: 1000,
            },
        );
        assert!(s.converged && s.iterations > 1, "{s:?}");
        for i in 0..2 {
            assert!(
                (s.forces[i].z - exact[i]).abs() < 1e-10 * exact[i].abs(),
                "{i}: {} vs {}",
                s.forces[i].z,
                exact[i]
            );
            assert!(c[i].gap(&x).norm() < 1e-14);
        }
    }
}
