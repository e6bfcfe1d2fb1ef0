//! Remeshing inside an explicit run (issue 21, thesis 9.2): the run pauses, a region is remeshed
//! (`remesh_problem`), the fields are transferred, and the run goes on with a resumed solver.
//! Expected values come from the physics: a rigid motion and a uniform deformation are states
//! every transfer keeps exactly (T1 and T3 reproduce constant and linear fields), and a wave's
//! energy changes by no more than the interpolation error of the fields in the region.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings, RunState};
use impact_solver::material::{LinearElastic, Material, MaterialModel};
use impact_solver::mesh::ops::{centroids, grow_region, MesherOptions};
use impact_solver::model::{Constraint, Motion, TimeFunction};
use impact_solver::problem::Problem;
use impact_solver::remesh::{remesh_problem, Remeshed};
use nalgebra::{Matrix3, Vector3};

/// Runs `steps` steps from `state` (or from the start) with a fixed time step `dt`.
fn run(problem: &Problem, dt: f64, state: Option<RunState>, steps: usize) -> RunState {
    let mut settings = ExplicitSettings::new(1.0);
    settings.time_step = Some(dt);
    run_steps(problem, settings, state, steps)
}

/// The elements whose centroid lies within `radius` of `center`, grown by one layer.
fn region_near(problem: &Problem, center: Vector3<f64>, radius: f64) -> Vec<usize> {
    let m = &problem.model;
    let seed: Vec<usize> = centroids(&m.reference, &m.tets)
        .iter()
        .enumerate()
        .filter(|(_, c)| (*c - center).norm() < radius)
        .map(|(e, _)| e)
        .collect();
    assert!(!seed.is_empty());
    grow_region(&m.tets, &seed, 1)
}

fn remesh(problem: &Problem, state: &RunState, region: &[usize]) -> Remeshed {
    let r = remesh_problem(problem, state, region, &MesherOptions::default(), 0.0).unwrap();
    assert!(
        r.problem.model.element_count() > problem.model.element_count(),
        "the region was refined"
    );
    r
}

/// The largest internal force on the nodes `free` (N).
fn largest_force(problem: &Problem, u: &[Vector3<f64>], free: impl Fn(usize) -> bool) -> f64 {
    let mut f = vec![Vector3::zeros(); u.len()];
    problem.model.internal_forces(u, &mut f).unwrap();
    (0..u.len())
        .filter(|&n| free(n))
        .map(|n| f[n].norm())
        .fold(0.0, f64::max)
}

/// A box of Saint-Venant-Kirchhoff steel moving rigidly at `v0`, after 20 steps, and the
/// region around its centre to remesh: `(problem, v0, state, region)`.
fn rigidly_moving_box() -> (Problem, Vector3<f64>, RunState, Vec<usize>) {
    let mut p = problem(
        box_body([1.0; 3], [4, 4, 4], 0.2, 7),
        MaterialModel::SaintVenantKirchhoff(STEEL),
    );
    let v0 = Vector3::new(3.0, -2.0, 1.5);
    p.initial_velocity = vec![v0; p.model.node_count()].into();
    let dt = 0.5 * p.model.critical_time_step().0;
    let state = run(&p, dt, None, 20);
    let region = region_near(&p, Vector3::repeat(0.5), 0.2);
    (p, v0, state, region)
}

/// (a) A box of Saint-Venant-Kirchhoff steel moving rigidly, remeshed mid-run over a region
/// around its centre: velocities stay uniform, momentum and kinetic energy are kept to 1e-12,
/// no stress appears, and the run goes on with the rigid motion.
#[test]
fn rigidly_moving_box_is_unchanged_by_a_remeshing() {
    let (p, v0, state, region) = rigidly_moving_box();
    let r = remesh(&p, &state, &region);
    let rec = r.record;
    let p_old = rec.before.momentum.norm();
    assert!((rec.momentum_jump().norm() / p_old) < 1e-12, "{rec:?}");
    let dk = rec.kinetic_jump().abs() / rec.before.kinetic;
    assert!(dk < 1e-12, "kinetic energy jump {dk:e}");
    assert!(((rec.after.mass - rec.before.mass) / rec.before.mass).abs() < 1e-12);
    for v in r.state.v_full.iter().chain(&r.state.v_half) {
        assert!((v - v0).norm() / v0.norm() < 1e-12, "{v} against {v0}");
    }
    // No stress: the forces are round-off of a strain of order 1e-16 (E h^2 1e-16 ~ 1 N).
    let scale = STEEL.youngs_modulus * 0.25 * 0.25;
    let f = largest_force(&r.problem, &r.state.u, |_| true);
    assert!(f < 1e-12 * scale, "force {f:e} N on a rigidly moving body");
    // The run goes on: 50 steps, still uniform.
    let after = run(
        &r.problem,
        0.5 * r.problem.model.critical_time_step().0,
        Some(r.state),
        50,
    );
    for v in &after.v_full {
        assert!((v - v0).norm() / v0.norm() < 1e-12, "{v} after 50 steps");
    }
    assert!(after.energies.relative_error().abs() < 1e-12);
}

