//! The rate-sensitive microplane model for concrete with relaxed kinematic constraint (thesis
//! chapter 5, Ožbolt, Li & Kožar 2001), made precise by `docs/MICROPLANE.md`.
//!
//! One update takes the Green-Lagrange strain `E` of an element (5.4), its equivalent rate
//! `gamma_dot` (5.111) and the element's crack band, and returns the back-rotated Cauchy stress
//! `s` (5.47); the element turns it into Cauchy stress with `sigma = R s R^T`.
//!
//! - [`directions`]: the microplanes and the quadrature on the sphere (5.2, Bažant & Oh 1986);
//! - [`laws`]: the virgin laws (5.19-5.23) and the crack-band scaling of their softening;
//! - [`cyclic`]: loading, unloading and reloading of one component (5.100-5.104);
//! - [`discontinuity`]: the relaxation functions `psi` (5.91, 5.96, 5.97, 5.99);
//! - [`state`]: the history an element carries from step to step;
//! - [`driver`]: a material-point driver for strain- and stress-controlled paths.

pub mod boundary_shape;
pub mod calibration;
mod crack_band;
pub mod crack_compression;
mod crack_strain;
mod crack_width;
pub mod cyclic;
mod dilatancy;
pub mod directions;
pub mod discontinuity;
mod dissipation;
pub mod driver;
mod elastic_path;
mod element;
pub mod experiments;
pub mod laws;
pub mod oscillation;
pub mod parameters;
mod plane_loop;
mod principal;
mod relaxation;
mod shear;
mod side_by_side;
pub mod state;
pub mod tabulated;
pub mod tension_boundary;
pub mod volumetric;

pub use boundary_shape::BoundaryShape;
pub use crack_band::{CrackBand, CrackBandError};
pub use crack_width::{ElementShape, CRACK_HISTORY};
pub use directions::{contract, Microplane, SphereRule, Sym};
pub use element::{sym, MicroplaneMaterial};
pub use parameters::{
    CrackBandWidth, MicroplaneParameters, ParameterError, RateEffect, RelaxationDriver,
    TensionDriver,
};
pub use principal::{
    largest_principal, mazars_strain, principal_stress_for_closure, principal_values,
};
pub use state::MicroplaneState;
pub use tension_boundary::TensionBoundary;
pub use volumetric::VolumetricStrain;

use cyclic::{Branch, UnloadingRule};
use directions::{Projections, MAX_PLANES};
use dissipation::VirginSteps;
use laws::{volumetric_compression, volumetric_compression_tangent, ExponentialLaw};
use plane_loop::PlaneSums;
use side_by_side::SideBySide;

/// The relaxation `psi` below which an element's cracks count as open for crack friction
/// (MICROPLANE "Crack friction"): 1 less the `f32` epsilon. The tension law's secant falls below
/// its initial modulus at any tension, by rounding first (`2^-25` at the elastic path's limit),
/// and a test against 1 engaged every plane's slider at the first volumetric tension, so that
/// the model left linear elasticity where the elastic path (and the thesis) keep it.
const RELAXATION_ONSET: f64 = 1.0 - f32::EPSILON as f64;

