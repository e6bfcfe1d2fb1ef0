//! The planes' crack strains and the element's crack strain tensor, for the tensile boundary
//! (`tension_boundary`, docs/MICROPLANE.md "Tensile boundary").
//!
//! Each plane `p` carries a crack strain `y_p >= 0` along its normal. They are homogenised into
//! the element's crack strain by the rule of the stress (5.36),
//! `eps_cr = sum_p 6 w_p y_p n_p (x) n_p`, and every law of the element (volumetric,
//! deviatoric, shear) sees the strain less it, `eps - eps_cr`: a crack opening is not a
//! deformation of the solid between the cracks. In the elastic range the stress is then
//! `C : (eps - eps_cr)` and the work of the crack strains is `sum_p 6 w_p int t_p dy_p` with
//! `t_p = n_p . sigma . n_p` the plane's traction, so the energy a plane dissipates is the area
//! under its own boundary, whatever the other planes do. This is the inelastic normal strain of
//! M7's planes (Caner & Bažant 2013, the boundary acting on the plane's own strain), and the
//! crack band's scaling of each plane's boundary (`TensionBoundary::scaled`, Bažant & Oh 1983)
//! then gives an energy per crack area that does not depend on the element. Without it each
//! plane's normal stress rose with `lambda tr(eps)` as the other planes opened, stored an energy
//! per unit volume before it cracked, and the fracture energy grew with the element
//! (docs/MICROPLANE.md "Tensile boundary": 80 / 100 / 113 N/m at 25 / 50 / 100 mm).
//!
//! Per plane, with the others' crack strains held, the driver
//! `q = (1 - theta) t + theta E n . (eps - eps_cr) . n` falls linearly with the plane's own crack
//! strain at the rate `k = 6 w ((1 - theta) (lambda + 2 mu) + theta E)`; the crack strain is the
//! root of `q(y) = F(y)` where the plane loads beyond the largest crack strain `y_max` it reached
//! (`F` the boundary of `tension_boundary`), on the secant `q = F(y_max) y / y_max` to the
//! origin below it, and zero where the plane is closed (`q <= 0`). The planes are coupled through
//! `eps_cr` and solved by Gauss-Seidel sweeps to a fixed point.

use super::directions::MAX_PLANES;
use super::state;
use super::tension_boundary::PlaneBoundary;
use super::{Microplane, Sym};

/// Most Gauss-Seidel sweeps over the planes; the crack strains of the paths tested converge in
/// a few.
const SWEEPS: usize = 60;

/// The elastic constants and the boundary the crack strains are solved with.
#[derive(Debug, Clone, Copy)]
pub(super) struct CrackStrainSolver {
    /// Lamé's `lambda` and `2 mu` (Pa).
    pub lambda: f64,
    pub two_mu: f64,
    /// Young's modulus `E` (Pa), of the driver's strain part.
    pub youngs: f64,
    /// `theta`, the strain weight of the driver.
    pub strain_weight: f64,
    /// The plane boundary of the element (its `youngs` is replaced per plane by `k`).
    pub boundary: PlaneBoundary,
}

/// `n . e . n` for the symmetric tensor `e` with tensor shears and `nn = n (x) n`.
#[inline(always)]
fn normal_part(nn: &Sym, e: &Sym) -> f64 {
    nn[0] * e[0] + nn[1] * e[1] + nn[2] * e[2] + 2.0 * (nn[3] * e[3] + nn[4] * e[4] + nn[5] * e[5])
}

impl CrackStrainSolver {
    /// The driver of a plane for the strain less the crack strains `e`: its normal stress
    /// `s_V + s_D`, with `s_V = volumetric(e_V)` the volumetric law's stress (elastic in tension,
    /// the compression law with its dilatancy in compression, which is what the plane carries)
    /// and `s_D = 2 mu (e_N - e_V)`, and its normal strain.
    #[inline(always)]
    fn driver(&self, nn: &Sym, e: &Sym, volumetric: &impl Fn(f64) -> f64) -> f64 {
        let normal = normal_part(nn, e);
        let e_v = (e[0] + e[1] + e[2]) / 3.0;
        let traction = volumetric(e_v) + self.two_mu * (normal - e_v);
        traction + self.strain_weight * (self.youngs * normal - traction)
    }