/// (b) A linear-elastic box held at a uniform stretch by its whole boundary (an affine
/// displacement), remeshed mid-run: T1 of a uniform `F` is exact, so every element, new or
/// kept, has `F = I + G` to round-off, the interior stays in equilibrium, and the new boundary
/// nodes join the constraint (else they would drift and the stress would not stay uniform).
#[test]
fn uniformly_stretched_box_keeps_its_stress_through_a_remeshing() {
    let size = [1.0; 3];
    let mut p = problem(
        box_body(size, [4, 4, 4], 0.2, 3),
        MaterialModel::LinearElastic(STEEL),
    );
    let g = Matrix3::new(1e-3, 2e-4, 0.0, 2e-4, -3e-4, 1e-4, 0.0, 1e-4, 5e-4);
    let boundary = box_boundary_nodes(&p.model, size);
    p.constraints.push(Constraint {
        name: "boundary".into(),
        nodes: boundary.clone(),
        motion: Motion::AffineDisplacement {
            translation: Vector3::zeros(),
            gradient: g,
            center: Vector3::zeros(),
            scale: TimeFunction::Constant(1.0),
        },
    });
    let u0: Vec<Vector3<f64>> = p.model.reference.iter().map(|x| g * x).collect();
    let dt = 0.5 * p.model.critical_time_step().0;
    let mut settings = ExplicitSettings::new(1.0);
    settings.time_step = Some(dt);
    let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
    solver.set_initial_displacement(&u0);
    for _ in 0..10 {
        solver.step().unwrap();
    }
    let state = solver.state();
    // A region that reaches the boundary, so that new nodes are inserted on constrained faces.
    let region = region_near(&p, Vector3::new(0.5, 0.5, 0.1), 0.2);
    let r = remesh(&p, &state, &region);
    let m = &r.problem.model;
    let f_exact = Matrix3::identity() + g;
    for e in 0..m.element_count() {
        let f = m.deformation_gradient(e, &r.state.u);
        assert!(
            (f - f_exact).amax() < 1e-12,
            "element {e}: F - (I + G) = {:e}",
            (f - f_exact).amax()
        );
    }
    let constrained = &r.problem.constraints[0].nodes;
    let on_box = |x: Vector3<f64>, d: Vector3<f64>| {
        let x0 = x - d;
        (0..3).any(|a| x0[a].abs() < 1e-9 || (x0[a] - size[a]).abs() < 1e-9)
    };
    let carried = &m.carried.as_ref().unwrap().displacement;
    let new_on_boundary = (0..m.node_count())
        .filter(|&n| on_box(m.reference[n], carried[n]))
        .count();
    assert!(new_on_boundary > boundary.len(), "new boundary nodes");
    assert_eq!(
        constrained.len(),
        new_on_boundary,
        "every boundary node held"
    );
    // Equilibrium of the free nodes: forces are round-off of the stress E |G| ~ 2e8 Pa times an
    // element face (h^2 / 2 ~ 0.03 m^2): 1e-10 of that.
    let held: std::collections::BTreeSet<u32> = constrained.iter().copied().collect();
    let scale = STEEL.youngs_modulus * g.amax() * 0.03;
    let f = largest_force(&r.problem, &r.state.u, |n| !held.contains(&(n as u32)));
    assert!(
        f < 1e-10 * scale,
        "free-node force {f:e} N, scale {scale:e} N"
    );
    let after = run(
        &r.problem,
        0.5 * r.problem.model.critical_time_step().0,
        Some(r.state),
        50,
    );
    for e in 0..m.element_count() {
        let f = m.deformation_gradient(e, &after.u);
        assert!(
            (f - f_exact).amax() < 1e-12,
            "element {e} after 50 steps: {:e}",
            (f - f_exact).amax()
        );
    }
}