/// The model with everything that does not change during a run precomputed.
#[derive(Debug, Clone)]
pub struct MicroplaneConcrete {
    /// The parameters the model was built from (validated).
    pub parameters: MicroplaneParameters,
    planes: Vec<Microplane>,
    /// `N`, `M` and `K` of the planes, component by component (see [`Projections`]).
    projections: Projections,
    /// The planes of the 21-direction rule side by side, for the update that runs them at
    /// once (`side_by_side`); `None` for other rules and with
    /// [`MicroplaneConcrete::with_planes_one_by_one`].
    side_by_side: Option<SideBySide>,
    /// `E_V0 = E / (1 - 2 nu)`, `E_D0 = E_M0 = E_K0 = E / (1 + nu)` (MICROPLANE "Elastic split").
    e_v0: f64,
    e_d0: f64,
    e_t0: f64,
    /// Volumetric and deviatoric tension (exponent `m`), deviatoric compression (`n`), shear (`k`).
    tension: ExponentialLaw,
    compression: ExponentialLaw,
    /// `(1 - 2 nu) / 3`: the equivalent tension driver per unit of Mazars' strain.
    equivalent_factor: f64,
    /// Lamé's `lambda` and `2 mu` over `E`: the elastic stress `C : E / E` of the relaxation's
    /// tensile-stress driver ([`RelaxationDriver::TensileStress`]).
    effective_lambda: f64,
    effective_two_mu: f64,
    shear: ExponentialLaw,
    rule: UnloadingRule,
    /// The cyclic shear damage `exp(-1.2 (Lambda / E)^1.1)` (5.104), tabulated.
    cyclic_damage: tabulated::DecayTable,
    /// Evaluate every law by `powf` and `exp` (see [`MicroplaneConcrete::with_exact_laws`]).
    exact: bool,
    /// Largest Frobenius norm of the strain deviator, and largest positive volumetric strain, for
    /// which every plane law is linear to `f32` precision (see [`MicroplaneConcrete::update`]).
    elastic_limit: f64,
    /// The planes' stress for a strain on the elastic path, `[11, 22, 33, 23, 13, 12]` with tensor
    /// shears: deviatoric and shear laws at their initial moduli, homogenised, with the
    /// deviatoric trace term.
    plane_stiffness: [[f64; 6]; 6],
    /// Whether the elastic path is used (off for [`MicroplaneConcrete::with_full_update`]).
    elastic_path: bool,
    /// Whether the processor has AVX2 and FMA, so the update runs its wide-register build.
    wide_vectors: bool,
    /// Whether the planes' dissipation is counted in the plane loop of every update, not only
    /// where the dilatancy reads it (see [`MicroplaneConcrete::with_dissipation_always_counted`]).
    always_count_dissipation: bool,
}

/// What one update gives besides the stress: enough for output and for checks.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UpdateInfo {
    /// Rate factor `F` used.
    pub rate_factor: f64,
    /// Deviatoric and shear relaxation `psi` used for planes in deviatoric compression.
    pub psi: f64,
}

impl MicroplaneConcrete {
    /// Validates `parameters` and precomputes the microplanes, the elastic split and the laws;
    /// the error names the parameter out of range and its admissible range.
    pub fn new(parameters: MicroplaneParameters) -> Result<Self, ParameterError> {
        parameters.validate()?;
        let (e, nu) = (parameters.youngs_modulus, parameters.poisson_ratio);
        let planes = directions::microplanes(parameters.rule);
        let mut model = Self {
            projections: Projections::new(&planes),
            side_by_side: SideBySide::new(&planes),
            planes,
            e_v0: e / (1.0 - 2.0 * nu),
            e_d0: e / (1.0 + nu),
            e_t0: e / (1.0 + nu),
            equivalent_factor: (1.0 - 2.0 * nu) / 3.0,
            effective_lambda: nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            effective_two_mu: 1.0 / (1.0 + nu),
            tension: ExponentialLaw::with_hordijk_tail(parameters.m, parameters.hordijk_tail),
            compression: ExponentialLaw::new(parameters.n),
            shear: ExponentialLaw::new(parameters.k),
            rule: UnloadingRule {
                alpha: parameters.alpha,
                beta: parameters.beta,
            },
            cyclic_damage: tabulated::DecayTable::new(1.2, 1.1),
            exact: false,
            elastic_limit: elastic_path::elastic_limit_of(&parameters),
            plane_stiffness: [[0.0; 6]; 6],
            // With crack friction too: an uncracked plane's slider takes its slip afresh from
            // the strain and the laws' stress in every full update (`crack_friction`), so the
            // slips the elastic path leaves untouched (zero, as the full update makes them at
            // linear laws) are never read.
            elastic_path: true,
            wide_vectors: wide_vectors(),
            always_count_dissipation: false,
            parameters,
        };
        model.plane_stiffness = model.plane_stiffness();
        Ok(model)
    }

