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
//! The driver of a plane is the traction across it raised by the compression along it,
//! `q = t + theta nu <-s_min>` (`theta` = `strain_weight`, `nu` Poisson's ratio, `s_min` the
//! smaller principal value of the stress in the plane, `<x> = max(x, 0)`): on the plane normal to
//! `sigma_1` under a lateral `sigma_2 <= 0` (and `sigma_3 = 0`) the plane opens at
//! `sigma_1 = F - theta nu sigma_2`, Kupfer & Gerstle's (1973) line
//! `sigma_1 / f_t = 1 + 0.8 sigma_2 / f_c` for `theta nu = 0.8 f_t / f_c`; a tension along the
//! plane does not lower it (Kupfer, Hilsdorf & Rüsch 1969: the biaxial tensile strength is about
//! the uniaxial one). The traction is carried from a known stress as M7 carries its planes'
//! normal stress (Caner & Bažant 2013, the elastic predictor `sigma_N,old + E_N d eps_N`):
//! `t = n . sigma_old . n + n . C : (e - e_old) . n`, `sigma_old` a stress of the laws and `e_old`
//! the strain less the crack strains it was computed with; `s_min` is that of `sigma_old`. Where
//! M7 takes `sigma_old` from the last step, the update here iterates it to the stress of this
//! update's own crack strains ([`MicroplaneConcrete::update_with_boundary`]): a traction one
//! update old is a delayed stiffness, which gives back more work than it takes under an
//! oscillating strain.
//!
//! Why the traction of a stress and not the plane's own normal stress `s_V + s_D`: under
//! the kinematic constraint the two part once a law is past its peak. In uniaxial compression
//! (docs/MICROPLANE.md "Tensile boundary", `examples/compression_splitting.rs`) the lateral
//! planes' `s_V + s_D` is about +1.5 MPa at 38 MPa of axial compression while the traction across
//! them is zero, and the former driver `(1 - theta) (s_V + s_D) + theta E e_N` (with the
//! inelastic lateral strain in `e_N`) reached the boundary there. Once a lateral plane opens under
//! a held zero lateral stress its driver cannot fall (every law sees the strain less the crack
//! strains, and those are fixed by the stresses; the plane's crack strain has no axial part), so
//! the crack had no equilibrium: the lateral stress's largest value over all lateral strains was
//! -0.05 MPa and the stress-controlled point stopped. With the traction and Kupfer's term a
//! lateral plane in uniaxial compression `sigma` has `q = theta nu sigma`, which reaches the
//! boundary only at `f_t / (theta nu) = 1.25 f_c`, and falls with the stress after the peak.
//!
//! Per plane, with the others' crack strains held, the driver falls linearly with the plane's
//! own crack strain at the rate `k = 6 w (lambda + 2 mu)`; the crack strain is the root of
//! `q(y) = F(y)` where the plane loads beyond the largest crack strain `y_max` it reached (`F` the
//! boundary of `tension_boundary`), on the secant `q = F(y_max) y / y_max` to the origin below
//! it, and zero where the plane is closed (`q <= 0`). The planes are coupled through `eps_cr` and
//! solved by Gauss-Seidel sweeps to a fixed point.
//!
//! A plane does not open against a compressive traction: where the root lies beyond the crack
//! strain of the last update and its traction `t = q - theta nu <-s_min>` is negative (the
//! boundary `F(y)` exhausted below Kupfer's term), the plane opens only to where its traction is
//! zero, or keeps its last crack strain. Otherwise an exhausted plane under a lateral compression
//! opened while pushed shut, with the traction `F(y) - theta nu <-s_min> < 0`, and its crack work
//! `t dy` was negative: the point generated energy (`examples/tension_boundary_work.rs`). The
//! lateral planes of uniaxial compression, at zero traction, still open by Kupfer's term.

use super::directions::MAX_PLANES;
use super::state;
use super::tension_boundary::{ElementBoundary, PlaneBoundary};
use super::{CrackBand, Microplane, MicroplaneConcrete, Sym, TensionBoundary, UpdateInfo};