/// The energy of a run at its last full step `t_n - dt`: the kinetic energy of `v_{n-1}` and
/// the stored energy at `u_n - du`, one instant (the state's `u` is one step ahead of its
/// full-step velocity).
fn synchronous_energy(model: &impact_solver::model::Model, s: &RunState) -> f64 {
    let back: Vec<Vector3<f64>> = s.u.iter().zip(&s.du_prev).map(|(u, d)| u - d).collect();
    s.energies.kinetic + model.stored_energy(&back)
}

/// A steel bar carrying a half-sine velocity pulse of half length 0.4 m, run until the pulse's
/// right-going half lies near x = 0.3..0.5 m, with the time step `dt` it ran with.
fn bar_with_pulse() -> (Problem, f64, RunState) {
    let mut p = problem(
        box_body([1.0, 0.1, 0.1], [40, 4, 4], 0.0, 1),
        MaterialModel::LinearElastic(STEEL),
    );
    let pulse = |x: f64| {
        if x < 0.4 {
            (std::f64::consts::PI * x / 0.4).sin().powi(2)
        } else {
            0.0
        }
    };
    p.initial_velocity = p
        .model
        .reference
        .iter()
        .map(|x| Vector3::new(pulse(x.x), 0.0, 0.0))
        .collect();
    let dt = 0.5 * p.model.critical_time_step().0;
    let c = 5.0e3; // about the bar wave speed sqrt(E / rho) = 5.06e3 m/s
    let steps = (0.1 / c / dt).round() as usize;
    let state = run(&p, dt, None, steps);
    (p, dt, state)
}

/// A run taken out and resumed with the same time step goes on bit for bit as if it had not
/// stopped. Resumed with a quarter of it (as after a remeshing that refined the smallest
/// element), its first step spans the mean of the two steps (central differences with a
/// variable step), and its energy stays within the band that the run keeping its step spans
/// by its own leapfrog oscillation over the same 400 steps (4.5e-4 of the energy here). With a
/// first step spanning the new `dt` instead of the mean, the energy jumps by 7.5e-3 of itself
/// and stays there.
#[test]
fn a_resumed_run_goes_on_with_its_energy_after_a_change_of_time_step() {
    let (p, dt, state) = bar_with_pulse();
    let straight = run(&p, dt, Some(state.clone()), 0);
    let continuous = run(&p, dt, None, state.step + 40);
    let resumed = run(&p, dt, Some(straight), 40);
    assert_eq!(continuous.u, resumed.u, "same step: bitwise the same run");
    assert_eq!(continuous.v_half, resumed.v_half);
    assert_eq!(continuous.energies, resumed.energies);

    // Energy at one instant on both runs, every 50 steps of the coarse one: the quarter step
    // keeps within the band the coarse run's own leapfrog oscillation spans.
    let e0 = synchronous_energy(&p.model, &state);
    let (mut band, mut off) = (0.0_f64, 0.0_f64);
    for k in (50..=400).step_by(50) {
        let coarse = run(&p, dt, Some(state.clone()), k);
        let fine = run(&p, 0.25 * dt, Some(state.clone()), 4 * k);
        assert!((fine.time - coarse.time).abs() < 1e-12);
        band = band.max((synchronous_energy(&p.model, &coarse) - e0).abs());
        off = off.max((synchronous_energy(&p.model, &fine) - e0).abs());
        let moved = fine.energies.balance_error() - state.energies.balance_error();
        assert!(
            moved.abs() < 1e-4 * e0,
            "the ledger's balance moved {moved} J"
        );
    }
    println!("energy departs by {band:.3e} J with the step kept, {off:.3e} J with dt/4");
    assert!(off <= band, "{off} J against the coarse run's {band} J");
}