    /// The same model evaluating `exp(-x^m)` of every law, and the cyclic damage, by `powf` and
    /// `exp` instead of the tables (absolute error below `1e-10`, `tabulated`): the reference that
    /// the tabulated update is verified against, too slow for runs.
    pub fn with_exact_laws(mut self) -> Self {
        for law in [&mut self.tension, &mut self.compression, &mut self.shear] {
            law.exact = true;
        }
        self.exact = true;
        self
    }

    /// The same model always running the portable build of the update, never its AVX2 build:
    /// the reference that the wide-register build is checked against bit for bit
    /// (`tests/microplane_wide_build.rs`).
    pub fn with_portable_code(mut self) -> Self {
        self.wide_vectors = false;
        self
    }

    /// The same model running the plane work one plane after the other for every rule, never
    /// with the planes side by side (`side_by_side.rs`): the reference that the side-by-side
    /// kernel is checked against bit for bit (`tests/microplane_side_by_side.rs`).
    pub fn with_planes_one_by_one(mut self) -> Self {
        self.side_by_side = None;
        self
    }

    /// Whether the plane work runs with the planes side by side (the 21-direction rule).
    pub fn runs_planes_side_by_side(&self) -> bool {
        self.side_by_side.is_some()
    }

    /// The same model counting the planes' dissipation in the plane loop of every update, as
    /// before the count was deferred to where the dilatancy reads it (`dissipation.rs`): the
    /// reference that the deferred count is checked against bit for bit
    /// (`tests/microplane_dissipation_count.rs`).
    pub fn with_dissipation_always_counted(mut self) -> Self {
        self.always_count_dissipation = true;
        self
    }

    /// Whether updates run the AVX2 and FMA build of [`MicroplaneConcrete::update`].
    pub fn runs_wide_vectors(&self) -> bool {
        self.wide_vectors
    }

    /// The microplanes of the model's direction rule, with their weights and projections.
    pub fn planes(&self) -> &[Microplane] {
        &self.planes
    }

    /// Number of `f32` values of history per element.
    pub fn state_len(&self) -> usize {
        let friction = if self.parameters.crack_friction.is_some() {
            state::FRICTION_PER_PLANE
        } else {
            0
        };
        let boundary = if self.parameters.tension_boundary.is_some() {
            state::BOUNDARY_HISTORY
        } else {
            0
        };
        state::HEADER + (state::PER_PLANE + friction) * self.planes.len() + boundary
    }

    /// A virgin state.
    pub fn initial_state(&self) -> MicroplaneState {
        MicroplaneState::new(self.state_len())
    }

    /// The rate factor `F(gamma_dot)` (1 with the rate effect off).
    #[inline(always)]
    pub fn rate_factor(&self, gamma_dot: f64) -> f64 {
        match self.parameters.rate_effect {
            Some(rate) => rate.factor(gamma_dot),
            None => 1.0,
        }
    }

    /// The update: back-rotated Cauchy stress `s` for the Green-Lagrange strain `strain` at the
    /// equivalent rate `gamma_dot`, advancing `state`. With
    /// [`MicroplaneParameters::volumetric_strain`] `volume_ratio` the laws see `dev E + e_V I`
    /// with `e_V = (J^(2/3) - 1) / 2` ([`volumetric`]).
    ///
    /// Steps: rate factor (5.110); volumetric law (5.22) with its own history; relaxation `psi`
    /// from the volumetric law and the largest principal stress of the previous update (5.91,
    /// 5.96-5.99); on every plane the deviatoric and shear strains (5.85, 5.86), their laws (5.23)
    /// with loading-unloading rules (5.100-5.104); homogenisation (5.36); `s_I` stored for the next
    /// update.
    ///
    /// The elastic path: while no update of the element has left it, and the strain deviator and
    /// the positive volumetric strain stay below [`MicroplaneConcrete::elastic_limit`], every
    /// plane is on its virgin branch where its law equals its initial modulus to `f32` precision
    /// (`exp(-x^m)` rounds to 1), and `psi` to 1. The planes' stress is then the linear map `D E`
    /// (36 products instead of 63 laws with their branches) and the plane histories stay zero;
    /// the volumetric law runs as always. A zero branch history and one at a turning point below
    /// the limit give the same stresses later, to the `f32` rounding of the history
    /// (`tests/microplane_elastic_path.rs`).
    pub fn update(
        &self,
        state: &mut [f32],
        strain: &Sym,
        gamma_dot: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        let measured;
        let strain = match self.parameters.volumetric_strain {
            VolumetricStrain::GreenLagrangeTrace => strain,
            other => {
                measured = other.measured(strain);
                &measured
            }
        };
        #[cfg(target_arch = "x86_64")]
        if self.wide_vectors {
            // SAFETY: the processor has AVX2 and FMA (detected when the model was built).
            return unsafe { self.update_avx2(state, strain, gamma_dot, band) };
        }
        self.update_portable(state, strain, gamma_dot, band)
    }