/// Most Gauss-Seidel sweeps over the planes; the crack strains of the paths tested converge in
/// a few.
const SWEEPS: usize = 60;

/// Most evaluations of the laws per update in the fixed point of the crack strains and the
/// stress ([`MicroplaneConcrete::update_with_boundary`]).
const CONSISTENCY_ITERATIONS: usize = 30;

/// The fixed point is taken as reached when no component of the element's crack strain moves
/// between two iterations by more than this fraction of its move at the first correction (the
/// iteration contracts by about 0.025 per step on the oscillating point of
/// `examples/tension_boundary_oscillation.rs`, so three evaluations of the laws reach it; the
/// lag left is then about 1e-3 of the one-iteration update's, and so is the work it gives back).
const CONSISTENCY_REDUCTION: f64 = 1e-2;

/// ... or by more than this fraction of the strain at the boundary's strength `f0 / E`: a move
/// at the rounding of the crack strains.
const CONSISTENCY_TOLERANCE: f64 = 1e-12;

/// The elastic constants and the boundary the crack strains are solved with.
#[derive(Debug, Clone, Copy)]
pub(super) struct CrackStrainSolver {
    /// Lamé's `lambda` and `2 mu` (Pa).
    pub lambda: f64,
    pub two_mu: f64,
    /// Young's modulus `E` (Pa): `f0 / E` scales the sweeps' tolerance.
    pub youngs: f64,
    /// `theta`, the strain weight of the driver, and Poisson's ratio `nu`: `theta nu` is the
    /// fall of a plane's strength per unit compression along it.
    pub strain_weight: f64,
    pub poisson: f64,
    /// A stress of the laws (Pa) and the strain less the crack strains it was computed with:
    /// those of the last update, then of the last iteration of this one.
    pub previous_stress: Sym,
    pub previous_elastic: Sym,
    /// The plane boundary of the element (its `youngs` is replaced per plane by `k`).
    pub boundary: PlaneBoundary,
}

/// `n . e . n` for the symmetric tensor `e` with tensor shears and `nn = n (x) n`.
#[inline(always)]
fn normal_part(nn: &Sym, e: &Sym) -> f64 {
    nn[0] * e[0] + nn[1] * e[1] + nn[2] * e[2] + 2.0 * (nn[3] * e[3] + nn[4] * e[4] + nn[5] * e[5])
}

/// `a . s . b` for the symmetric tensor `s` with tensor shears.
#[inline(always)]
fn bilinear(a: &[f64; 3], s: &Sym, b: &[f64; 3]) -> f64 {
    a[0] * (s[0] * b[0] + s[5] * b[1] + s[4] * b[2])
        + a[1] * (s[5] * b[0] + s[1] * b[1] + s[3] * b[2])
        + a[2] * (s[4] * b[0] + s[3] * b[1] + s[2] * b[2])
}

impl CrackStrainSolver {
    /// The part of a plane's driver that does not change within the update: the traction of the
    /// last stress less the elastic traction of the last strain less cracks, and Kupfer's term
    /// `theta nu <-s_min>` of the last stress (see the module doc).
    /// Returned as `(base, kupfer)`, `base` including `kupfer`.
    fn driver_base(&self, plane: &Microplane) -> (f64, f64) {
        let (s, e) = (&self.previous_stress, &self.previous_elastic);
        let (m, k) = (&plane.m, &plane.k);
        let (smm, skk, smk) = (bilinear(m, s, m), bilinear(k, s, k), bilinear(m, s, k));
        let smallest = 0.5 * (smm + skk) - (0.25 * (smm - skk).powi(2) + smk * smk).sqrt();
        let kupfer = self.strain_weight * self.poisson * (-smallest).max(0.0);
        (
            normal_part(&plane.nn, s) - self.elastic_traction(&plane.nn, e) + kupfer,
            kupfer,
        )
    }

    /// `n . C : e . n = lambda tr(e) + 2 mu e_N`, the elastic traction of the strain `e`.
    #[inline(always)]
    fn elastic_traction(&self, nn: &Sym, e: &Sym) -> f64 {
        self.lambda * (e[0] + e[1] + e[2]) + self.two_mu * normal_part(nn, e)
    }