/// (c) The bar of [`bar_with_pulse`], remeshed where the pulse is. Energies are compared at one
/// instant ([`synchronous_energy`], as the record measures them):
///
/// * the remeshing's jump in kinetic energy is round-off (the region's nodes are given back what
///   the interpolation changed, `remesh::kinetic_energy`), and in total (kinetic plus stored)
///   energy below a tenth of the energy the region held (T3 and T1 replace the region's fields by their interpolations, whose
///   energy differs by the relative interpolation error `(k h)^2 / 2`, `k h = pi h / l ~ 0.2`
///   for cells `h = 0.025` m and the pulse's half length `l = 0.4` m: about 2 %; a tenth leaves
///   a factor 5);
/// * the record's energy before is the run's energy at that instant (1e-9);
/// * 100 steps later the energy is the record's energy after to within the drift of the run
///   that did not remesh over the same time, plus 1e-4 of the energy; and the ledger's balance,
///   which books the jump as remeshing work, has not moved by more than that either (the new
///   elements take their parents' `F`, whose jumps leave forces at the new nodes: the
///   trapezoidal work of the ledger then departs from the stored energy by 2.1e-3 J here, of
///   the order of the kept mesh's own leapfrog oscillation, 3.3e-3 J).
#[test]
fn travelling_wave_keeps_its_energy_through_a_remeshing() {
    let (p, dt, state) = bar_with_pulse();
    let region = region_near(&p, Vector3::new(0.45, 0.05, 0.05), 0.07);
    let r = remesh(&p, &state, &region);
    let rec = r.record;
    // Energy in the region before: kinetic of its nodes (quarter masses) and stored in it.
    let m = &p.model;
    let w = LinearElastic::new(STEEL);
    let mut region_energy = 0.0;
    for &e in &region {
        let f = m.deformation_gradient(e, &state.u);
        let h = f - Matrix3::identity();
        region_energy += m.volume(e) * w.strain_energy_density(&h).unwrap();
        for n in m.tets[e] {
            let n = n as usize;
            let mass = STEEL.density * m.volume(e) / 4.0;
            region_energy += 0.5 * mass * state.v_full[n].norm_squared();
        }
    }
    let e_before = synchronous_energy(m, &state);
    assert!(
        region_energy > 0.05 * e_before,
        "the pulse is in the region"
    );
    let jump = rec.total_energy_jump();
    println!(
        "energy before {e_before:.9e} J (record {:.9e} J), region {region_energy:.6e} J, jump \
         {jump:.3e} J ({:.3e} of the region's)",
        rec.before.total_energy(),
        jump / region_energy
    );
    assert!(((rec.before.total_energy() - e_before) / e_before).abs() < 1e-9);
    assert!(jump.abs() < 0.1 * region_energy, "{}", rec.summary());
    // What T3's averaging changed in the kinetic energy is given back to (or taken from) the
    // region's nodes, their momentum kept: the kinetic jump is round-off.
    println!(
        "kinetic energy given back {:.3e} J (fluctuations times {:.4}); kinetic jump {:.3e} J",
        rec.kinetic_restored,
        rec.fluctuation_scale,
        rec.kinetic_jump()
    );
    assert!(rec.kinetic_restored.abs() > 1e-6 * region_energy);
    assert!(
        rec.kinetic_jump().abs() < 1e-12 * e_before,
        "{}",
        rec.summary()
    );

    let p2 = r.problem;
    let after = run(
        &p2,
        0.5 * p2.model.critical_time_step().0,
        Some(r.state),
        100,
    );
    let e_after = rec.after.total_energy();
    let e_later = synchronous_energy(&p2.model, &after);
    // The run that kept its mesh, over the same span of time.
    let span = after.time - state.time;
    let kept = run(&p, dt, Some(state.clone()), (span / dt).round() as usize);
    let drift_kept = (synchronous_energy(m, &kept) - e_before).abs();
    let balance_moved = after.energies.balance_error() - state.energies.balance_error();
    println!(
        "after the remeshing {e_after:.9e} J, {span:.3e} s later {e_later:.9e} J; the kept \
         mesh drifts {drift_kept:.3e} J; the balance moved {balance_moved:.3e} J"
    );
    assert!((e_later - e_after).abs() < drift_kept + 1e-4 * e_before);
    assert!(balance_moved.abs() < drift_kept + 1e-4 * e_before);
}