    /// The rate `k` at which a plane's driver falls with its own crack strain.
    #[inline(always)]
    fn own_rate(&self, plane: &Microplane) -> f64 {
        let m = self.lambda + self.two_mu;
        6.0 * plane.weight * (m + self.strain_weight * (self.youngs - m))
    }

    /// The crack strain of a plane whose driver is `q0` at zero own crack strain, with the
    /// largest crack strain `reached` (see the module doc).
    fn plane_crack_strain(&self, q0: f64, k: f64, reached: f64) -> f64 {
        if q0 <= 0.0 {
            return 0.0;
        }
        let b = PlaneBoundary {
            youngs: k,
            ..self.boundary
        };
        if reached > 0.0 {
            let secant = b.value(reached) / reached;
            let on_secant = q0 / (k + secant);
            if on_secant <= reached {
                return on_secant;
            }
        } else if q0 <= b.f0 {
            return 0.0;
        }
        // Loading beyond the largest crack strain: `q0 - k y = F(y)`, the root the boundary's
        // damage gives (`d = k y / q0`).
        b.damage(q0) * q0 / k
    }

    /// The element's crack strain for the strain `strain`, advancing the planes' crack strains
    /// in `planes` (the `D+` slots of each plane: largest crack strain, crack strain). Zero, and
    /// the histories untouched, while no plane has cracked and none reaches its strength.
    pub(super) fn solve(
        &self,
        planes: &[Microplane],
        histories: &mut [f32],
        strain: &Sym,
        volumetric: impl Fn(f64) -> f64,
    ) -> Sym {
        let slot = |p: usize| state::PER_PLANE * p + state::D_POSITIVE;
        let cracked = (0..planes.len()).any(|p| histories[slot(p)] > 0.0);
        if !cracked
            && planes
                .iter()
                .all(|plane| self.driver(&plane.nn, strain, &volumetric) <= self.boundary.f0)
        {
            return [0.0; 6];
        }
        // On the stack, as the plane loop's arrays: no allocation per update.
        let mut y = [0.0; MAX_PLANES];
        let y = &mut y[..planes.len()];
        for (p, y) in y.iter_mut().enumerate() {
            *y = histories[slot(p) + 1] as f64;
        }
        let mut crack = [0.0; 6];
        for (plane, &y) in planes.iter().zip(y.iter()) {
            for i in 0..6 {
                crack[i] += 6.0 * plane.weight * y * plane.nn[i];
            }
        }
        let scale = self.boundary.f0 / self.youngs;
        for _ in 0..SWEEPS {
            let mut change: f64 = 0.0;
            for (p, plane) in planes.iter().enumerate() {
                let k = self.own_rate(plane);
                let elastic: Sym = std::array::from_fn(|i| strain[i] - crack[i]);
                // The driver with the plane's own crack strain given back.
                let q0 = self.driver(&plane.nn, &elastic, &volumetric) + k * y[p];
                let next = self.plane_crack_strain(q0, k, histories[slot(p)] as f64);
                let step = next - y[p];
                if step != 0.0 {
                    for i in 0..6 {
                        crack[i] += 6.0 * plane.weight * step * plane.nn[i];
                    }
                    y[p] = next;
                    change = change.max(step.abs());
                }
            }
            if change <= 1e-9 * scale {
                break;
            }
        }
        for (p, &y) in y.iter().enumerate() {
            let s = slot(p);
            histories[s] = histories[s].max(y as f32);
            histories[s + 1] = y as f32;
        }
        crack
    }
}