    /// The rate `k` at which a plane's driver falls with its own crack strain.
    #[inline(always)]
    fn own_rate(&self, plane: &Microplane) -> f64 {
        6.0 * plane.weight * (self.lambda + self.two_mu)
    }

    /// The crack strain of a plane whose driver is `q0` at zero own crack strain, with Kupfer's
    /// term `kupfer` in it, the largest crack strain `reached` and the crack strain `last` of the
    /// last update (see the module doc): the root of the boundary or its secant, except that the
    /// plane does not open beyond `last` against a compressive traction `t = q0 - kupfer - k y`.
    /// There it opens only to where its traction is zero, `y = (q0 - kupfer) / k`, or stays at
    /// `last`, so that the work `t dy` of a plane that opens is never negative.
    fn plane_crack_strain(&self, q0: f64, kupfer: f64, k: f64, reached: f64, last: f64) -> f64 {
        let root = self.boundary_root(q0, k, reached);
        if root > last && q0 - kupfer - k * root < 0.0 {
            return root.min(last.max((q0 - kupfer) / k));
        }
        root
    }

    /// The crack strain of a plane whose driver is `q0` at zero own crack strain, with the
    /// largest crack strain `reached`, on the boundary `q = F(y)` beyond `reached`, on its secant
    /// below it, and zero where the driver is not positive.
    fn boundary_root(&self, q0: f64, k: f64, reached: f64) -> f64 {
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

    /// The element's crack strain for the strain `strain` and each plane's crack strain, from
    /// the planes' histories `histories` (the `D+` slots of each plane: largest crack strain,
    /// crack strain, of the last update); [`write_crack_strains`] commits them. `None` while no
    /// plane has cracked and none reaches its strength (the crack strain is zero).
    pub(super) fn solve(
        &self,
        planes: &[Microplane],
        histories: &[f32],
        strain: &Sym,
    ) -> Option<(Sym, [f64; MAX_PLANES])> {
        let slot = |p: usize| state::PER_PLANE * p + state::D_POSITIVE;
        let (mut base, mut kupfer) = ([0.0; MAX_PLANES], [0.0; MAX_PLANES]);
        let (base, kupfer) = (&mut base[..planes.len()], &mut kupfer[..planes.len()]);
        for ((b, c), plane) in base.iter_mut().zip(kupfer.iter_mut()).zip(planes) {
            (*b, *c) = self.driver_base(plane);
        }
        let driver = |p: usize, e: &Sym| base[p] + self.elastic_traction(&planes[p].nn, e);
        let cracked = (0..planes.len()).any(|p| histories[slot(p)] > 0.0);
        if !cracked && (0..planes.len()).all(|p| driver(p, strain) <= self.boundary.f0) {
            return None;
        }
        // On the stack, as the plane loop's arrays: no allocation per update.
        let mut all = [0.0; MAX_PLANES];
        let y = &mut all[..planes.len()];
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
                let q0 = driver(p, &elastic) + k * y[p];
                let (reached, last) = (histories[slot(p)] as f64, histories[slot(p) + 1] as f64);
                let next = self.plane_crack_strain(q0, kupfer[p], k, reached, last);
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
        Some((crack, all))
    }
}

/// Writes the planes' crack strains `y` into their histories `histories` (the `D+` slots:
/// the largest crack strain reached and the crack strain).
fn write_crack_strains(histories: &mut [f32], y: &[f64]) {
    for (h, &y) in histories.chunks_exact_mut(state::PER_PLANE).zip(y) {
        let s = state::D_POSITIVE;
        h[s] = h[s].max(y as f32);
        h[s + 1] = y as f32;
    }
}

impl MicroplaneConcrete {
    /// The update with the tensile boundary: the planes' crack strains (`crack_strain`) and the
    /// laws for the strain less them, `planes` the planes' histories followed by the
    /// [`state::BOUNDARY_HISTORY`] values of the last stress and the strain less cracks it saw.
    ///
    /// The drivers' traction is that of a stress, and the stress is that of the laws at the strain
    /// less the crack strains the drivers give: the two are iterated to a fixed point within the
    /// update, each iteration starting the drivers from the stress the laws gave at the last
    /// one, with the histories of the last update. With the drivers from the last update's stress
    /// alone (one iteration) the traction lags the laws by one update wherever the laws are not
    /// the elastic moduli the drivers assume (the shear released by the boundary, Kupfer's term
    /// of the last stress): a delayed stiffness, which under a strain of amplitude `a`
    /// oscillating about a softened state gives back more work than it takes, up to 3 % of
    /// `E a^2` per period of 3 to 24 updates (`examples/tension_boundary_oscillation.rs`), and
    /// grew the mesh's fastest modes in a free crack band until its energy balance failed.
    /// Iterated, at most 7e-5 of it. An element with no cracked plane and none at its strength
    /// takes one evaluation of the laws, as without the boundary.
    #[inline(always)]
    pub(super) fn update_with_boundary(
        &self,
        boundary: &TensionBoundary,
        header: &mut [f32],
        planes: &mut [f32],
        strain: &Sym,
        f: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        let (planes, last) = planes.split_at_mut(planes.len() - state::BOUNDARY_HISTORY);
        let mut solver = CrackStrainSolver {
            lambda: (self.e_v0 - self.e_d0) / 3.0,
            two_mu: self.e_d0,
            youngs: self.parameters.youngs_modulus,
            strain_weight: boundary.strain_weight,
            poisson: self.parameters.poisson_ratio,
            previous_stress: std::array::from_fn(|i| last[i] as f64),
            previous_elastic: std::array::from_fn(|i| last[6 + i] as f64),
            boundary: ElementBoundary::plane_boundary(boundary, &self.parameters, band, f),
        };
        let count = self.planes.len();
        let Some((mut crack, y)) = solver.solve(&self.planes, planes, strain) else {
            let (sigma, info) = self.update_laws(header, planes, strain, f, band);
            remember(last, &sigma, strain);
            return (sigma, info);
        };
        // The histories of the last update, which every iteration starts from.
        let mut saved_header = [0.0f32; state::HEADER];
        // The planes' laws and, with crack friction, their sliders.
        let mut saved_planes =
            [0.0f32; (state::PER_PLANE + state::FRICTION_PER_PLANE) * MAX_PLANES];
        let saved_planes = &mut saved_planes[..planes.len()];
        saved_header.copy_from_slice(&header[..state::HEADER]);
        saved_planes.copy_from_slice(planes);
        write_crack_strains(planes, &y[..count]);
        let tolerance = CONSISTENCY_TOLERANCE * solver.boundary.f0 / solver.youngs;
        let mut iteration = 1;
        let mut first_move = None;
        loop {
            let uncracked: Sym = std::array::from_fn(|i| strain[i] - crack[i]);
            let (sigma, info) = self.update_laws(header, planes, &uncracked, f, band);
            if iteration == CONSISTENCY_ITERATIONS {
                remember(last, &sigma, &uncracked);
                return (sigma, info);
            }
            solver.previous_stress = sigma;
            solver.previous_elastic = uncracked;
            let (next, y) = solver
                .solve(&self.planes, saved_planes, strain)
                .unwrap_or(([0.0; 6], [0.0; MAX_PLANES]));
            let moved = (0..6).fold(0.0f64, |m, i| m.max((next[i] - crack[i]).abs()));
            let first = *first_move.get_or_insert(moved);
            if moved <= tolerance.max(CONSISTENCY_REDUCTION * first) {
                // The crack strain this stress was computed with is the fixed point.
                remember(last, &sigma, &uncracked);
                return (sigma, info);
            }
            header[..state::HEADER].copy_from_slice(&saved_header);
            planes.copy_from_slice(saved_planes);
            write_crack_strains(planes, &y[..count]);
            crack = next;
            iteration += 1;
        }
    }
}

/// Keeps the stress `sigma` and the strain less cracks `uncracked` of this update in `last`
/// for the next update's drivers.
fn remember(last: &mut [f32], sigma: &Sym, uncracked: &Sym) {
    for i in 0..6 {
        last[i] = sigma[i] as f32;
        last[6 + i] = uncracked[i] as f32;
    }
}