/// A soft block on a perturbed mesh sheared by its boundary (`v_x = gamma_dot y` on every
/// boundary node) to a shear of 1, through [`run_remeshing`] with a collapse limit 1.3 times
/// the initial worst: the worst elements pass the limit, the run remeshes them and goes on,
/// and again when they have distorted a quarter further (the policy's regrowth), several
/// times. The deformation stays close to affine (the shear is slow against the wave transit),
/// which the transfers keep: the jumps stay below 1e-2 of the stored energy; the run reaches
/// its end time with the energy balance (the jumps booked as remeshing work) within 1e-3 and
/// time increasing through the history, and the top face's displacement probe (carried across
/// the remeshings) follows the prescribed shear to 1e-9.
#[test]
fn a_sheared_block_remeshes_as_it_distorts_and_keeps_its_balance() {
    use impact_solver::dynamics::{ExplicitSettings, OutputSettings};
    use impact_solver::material::IsotropicElastic;
    use impact_solver::mesh::ops::check_distortion;
    use impact_solver::remesh::{run_remeshing, RemeshPolicy};
    const SOFT: IsotropicElastic = IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1.0e7,
        poisson_ratio: 0.3,
    };
    let size = [0.1; 3];
    let mut p = problem(
        box_body(size, [4, 4, 4], 0.3, 11),
        MaterialModel::SaintVenantKirchhoff(SOFT),
    );
    let end = 0.02;
    let rate = 1.0 / end;
    shear_the_box(&mut p, size, rate);
    let initial = check_distortion(&p.model.reference, &p.model.tets, f64::INFINITY).worst_ratio;
    let mut settings = ExplicitSettings::new(end);
    settings.safety = 0.5;
    settings.history_interval = Some(end / 200.0);
    let mut policy = RemeshPolicy::new(0);
    policy.collapse_limit = 1.3 * initial;
    policy.check_every = 5;
    let run = run_remeshing(
        &p,
        &settings,
        &OutputSettings::default(),
        &policy,
        &mut [],
        &mut |r| println!("{}", r.summary()),
    )
    .unwrap();
    let s = &run.summary;
    let stored = s.history.column("stored_energy").unwrap();
    let stored_end = *stored.last().unwrap();
    let jumps: f64 = run
        .records
        .iter()
        .map(|r| r.total_energy_jump().abs())
        .sum();
    println!(
        "{} remeshings, {} steps, largest balance error {:.3e}, jumps {jumps:.3e} J of \
         {stored_end:.3e} J stored, final elements {} (initial worst collapse ratio {initial:.3})",
        run.records.len(),
        s.steps,
        s.max_relative_energy_error,
        run.problem.as_ref().map_or(0, |p| p.model.element_count())
    );
    assert!(run.records.len() >= 2, "more than one remeshing");
    for r in &run.records {
        assert!(
            (r.after.mass - r.before.mass).abs() < 1e-12 * r.before.mass,
            "mass kept"
        );
    }
    assert!((s.time - end).abs() <= s.time_step);
    assert!(jumps < 1e-2 * stored_end);
    assert!(s.max_relative_energy_error < 1e-3);
    let t = s.history.column("time").unwrap();
    assert!(t.windows(2).all(|w| w[1] > w[0]), "time increases");
    let x = s.history.column("top_x").unwrap();
    for (t, x) in t.iter().zip(&x) {
        let exact = rate * t * 0.1;
        assert!(
            (x - exact).abs() < 1e-9 * 0.1,
            "top face at {x} m at t = {t} s, not {exact}"
        );
    }
}

/// The stable limit of the current configuration is that of a model built over it: a box
/// compressed to half its height along y and sheared has the critical step of the same mesh
/// with its nodes at the deformed positions, bit for bit, and it is below the reference one.
#[test]
fn the_current_critical_step_is_that_of_the_deformed_mesh() {
    use impact_solver::model::Model;
    let mesh = box_body([1.0, 0.5, 0.5], [4, 2, 2], 0.2, 9);
    let p = problem(mesh.clone(), MaterialModel::LinearElastic(STEEL));
    let g = Matrix3::new(0.0, 0.3, 0.0, 0.0, -0.5, 0.0, 0.0, 0.0, 0.0);
    let u: Vec<Vector3<f64>> = p.model.reference.iter().map(|x| g * x).collect();
    let mut deformed = mesh;
    deformed.nodes.iter_mut().zip(&u).for_each(|(x, u)| *x += u);
    let built = Model::new(vec![(
        "body".to_string(),
        deformed,
        MaterialModel::LinearElastic(STEEL),
    )])
    .unwrap();
    let current = p.model.current_critical_time_step(&u);
    assert_eq!(current, built.critical_time_step());
    assert!(current.0 < 0.6 * p.model.critical_time_step().0);
}

