//! Free vibration of an elastic cantilever (CATALOGUE `energy/free-vibration`): released from a
//! statically bent state with no damping, it must keep its energy for 10 periods.

mod common;

use common::*;
use impact_references::analytic::cantilever_first_frequency;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::MaterialModel;
use impact_solver::statics::{solve_static, StaticSettings};

#[test]
fn cantilever_keeps_its_energy_for_ten_periods() {
    let (l, h) = (1.0, 0.1);
    for material in [
        MaterialModel::SaintVenantKirchhoff(STEEL),
        MaterialModel::LinearElastic(STEEL),
    ] {
        let (mut p, _) = tip_loaded_cantilever(material, l, h, -2e4);
        let bent = solve_static(&p, &StaticSettings::default()).unwrap();
        let stored = p.model.stored_energy(&bent.u);
        p.loads.clear();
        // First bending frequency of the cantilever (Euler-Bernoulli), to run ten periods.
        let freq = cantilever_first_frequency(&STEEL, l, h);
        let end = 10.0 / freq;
        let mut settings = ExplicitSettings::new(end);
        settings.history_interval = Some(end / 2000.0);
        let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
        solver.set_initial_displacement(&bent.u);
        let summary = solver.run(&mut |_| {}).unwrap();
        let hist = &summary.history;
        let kinetic = hist.column("kinetic").unwrap();
        let errors = hist.column("energy_error").unwrap();
        // Energy really moves between strain and motion (the beam vibrates).
        let k_max = kinetic.iter().cloned().fold(0.0, f64::max);
        assert!(
            k_max > 0.5 * stored,
            "{}: peak kinetic {k_max:e} J against stored {stored:e} J",
            material.name()
        );
        let worst = errors.iter().map(|e| e.abs()).fold(0.0, f64::max) / stored;
        assert!(
            worst < 1e-3,
            "{}: energy balance error {worst:.2e} of the initial stored energy",
            material.name()
        );
        // Independent of the solver's bookkeeping: kinetic + stored energy stays the initial stored energy.
        let total_drift = kinetic_plus_stored_drift(hist, stored);
        assert!(
            total_drift < 1e-3,
            "{}: K + W drifted by {total_drift:.2e}",
            material.name()
        );
    }
}
