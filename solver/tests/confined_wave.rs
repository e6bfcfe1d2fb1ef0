//! Confined column hit at one end (CATALOGUE `elastic/confined-wave`): uniaxial strain, so the
//! front moves at `c_d = sqrt((lambda + 2 mu) / rho)` and carries the stress `rho c_d v0`
//! (one-dimensional wave theory; e.g. Kolsky 1963, ch. 1).

mod common;

use common::*;
use impact_references::analytic::{dilatational_wave_speed, plane_wave_stress};
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::model::{Constraint, Motion, Probe, ProbeQuantity, TimeFunction};

/// Time at which `signal` first reaches `level`, linearly interpolated between records.
fn crossing(time: &[f64], signal: &[f64], level: f64) -> f64 {
    for i in 1..signal.len() {
        if signal[i] >= level && signal[i - 1] < level {
            let s = (level - signal[i - 1]) / (signal[i] - signal[i - 1]);
            return time[i - 1] + s * (time[i] - time[i - 1]);
        }
    }
    panic!("signal never reached {level}");
}

#[test]
fn front_speed_and_stress_plateau_of_the_confined_column() {
    let concrete = IsotropicElastic {
        density: 2300.0,
        youngs_modulus: 30e9,
        poisson_ratio: 0.2,
    };
    let c_d = dilatational_wave_speed(&concrete);
    let (length, width, v0) = (1.0, 0.02, 0.5);
    let mut p = problem(
        box_body([length, width, width], [200, 2, 2], 0.0, 0),
        MaterialModel::LinearElastic(concrete),
    );
    let model = &p.model;
    let select = |f: &dyn Fn(&nalgebra::Vector3<f64>) -> bool| -> Vec<u32> {
        (0..model.node_count() as u32)
            .filter(|&n| f(&model.reference[n as usize]))
            .collect()
    };
    let lateral_y = select(&|x| x.y.abs() < 1e-12 || (x.y - width).abs() < 1e-12);
    let lateral_z = select(&|x| x.z.abs() < 1e-12 || (x.z - width).abs() < 1e-12);
    let end = select(&|x| x.x.abs() < 1e-12);
    let (x1, x2) = (0.25, 0.75);
    let probe_1 = select(&|x| (x.x - x1).abs() < 1e-9);
    let probe_2 = select(&|x| (x.x - x2).abs() < 1e-9);
    p.constraints.push(Constraint {
        name: "rollers_y".into(),
        nodes: lateral_y,
        motion: Motion::Fixed([false, true, false]),
    });
    p.constraints.push(Constraint {
        name: "rollers_z".into(),
        nodes: lateral_z,
        motion: Motion::Fixed([false, false, true]),
    });
    p.constraints.push(Constraint {
        name: "impact".into(),
        nodes: end,
        motion: Motion::Velocity([true, false, false], TimeFunction::Constant(v0)),
    });
    p.probes.push(Probe {
        name: "p1".into(),
        nodes: probe_1,
        quantity: ProbeQuantity::Velocity,
    });
    p.probes.push(Probe {
        name: "p2".into(),
        nodes: probe_2,
        quantity: ProbeQuantity::Velocity,
    });
    // Stop when the front is at 0.9 L, before any reflection.
    let end_time = 0.9 * length / c_d;
    let mut settings = ExplicitSettings::new(end_time);
    settings.history_interval = Some(0.0);
    let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
    let summary = solver.run(&mut |_| {}).unwrap();
    let h = &summary.history;
    let (t, v1, v2) = (
        h.column("time").unwrap(),
        h.column("p1_x").unwrap(),
        h.column("p2_x").unwrap(),
    );
    let speed = (x2 - x1) / (crossing(&t, &v2, 0.5 * v0) - crossing(&t, &v1, 0.5 * v0));
    let speed_error = (speed - c_d).abs() / c_d;
    eprintln!(
        "confined wave: front speed {speed:.2} m/s, c_d {c_d:.2} m/s, error {speed_error:.3e}"
    );
    assert!(
        speed_error < 0.01,
        "front speed {speed:.1} m/s against c_d = {c_d:.1} m/s ({speed_error:.2e})"
    );
    // Stress plateau behind the front, between 0.1 L and 0.6 L.
    let fields = p.model.element_fields(&solver.whole(&solver.u));
    let mut sum = 0.0;
    let mut count = 0;
    for (e, tet) in p.model.tets.iter().enumerate() {
        let centroid = tet
            .iter()
            .map(|&n| p.model.reference[n as usize].x)
            .sum::<f64>()
            / 4.0;
        if (0.1 * length..0.6 * length).contains(&centroid) {
            sum += fields.cauchy[e][0];
            count += 1;
        }
    }
    let plateau = -sum / count as f64;
    // The compressive stress behind the front, as a positive number.
    let expected = -plane_wave_stress(&concrete, v0);
    let plateau_error = (plateau - expected).abs() / expected;
    eprintln!("confined wave: plateau {plateau:.5e} Pa, rho c v0 {expected:.5e} Pa, error {plateau_error:.3e}");
    assert!(
        plateau_error < 0.02,
        "plateau {plateau:.4e} Pa against rho c v0 = {expected:.4e} Pa ({plateau_error:.2e})"
    );
    // The energy put in by the moving end equals kinetic plus stored energy.
    // The energy put in by the moving end is kinetic plus stored energy. The impulsive start
    // leaves a one-off bookkeeping offset of about one node layer's kinetic energy (full-step
    // velocities average across the jump); it must not grow, so it is a small share at the end.
    let rel = h.column("energy_error_relative").unwrap();
    let final_error = rel[rel.len() - 1].abs();
    assert!(
        final_error < 1e-3,
        "energy balance error {final_error:.2e} at the end"
    );
    let abs = h.column("energy_error").unwrap();
    let (early, late) = (abs[1].abs(), abs[abs.len() - 1].abs());
    assert!(
        late < 1.5 * early,
        "the balance error grew from {early:.3e} J to {late:.3e} J"
    );
}