/// Selective mass scaling at a remeshing (`RemeshSettings::mass_scaling_step`): the new mesh's
/// elements whose stable step falls below the floor get the mass that brings it to the floor,
/// and only they; the body's momentum is kept, so a rigid motion slows by `M_old / M_new` and
/// loses the kinetic energy of a perfectly inelastic accretion, which the record books; the
/// motion stays rigid after (the added mass carries no force).
#[test]
fn mass_scaling_lifts_the_stable_step_to_its_floor_and_keeps_the_momentum() {
    let (p, v0, state, region) = rigidly_moving_box();
    let plain = remesh(&p, &state, &region);
    let refined_step = plain.problem.model.critical_time_step().0;
    // A floor above the refined mesh's limit, below the old mesh's: the children are scaled.
    let floor = 1.5 * refined_step;
    assert!(floor < p.model.critical_time_step().0);
    let r = remesh_problem(&p, &state, &region, &MesherOptions::default(), floor).unwrap();
    let m = &r.problem.model;
    let rec = r.record;
    // The same mesh, more mass, exactly what the record says was added.
    assert_eq!(m.tets, plain.problem.model.tets);
    assert!(rec.added_mass > 0.0);
    let physical: f64 = plain.problem.model.mass.iter().sum();
    let total: f64 = m.mass.iter().sum();
    assert!(((total - physical) - rec.added_mass).abs() < 1e-12 * physical);
    assert!(((rec.after.mass - rec.before.mass) - rec.added_mass).abs() < 1e-12 * physical);
    // Every element now steps at the floor or above; the scaled ones exactly at it.
    let (limit, _) = m.critical_time_step();
    assert!(
        (limit / floor - 1.0).abs() < 1e-12,
        "{limit:e} against {floor:e}"
    );
    let scale = m.mass_scale.as_ref().unwrap();
    let c = STEEL.dilatational_wave_speed();
    for (e, s) in scale.iter().enumerate() {
        let own = m.min_altitude(e) / c;
        if *s > 1.0 {
            assert!(own < floor);
            assert!((m.min_altitude(e) * s.sqrt() / c / floor - 1.0).abs() < 1e-12);
        } else {
            assert!(own >= floor, "element {e} left below the floor");
        }
    }
    // Nodes of unscaled elements only keep their masses bitwise.
    let mut touched = vec![false; m.node_count()];
    for (tet, s) in m.tets.iter().zip(scale) {
        if *s > 1.0 {
            tet.iter().for_each(|&n| touched[n as usize] = true);
        }
    }
    let untouched = (0..m.node_count()).filter(|&n| !touched[n]).count();
    assert!(untouched > 0);
    for n in (0..m.node_count()).filter(|&n| !touched[n]) {
        assert_eq!(m.mass[n], plain.problem.model.mass[n], "node {n}");
    }
    // Momentum kept: the rigid motion slows by M_old / M_new, with the inelastic loss booked.
    let p_old = rec.before.momentum.norm();
    assert!(rec.momentum_jump().norm() / p_old < 1e-12, "{rec:?}");
    let ratio = rec.before.mass / rec.after.mass;
    for v in r.state.v_full.iter().chain(&r.state.v_half) {
        assert!((v - ratio * v0).norm() / v0.norm() < 1e-12, "{v}");
    }
    let expected = 0.5 * rec.before.mass * (ratio - 1.0) * v0.norm_squared();
    assert!(
        (rec.kinetic_jump() / expected - 1.0).abs() < 1e-9,
        "{} against {expected}",
        rec.kinetic_jump()
    );
    assert_eq!(r.state.energies.remesh_work, rec.total_energy_jump());
    // The run goes on at the floor's step, still rigid, its balance closed.
    let after = run(&r.problem, 0.5 * limit, Some(r.state), 50);
    for v in &after.v_full {
        assert!(
            (v - ratio * v0).norm() / v0.norm() < 1e-12,
            "{v} after 50 steps"
        );
    }
    assert!(after.energies.relative_error().abs() < 1e-12);
}