    /// [`MicroplaneConcrete::update`] compiled for AVX2 and FMA: the same operations in the same
    /// order on wider registers, so the same bits (Rust never fuses a product and a sum unless
    /// asked to, so FMA changes no rounding).
    ///
    /// # Safety
    /// The processor must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn update_avx2(
        &self,
        state: &mut [f32],
        strain: &Sym,
        gamma_dot: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        self.update_portable(state, strain, gamma_dot, band)
    }

    /// The update for any processor (see [`MicroplaneConcrete::update`]).
    #[inline(always)]
    fn update_portable(
        &self,
        state: &mut [f32],
        strain: &Sym,
        gamma_dot: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        debug_assert_eq!(state.len(), self.state_len());
        let f = self.rate_factor(gamma_dot);
        let (header, planes) = state.split_at_mut(state::HEADER);
        let Some(boundary) = &self.parameters.tension_boundary else {
            return self.update_laws(header, planes, strain, f, band);
        };
        // With the tensile boundary every law sees the strain less the planes' crack strains
        // (`crack_strain`), solved with the stress they give.
        self.update_with_boundary(boundary, header, planes, strain, f, band)
    }

    /// The laws of the volumetric stress and of the planes for the strain `strain` (less the
    /// crack strains with the tensile boundary).
    #[inline(always)]
    pub(super) fn update_laws(
        &self,
        header: &mut [f32],
        planes: &mut [f32],
        strain: &Sym,
        f: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        let e_v = (strain[0] + strain[1] + strain[2]) / 3.0;
        let s_v = self.volumetric_stress(header, strain, e_v, f, band);
        if self.elastic_path
            && header[state::VIRGIN_PLANES] == 1.0
            && self.on_elastic_path(strain, e_v, band.strength)
        {
            return self.elastic_update(header, strain, s_v, f);
        }
        header[state::VIRGIN_PLANES] = 0.0;
        self.plane_update(header, planes, strain, e_v, s_v, f, band)
    }

    /// The volumetric stress `s_V` (5.21, 5.22), advancing the volumetric history in `header`.
    #[inline(always)]
    fn volumetric_stress(
        &self,
        header: &mut [f32],
        strain: &Sym,
        e_v: f64,
        f: f64,
        band: &CrackBand,
    ) -> f64 {
        let p = &self.parameters;

        // Volumetric stress: tension softens (with the crack band), compression does not damage
        // and unloads with the larger of E_V0 and the tangent of the law where unloading starts
        // (Fig. 5.11a; Bažant et al. M4 2000, M7 2013: unloading in volumetric compression is
        // stiffer than the virgin secant). Once the law stiffens (x > b) the secant exceeds E_V0,
        // and a secant unloading line through the origin would run above the convex loading curve
        // and give back 1.5 times the work of loading; the tangent line lies under it.
        let e1 = f * band.strength * p.e1;
        // The volumetric law sees the strain less the dilatant part reached so far (the previous
        // update's: MICROPLANE "Dilatancy").
        let e_v_law = e_v - header[state::DILATANCY] as f64;
        if e_v_law >= 0.0 && p.tension_boundary.is_some() {
            // The planes' boundaries carry the tension (`tension_boundary`).
            self.e_v0 * e_v_law
        } else if e_v_law >= 0.0 && p.tension_driver == TensionDriver::Equivalent {
            // Scalar damage at the largest driver reached: s_V = E_V0 e_V s(k) / (E_V0 k), with
            // k = (1 - 2 nu) / 3 sqrt(sum <e_i>^2) (MICROPLANE "Tension driver").
            let stored = &mut header[state::V_TENSION..state::V_TENSION + 2];
            let (reached, stress_reached) = (stored[0] as f64, stored[1] as f64);
            // Mazars' strain is at most the strain's norm sqrt(E : E) (sum <e_i>^2 <= sum e_i^2):
            // below the driver reached, the eigenvalues (an `acos` and two `cos`) cannot change
            // `kappa`. The margin covers the rounding of both (a few ulp), so that the shortcut is taken
            // only where the computed driver, too, would lose to `reached`: bitwise the same.
            let bound = self.equivalent_factor * contract(strain, strain).sqrt() * (1.0 + 1e-9);
            let kappa = if bound <= reached {
                reached
            } else {
                (self.equivalent_factor * mazars_strain(strain)).max(reached)
            };
            let mut secant = if kappa > 0.0 {
                self.tension.stress(kappa, e1, 1.0, band.tension) / kappa
            } else {
                1.0
            };
            if reached > 0.0 {
                secant = secant.min(stress_reached / reached);
            }
            stored[0] = kappa as f32;
            stored[1] = (secant * kappa) as f32;
            self.e_v0 * e_v_law * secant
        } else if e_v_law >= 0.0 {
            let peak = self.tension.peak(e1, self.e_v0);
            let mut branch = Branch::load(&header[state::V_TENSION..state::V_TENSION + 2]);
            let s = branch.stress(e_v_law, self.e_v0, peak, &self.rule, |x| {
                self.tension.stress(x, e1, self.e_v0, band.tension)
            });
            branch.store(&mut header[state::V_TENSION..state::V_TENSION + 2]);
            s
        } else {
            let x = -e_v_law;
            let reached = header[state::V_COMPRESSION] as f64;
            if x >= reached {
                header[state::V_COMPRESSION] = x as f32;
            }
            -self.volumetric_pressure(x, reached)
        }
    }

    /// The pressure `-s_V >= 0` of the volumetric compression law at the compressive strain
    /// `x = -(e_V - e_dil) >= 0` with the largest `x` reached so far `reached`: the envelope
    /// (5.21) at or beyond it, the unloading line below it (see [`Self::volumetric_stress`]).
    /// It rises with `x` on both.
    #[inline(always)]
    fn volumetric_pressure(&self, x: f64, reached: f64) -> f64 {
        let p = &self.parameters;
        let envelope = |x: f64| -volumetric_compression(-x, self.e_v0, p.a, p.b, p.p, p.q);
        if x >= reached {
            envelope(x)
        } else {
            let s_reached = envelope(reached);
            let unloading = self.e_v0.max(volumetric_compression_tangent(
                reached, self.e_v0, p.a, p.b, p.p, p.q,
            ));
            (s_reached - unloading * (reached - x)).max(0.0)
        }
    }

    /// The planes (5.85, 5.86, 5.23, 5.100-5.104) and the homogenisation (5.36) around the
    /// volumetric stress `s_V`, advancing the plane histories.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn plane_update(
        &self,
        header: &mut [f32],
        planes: &mut [f32],
        strain: &Sym,
        e_v: f64,
        s_v: f64,
        f: f64,
        band: &CrackBand,
    ) -> (Sym, UpdateInfo) {
        let p = &self.parameters;
        let e1 = f * band.strength * p.e1;

        // Relaxation: psi follows the volumetric tension law at f(s_I) <e_V> (5.91), so that the
        // deviatoric secant stays proportional to the volumetric one (5.84). It is kept as damage,
        // the smallest value reached: a psi that rises again when the crack closes is not a
        // potential, and shear cycles across an opening crack then give energy back (in the beam
        // drop tests the cracked zone pumped about 700 J into the beam in 3 ms).
        // With the tensile boundary the planes crack one by one and psi stays 1.
        let boundary = p.tension_boundary.map(|b| {
            let count = self.planes.len();
            tension_boundary::ElementBoundary::new(
                &b,
                p,
                band,
                f,
                &planes[..state::PER_PLANE * count],
            )
        });
        let relaxation = if boundary.is_some() {
            1.0
        } else {
            let s_i = header[state::PRINCIPAL_STRESS] as f64;
            let driver = match p.relaxation_driver {
                RelaxationDriver::Volumetric => e_v,
                RelaxationDriver::TensileStress => {
                    self.tensile_stress_driver(strain, e_v, header[state::OPENING] as f64)
                }
            };
            discontinuity::relaxation(
                discontinuity::closure(s_i, p.s_i_min) * driver.max(0.0),
                e1,
                &self.tension,
                band.tension,
            )
            .min(header[state::RELAXATION] as f64)
        };
        header[state::RELAXATION] = relaxation as f32;
        let scales = self.plane_scales(e_v, s_v, f, band, relaxation);

        let count = self.planes.len();
        let (planes, sliders) = planes.split_at_mut(state::PER_PLANE * count);
        let mut virgin_steps = VirginSteps::new();
        let sums = match &self.side_by_side {
            Some(kernel) if boundary.is_none() && !scales.eager => self.planes_side_by_side(
                kernel,
                planes,
                sliders,
                strain,
                &scales,
                &mut virgin_steps,
            ),
            _ => {
                // The kinematic constraint (5.85, 5.86) for every plane at once, in one pass per
                // tensor over planes laid out side by side (it vectorises; the sums are those of
                // `contract`).
                let mut normal = [0.0; MAX_PLANES];
                let mut along_m = [0.0; MAX_PLANES];
                let mut along_k = [0.0; MAX_PLANES];
                self.projections.contract_all(
                    strain,
                    &mut normal[..count],
                    &mut along_m[..count],
                    &mut along_k[..count],
                );
                self.planes_one_by_one(
                    planes,
                    sliders,
                    [&normal[..count], &along_m[..count], &along_k[..count]],
                    &scales,
                    boundary.as_ref(),
                    &mut virgin_steps,
                )
            }
        };
        let PlaneSums {
            mut sigma,
            sum_d,
            inelastic_compression,
            dissipation,
        } = sums;
        let eager = scales.eager;
        let volumetric = if p.deviatoric_trace_term {
            s_v - sum_d / 3.0
        } else {
            s_v
        };
        for s in &mut sigma[..3] {
            *s += volumetric;
        }
        header[state::RATE_FACTOR] = f as f32;
        header[state::PRINCIPAL_STRESS] =
            principal_stress_for_closure(&sigma, self.parameters.s_i_min) as f32;
        self.advance_opening(header, &sigma);
        if scales.dilatant {
            let wanted = p.dilatancy * inelastic_compression;
            let reached = header[state::DILATANCY] as f64;
            if wanted > reached {
                header[state::DILATANCY] = self.admissible_dilatancy(
                    reached,
                    wanted,
                    e_v,
                    header[state::V_COMPRESSION] as f64,
                    || {
                        if eager {
                            return dissipation;
                        }
                        virgin_steps.dissipation(
                            |p| 6.0 * self.planes[p].weight,
                            |law| scales.modulus(self, law),
                            &self.rule,
                        )
                    },
                ) as f32;
            }
        }
        (
            sigma,
            UpdateInfo {
                rate_factor: f,
                psi: relaxation,
            },
        )
    }
}

/// Whether this processor runs AVX2 and FMA (the wide-register build of the update).
fn wide_vectors() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
