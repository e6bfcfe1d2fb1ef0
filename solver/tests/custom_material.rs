//! A constitutive model added from outside the solver with one trait implementation: compressible
//! Neo-Hookean hyperelasticity (Bonet & Wood 2008, (6.27)-(6.28)). It runs in the static solver
//! (which differences its forces, since it gives no closed-form tangent) and in an explicit run,
//! where it must keep the energy of a vibrating cantilever and, at small strain, move as the
//! Saint-Venant-Kirchhoff beam does (both reduce to Hooke's law with the same Lamé constants).

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::{
    Deformation, ElementState, IsotropicElastic, Material, SaintVenantKirchhoff,
};
use impact_solver::model::{BodyMaterial, Probe, ProbeQuantity};
use impact_solver::problem::Problem;
use impact_solver::statics::{solve_static, StaticSettings};
use nalgebra::Matrix3;

/// `W = mu/2 (I_C - 3) - mu ln J + lambda/2 (ln J)^2`,
/// `P = mu (F - F^-T) + lambda ln(J) F^-T`, written in `H = F - I` so that small strains keep
/// their digits: `F - F^-T = (H + H^T + H H^T) F^-T` and `J - 1 = tr H + I_2(H) + det H`.
#[derive(Debug)]
struct NeoHookean {
    c: IsotropicElastic,
}

/// `ln J` from `J - 1 = tr H + (tr(H)^2 - tr(H^2)) / 2 + det H`.
fn ln_j(h: &Matrix3<f64>) -> f64 {
    let tr = h.trace();
    (tr + 0.5 * (tr * tr - (h * h).trace()) + h.determinant()).ln_1p()
}

impl Material for NeoHookean {
    fn name(&self) -> &'static str {
        "neo_hookean"
    }

    fn constants(&self) -> IsotropicElastic {
        self.c
    }

    fn update(
        &self,
        _element: usize,
        d: &Deformation,
        _state: ElementState,
    ) -> Option<Matrix3<f64>> {
        if !(d.det > 0.0) {
            return None;
        }
        let f_inv_t = d.f.try_inverse()?.transpose();
        let h = &d.h;
        let b_minus_i = h + h.transpose() + h * h.transpose();
        Some((self.c.mu() * b_minus_i + self.c.lambda() * ln_j(h) * Matrix3::identity()) * f_inv_t)
    }

    /// With `I_C - 3 = 2 tr H + tr(H^T H)` so that small strains keep their digits.
    fn strain_energy_density(&self, h: &Matrix3<f64>) -> Option<f64> {
        let ic_minus_3 = 2.0 * h.trace() + (h.transpose() * h).trace();
        let ln_j = ln_j(h);
        Some(
            0.5 * self.c.mu() * ic_minus_3 - self.c.mu() * ln_j
                + 0.5 * self.c.lambda() * ln_j * ln_j,
        )
    }
}

const LENGTH: f64 = 1.0;
const DEPTH: f64 = 0.1;
/// Tip load per node: a tip deflection of about 2 mm on this coarse mesh, bending strains of a
/// few 1e-4.
const TIP_LOAD: f64 = -2e3;

/// A steel cantilever clamped at `x = 0` with a tip load and a tip probe, of the given material.
fn cantilever(material: Arc<dyn BodyMaterial>) -> Problem {
    let (mut p, tip) = tip_loaded_cantilever(material, LENGTH, DEPTH, TIP_LOAD);
    p.probes.push(Probe {
        name: "tip".into(),
        nodes: tip,
        quantity: ProbeQuantity::Displacement,
    });
    p
}

/// Bends the cantilever statically, releases it and runs two bending periods: the tip's vertical
/// displacement over time, the stored energy at release, and the history.
fn release(
    material: Arc<dyn BodyMaterial>,
) -> (Vec<f64>, f64, impact_solver::output::HistoryTable) {
    let mut p = cantilever(material);
    let bent = solve_static(&p, &StaticSettings::default()).unwrap();
    let stored = p.model.stored_energy(&bent.u);
    p.loads.clear();
    let freq = 1.875f64.powi(2) / (2.0 * std::f64::consts::PI)
        * (STEEL.youngs_modulus * DEPTH * DEPTH / 12.0 / STEEL.density / LENGTH.powi(4)).sqrt();
    let end = 2.0 / freq;
    let mut settings = ExplicitSettings::new(end);
    settings.history_interval = Some(end / 400.0);
    let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
    solver.set_initial_displacement(&bent.u);
    let summary = solver.run(&mut |_| {}).unwrap();
    let tip = summary.history.column("tip_z").unwrap();
    (tip, stored, summary.history)
}

#[test]
fn a_neo_hookean_body_defined_in_a_test_runs_statically_and_explicitly() {
    let neo: Arc<dyn BodyMaterial> = Arc::new(NeoHookean { c: STEEL });
    let svk: Arc<dyn BodyMaterial> = Arc::new(SaintVenantKirchhoff::new(STEEL));
    let (tip, stored, history) = release(neo);
    let (tip_svk, stored_svk, _) = release(svk);

    // Statics: the same bent state as Saint-Venant-Kirchhoff to first order in the strain (the
    // two differ at second order: strains of 6e-4 here).
    assert!(
        (tip[0] - tip_svk[0]).abs() < 2e-3 * tip_svk[0].abs(),
        "static tip {:.6e} m against Saint-Venant-Kirchhoff {:.6e} m",
        tip[0],
        tip_svk[0]
    );
    assert!((stored - stored_svk).abs() < 2e-3 * stored_svk);

    // Dynamics: the beam swings through zero, keeps its energy, and moves as the SVK beam does.
    let lowest = tip.iter().cloned().fold(f64::INFINITY, f64::min);
    let highest = tip.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert!(highest > 0.5 * tip[0].abs() && lowest < 0.9 * tip[0]);
    let drift = kinetic_plus_stored_drift(&history, stored);
    assert!(
        drift < 1e-3,
        "K + W drifted by {drift:.2e} of the stored energy"
    );
    let apart = tip
        .iter()
        .zip(&tip_svk)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        apart < 1e-3 * tip[0].abs(),
        "tip histories differ by {apart:.3e} m (amplitude {:.3e} m)",
        tip[0].abs()
    );
}
