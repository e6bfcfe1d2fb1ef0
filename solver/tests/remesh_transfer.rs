//! The transfer operators of a remeshing (CATALOGUE `remesh/transfer-*`, thesis 8.4, issue 21):
//! a uniform or linear state carried from one mesh of a body to another, different one, keeps
//! its values to round-off; a damaged zone keeps its damage without spreading; the velocity
//! transfer keeps the momentum.
//!
//! The two meshes are box meshes of different resolution with perturbed interiors, both mapped
//! by the same deformation, so that they mesh the same current configuration as a mesher would.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use impact_solver::material::{IsotropicElastic, SaintVenantKirchhoff};
use impact_solver::mesh::ops::*;
use impact_solver::mesh::{box_mesh, perturb_interior, BoxSpec, Mesh};
use impact_solver::remesh::*;
use nalgebra::{Matrix3, Vector3};

const ORIGIN: [f64; 3] = [0.1, -0.2, 0.3];
const SIZE: [f64; 3] = [1.0, 0.8, 0.6];

/// A box mesh of `divisions` with its interior nodes moved by up to `fraction` of a cell.
fn box_of(divisions: [usize; 3], fraction: f64, seed: u64) -> Mesh {
    let spec = BoxSpec {
        origin: ORIGIN,
        size: SIZE,
        divisions,
        mirror: Vec::new(),
    };
    let mut mesh = box_mesh(&spec);
    perturb_interior(&mut mesh, &spec, fraction, seed);
    mesh
}

/// A homogeneous deformation: stretch, shear and rotation, `det A = 1.092`.
fn affine_gradient() -> Matrix3<f64> {
    let rotation = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 0.5);
    rotation.matrix() * Matrix3::new(1.2, 0.1, 0.0, 0.0, 0.95, 0.05, 0.0, 0.0, 0.96)
}

fn map(mesh: &Mesh, phi: impl Fn(&Vector3<f64>) -> Vector3<f64>) -> Vec<Vector3<f64>> {
    mesh.nodes.iter().map(phi).collect()
}

/// The old mesh (coarse) and the new one (finer), in the current configuration of the affine
/// deformation.
fn affine_pair() -> (Mesh, Vec<Vector3<f64>>, Mesh, Vec<Vector3<f64>>) {
    let a = affine_gradient();
    let b = Vector3::new(0.01, -0.02, 0.03);
    let old = box_of([5, 4, 3], 0.2, 1);
    let new = box_of([8, 6, 5], 0.2, 2);
    let x_old = map(&old, |x| a * x + b);
    let x_new = map(&new, |x| a * x + b);
    (old, x_old, new, x_new)
}

fn max_abs(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |m, v| m.max(v.abs()))
}

/// Largest distance of the transferred nodal vectors from the exact field at the new nodes,
/// relative to the largest transferred vector.
fn nodal_relative_error(
    x_new: &[Vector3<f64>],
    new_values: &[Vector3<f64>],
    field: impl Fn(&Vector3<f64>) -> Vector3<f64>,
) -> f64 {
    let scale = max_abs(new_values.iter().map(|v| v.norm()));
    max_abs(
        x_new
            .iter()
            .zip(new_values)
            .map(|(x, v)| (v - field(x)).norm()),
    ) / scale
}

/// T3 (8.10): a constant and a linear nodal field come through to round-off.
#[test]
fn t3_is_exact_for_constant_and_linear_nodal_fields() {
    let (old, x_old, _, x_new) = affine_pair();
    let locator = Locator::new(&x_old, &old.tets).unwrap();
    let locations = locator.locate_all(&x_new, 0.0).unwrap();
    let constant = Vector3::new(1.5, -2.0, 0.25);
    let gradient = Matrix3::new(0.3, -1.0, 2.0, 0.5, 0.1, -0.7, 1.1, 0.0, 0.4);
    let linear = |x: &Vector3<f64>| gradient * x + constant;
    for (name, field) in [
        (
            "constant",
            &(|_: &Vector3<f64>| constant) as &dyn Fn(&Vector3<f64>) -> Vector3<f64>,
        ),
        ("linear", &linear),
    ] {
        let old_values: Vec<_> = x_old.iter().map(field).collect();
        let new_values = transfer_nodal_vectors(&old_values, &old.tets, &locations);
        let error = nodal_relative_error(&x_new, &new_values, field);
        println!(
            "T3 {name} field: max relative error {error:.3e} over {} new nodes",
            x_new.len()
        );
        assert!(error < 1e-12, "T3 {name}: relative error {error:e}");
    }
}

/// T3 over a curved deformed boundary: the new boundary nodes fall just outside the old
/// polyhedral boundary (the faces chord the curve differently); the nearest-element fallback
/// extrapolates linearly, so a linear field is still exact, and the gap is a small part of a
/// cell.
#[test]
fn t3_stays_exact_for_new_nodes_just_outside_a_curved_boundary() {
    let bend = |x: &Vector3<f64>| {
        Vector3::new(
            x.x + 0.05 * (3.0 * x.z).sin(),
            x.y + 0.04 * (2.0 * x.x).cos(),
            x.z + 0.06 * (2.5 * x.y).sin(),
        )
    };
    let old = box_of([5, 4, 3], 0.2, 1);
    let new = box_of([8, 6, 5], 0.2, 2);
    let (x_old, x_new) = (map(&old, bend), map(&new, bend));
    let locator = Locator::new(&x_old, &old.tets).unwrap();
    // Allow a gap of 2 % of the old cells' edge (0.2 m): the chords of the bent faces sag by
    // about `kappa L^2 / 8 = 0.45 * 0.2^2 / 8 = 2.3e-3` m at most.
    let allowed = 0.02 * 0.2;
    let locations = locator.locate_all(&x_new, allowed).unwrap();
    let outside = locations.iter().filter(|l| l.distance > 0.0).count();
    let gap = max_abs(locations.iter().map(|l| l.distance));
    let gradient = Matrix3::new(0.3, -1.0, 2.0, 0.5, 0.1, -0.7, 1.1, 0.0, 0.4);
    let field = |x: &Vector3<f64>| gradient * x + Vector3::new(1.0, 2.0, 3.0);
    let old_values: Vec<_> = x_old.iter().map(field).collect();
    let new_values = transfer_nodal_vectors(&old_values, &old.tets, &locations);
    let error = nodal_relative_error(&x_new, &new_values, field);
    println!(
        "T3 curved boundary: {outside} of {} new nodes outside the old mesh, largest gap \
         {gap:.3e} m, linear field relative error {error:.3e}",
        x_new.len()
    );
    assert!(
        outside > 0,
        "the test must exercise the nearest-element fallback"
    );
    assert!(error < 1e-12, "relative error {error:e}");
}

/// T1 (8.9): a constant element field (a uniform stress and a uniform deformation gradient)
/// comes through to round-off, and (8.8) holds to round-off for it.
#[test]
fn t1_is_exact_for_constant_element_fields() {
    let (old, x_old, new, x_new) = affine_pair();
    let locator = Locator::new(&x_old, &old.tets).unwrap();
    let locations = locator.locate_all(&x_new, 0.0).unwrap();
    let old_volumes = element_volumes(&x_old, &old.tets);
    let new_volumes = element_volumes(&x_new, &new.tets);
    // A uniform Cauchy stress [xx, yy, zz, xy, yz, xz] (Pa) and F of the deformation.
    let stress = [-12e6, 3.5e6, 0.7e6, 1.25e6, -0.4e6, 2e6];
    let f = affine_gradient();
    for (name, row) in [("stress", stress.to_vec()), ("F", matrices_to_rows(&[f]))] {
        let width = row.len();
        let values: Vec<f64> = (0..old.tets.len()).flat_map(|_| row.clone()).collect();
        let moved = shape_function_transfer(
            &values,
            width,
            &old.tets,
            &old_volumes,
            old.nodes.len(),
            &locations,
            &new.tets,
        )
        .unwrap();
        assert_eq!(moved.len(), new.tets.len() * width);
        let scale = max_abs(row.iter().copied());
        let error = max_abs(
            moved
                .chunks_exact(width)
                .flat_map(|r| r.iter().zip(&row).map(|(a, b)| a - b)),
        ) / scale;
        let before = element_integral(&values, width, &old_volumes);
        let after = element_integral(&moved, width, &new_volumes);
        let integral_error =
            max_abs(before.iter().zip(&after).map(|(a, b)| a - b)) / max_abs(before.into_iter());
        println!(
            "T1 constant {name}: max relative error {error:.3e}, (8.8) integral {integral_error:.3e}"
        );
        assert!(error < 1e-12, "T1 {name}: relative error {error:e}");
        assert!(
            integral_error < 1e-12,
            "(8.8) for {name}: {integral_error:e}"
        );
    }
}

/// T1 smooths a jump (the artificial diffusion of 8.4.1.1) while T2 (Fig. 8.6) copies values:
/// a damage field, 1 in the old elements whose centroid lies in a sphere and 0 elsewhere, keeps
/// only the values 0 and 1 through T2, its damaged volume within the resolution, and no damage
/// appears away from the damaged elements; through T1 it takes intermediate values.
#[test]
fn t2_keeps_a_damaged_zone_without_spreading_it() {
    let spec = |n: usize| BoxSpec {
        origin: [0.0; 3],
        size: [1.0; 3],
        divisions: [n; 3],
        mirror: Vec::new(),
    };
    let mut old = box_mesh(&spec(10));
    perturb_interior(&mut old, &spec(10), 0.2, 3);
    let mut new = box_mesh(&spec(13));
    perturb_interior(&mut new, &spec(13), 0.2, 4);
    let (centre, radius) = (Vector3::new(0.45, 0.5, 0.55), 0.3);
    let old_centroids = centroids(&old.nodes, &old.tets);
    let damage: Vec<f64> = old_centroids
        .iter()
        .map(|c| {
            if (c - centre).norm() < radius {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let sources =
        closest_gauss_point_sources(&old.nodes, &old.tets, &new.nodes, &new.tets).unwrap();
    let moved = copy_rows(&damage, 1, &sources);
    assert!(
        moved.iter().all(|&d| d == 0.0 || d == 1.0),
        "T2 made intermediate values"
    );

    // Damaged volume, within the resolution. Each mesh can represent the damaged ball only to
    // its own resolution: the old damaged volume `V_old` (old elements whose centroid is in the
    // ball) differs from the ball's `4/3 pi R^3` by `e_old`, and the new mesh's own sampling of
    // the ball (new elements whose centroid is in it) by `e_new`. The transfer is within the
    // resolution when it moves the damaged volume by no more than these two errors together:
    // `|V_T2 - V_old| <= e_old + e_new`. A spread of the damage by one layer of elements adds a
    // layer's volume, far more (checked below as a negative control).
    let old_volumes = element_volumes(&old.nodes, &old.tets);
    let new_volumes = element_volumes(&new.nodes, &new.tets);
    let damaged = |d: &[f64], v: &[f64]| d.iter().zip(v).map(|(d, v)| d * v).sum::<f64>();
    let ball = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    let new_sampled: Vec<f64> = centroids(&new.nodes, &new.tets)
        .iter()
        .map(|c| {
            if (c - centre).norm() < radius {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let (v_old, v_new) = (
        damaged(&damage, &old_volumes),
        damaged(&moved, &new_volumes),
    );
    let e_old = (v_old - ball).abs();
    let e_new = (damaged(&new_sampled, &new_volumes) - ball).abs();
    let tolerance = e_old + e_new;
    let change = (v_new - v_old).abs();
    println!(
        "T2 damaged volume {v_old:.6e} -> {v_new:.6e} m^3: change {change:.3e} m^3 ({:.3e} \
         relative); the meshes' own errors for the ball {ball:.6e} m^3: old {e_old:.3e}, new \
         {e_new:.3e}; tolerance {tolerance:.3e} m^3 ({:.3e} relative)",
        change / v_old,
        tolerance / v_old
    );
    assert!(
        change <= tolerance,
        "damaged volume changed by {change:e} m^3"
    );
    // The negative control: damage every new element that has a node in a damaged old element
    // (a one-layer spread); its volume change must fail the tolerance.
    let locator = Locator::new(&old.nodes, &old.tets).unwrap();
    let locations = locator.locate_all(&new.nodes, 0.0).unwrap();
    let spread: Vec<f64> = new
        .tets
        .iter()
        .map(|t| {
            let hit = t
                .iter()
                .any(|&n| damage[locations[n as usize].element] == 1.0);
            if hit {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let spread_change = (damaged(&spread, &new_volumes) - v_old).abs();
    println!("one-layer spread would change it by {spread_change:.3e} m^3");
    assert!(spread_change > tolerance);

    // No spreading element by element: a new element takes the value of the old centroid
    // closest to its own, and the old element holding its centroid has its centroid within its
    // diameter, so every new element lies within `h_old` of an old centroid of its own value.
    let h_old = (0..old.tets.len())
        .map(|e| diameter(&old.element_nodes(e)))
        .fold(0.0, f64::max);
    let w = h_old;
    // No spreading: every damaged new element is within `w` of an old damaged element's
    // centroid, every undamaged one within `w` of an undamaged one.
    for (e, d) in moved.iter().enumerate() {
        let c = new.element_nodes(e).iter().sum::<Vector3<f64>>() / 4.0;
        let near = old_centroids
            .iter()
            .zip(&damage)
            .filter(|(_, od)| *od == d)
            .map(|(oc, _)| (oc - c).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            near <= w,
            "new element {e} (damage {d}) is {near} m from any such old one"
        );
    }

    // T1 of the same field diffuses it: values strictly between 0 and 1 appear.
    let smoothed = shape_function_transfer(
        &damage,
        1,
        &old.tets,
        &old_volumes,
        old.nodes.len(),
        &locations,
        &new.tets,
    )
    .unwrap();
    let intermediate = smoothed
        .iter()
        .filter(|&&d| d > 1e-9 && d < 1.0 - 1e-9)
        .count();
    println!(
        "T1 of the same damage: {intermediate} of {} new elements take values strictly between 0 \
         and 1",
        new.tets.len()
    );
    assert!(intermediate > 0);
}

/// Longest edge of a tetrahedron (its diameter).
fn diameter(x: &[Vector3<f64>; 4]) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            d = d.max((x[i] - x[j]).norm());
        }
    }
    d
}

/// Velocities through T3 then the uniform shift: the momentum of the new mesh equals the old
/// one to round-off, while T3 alone misses it.
#[test]
fn velocity_transfer_keeps_the_momentum() {
    let (old, x_old, new, x_new) = affine_pair();
    let locator = Locator::new(&x_old, &old.tets).unwrap();
    let locations = locator.locate_all(&x_new, 0.0).unwrap();
    let rho = 2400.0;
    let old_volumes = element_volumes(&x_old, &old.tets);
    let new_volumes = element_volumes(&x_new, &new.tets);
    let old_mass = lumped_masses(
        &old.tets,
        &old_volumes,
        &vec![rho; old.tets.len()],
        old.nodes.len(),
    );
    let new_mass = lumped_masses(
        &new.tets,
        &new_volumes,
        &vec![rho; new.tets.len()],
        new.nodes.len(),
    );
    // A translation, a spin and a wave: not linear, so T3 does not reproduce it exactly.
    let omega = Vector3::new(3.0, -1.0, 2.0);
    let velocity = |x: &Vector3<f64>| {
        Vector3::new(10.0, -4.0, 2.5)
            + omega.cross(x)
            + Vector3::new((7.0 * x.y).sin(), (5.0 * x.z).cos(), (6.0 * x.x).sin()) * 3.0
    };
    let old_v: Vec<_> = x_old.iter().map(velocity).collect();
    let (new_v, shift) =
        transfer_velocities(&old_v, &old_mass, &old.tets, &locations, &new_mass).unwrap();
    let p_old = momentum(&old_mass, &old_v);
    let p_new = momentum(&new_mass, &new_v);
    let p_t3 = momentum(
        &new_mass,
        &transfer_nodal_vectors(&old_v, &old.tets, &locations),
    );
    let error = (p_new - p_old).norm() / p_old.norm();
    let t3_error = (p_t3 - p_old).norm() / p_old.norm();
    let mass_change = (new_mass.iter().sum::<f64>() - old_mass.iter().sum::<f64>()).abs()
        / old_mass.iter().sum::<f64>();
    println!(
        "velocities: momentum error {error:.3e} after the shift {:.3e} m/s, {t3_error:.3e} by T3 \
         alone; kinetic energy {:.6e} -> {:.6e} J; total mass relative change {mass_change:.3e}",
        shift.norm(),
        kinetic_energy(&old_mass, &old_v),
        kinetic_energy(&new_mass, &new_v)
    );
    assert!(error < 1e-12, "momentum relative error {error:e}");
    assert!(
        t3_error > 1e-6,
        "T3 alone should miss the momentum here ({t3_error:e})"
    );
    assert!(
        mass_change < 1e-12,
        "same domain, same density: same mass ({mass_change:e})"
    );
}

/// The record of a remeshing of a Saint-Venant-Kirchhoff body in uniform deformation, moving
/// rigidly: the stored energy (with `F` carried by T1) and the momentum do not jump; the
/// kinetic energy changes only through the lumped masses' different positions.
#[test]
fn record_of_a_uniform_state_shows_no_jump() {
    let (old, x_old, new, x_new) = affine_pair();
    let locator = Locator::new(&x_old, &old.tets).unwrap();
    let locations = locator.locate_all(&x_new, 0.0).unwrap();
    let material = SaintVenantKirchhoff::new(IsotropicElastic {
        density: 2400.0,
        youngs_modulus: 30e9,
        poisson_ratio: 0.2,
    });
    let f = affine_gradient();
    let j = f.determinant();
    let old_volumes = element_volumes(&x_old, &old.tets);
    let new_volumes = element_volumes(&x_new, &new.tets);
    let old_f = vec![f; old.tets.len()];
    let moved = shape_function_transfer(
        &matrices_to_rows(&old_f),
        9,
        &old.tets,
        &old_volumes,
        old.nodes.len(),
        &locations,
        &new.tets,
    )
    .unwrap();
    let new_f = rows_to_matrices(&moved);
    // Current density rho_0 / det F through T1, then the new masses.
    let density = vec![2400.0 / j; old.tets.len()];
    let new_density = shape_function_transfer(
        &density,
        1,
        &old.tets,
        &old_volumes,
        old.nodes.len(),
        &locations,
        &new.tets,
    )
    .unwrap();
    let old_mass = lumped_masses(&old.tets, &old_volumes, &density, old.nodes.len());
    let new_mass = lumped_masses(&new.tets, &new_volumes, &new_density, new.nodes.len());
    let velocity = Vector3::new(50.0, 0.0, -20.0);
    let old_v = vec![velocity; old.nodes.len()];
    let (new_v, shift) =
        transfer_velocities(&old_v, &old_mass, &old.tets, &locations, &new_mass).unwrap();
    let before = MeshState::measure(
        &x_old,
        &old.tets,
        &old_mass,
        &old_v,
        stored_energy(&old_volumes, &old_f, &material).unwrap(),
    );
    let after = MeshState::measure(
        &x_new,
        &new.tets,
        &new_mass,
        &new_v,
        stored_energy(&new_volumes, &new_f, &material).unwrap(),
    );
    let record = RemeshRecord {
        time: 1.25e-4,
        region_elements: old.tets.len(),
        before,
        after,
        velocity_shift: shift,
        separation: Default::default(),
        peeled: 0,
        surface_collapses: 0,
        surface_volume_change: 0.0,
        added_mass: 0.0,
        peeled_volume: 0.0,
        kinetic_restored: 0.0,
        fluctuation_scale: 1.0,
    };
    println!("{}", record.summary());
    assert_eq!(record.before.elements, old.tets.len());
    assert_eq!(record.after.elements, new.tets.len());
    assert!(record.before.stored > 0.0);
    let stored = record.stored_jump().abs() / record.before.stored;
    let kinetic = record.kinetic_jump().abs() / record.before.kinetic;
    let p = record.momentum_jump().norm() / record.before.momentum.norm();
    println!("relative jumps: stored {stored:.3e}, kinetic {kinetic:.3e}, momentum {p:.3e}");
    assert!(stored < 1e-12, "stored energy jump {stored:e}");
    assert!(kinetic < 1e-12, "kinetic energy jump {kinetic:e}");
    assert!(p < 1e-12, "momentum jump {p:e}");
    // A uniform history (of any material) is copied bit for bit by T2.
    let history: Vec<f32> = (0..old.tets.len())
        .flat_map(|_| [1.0f32, 0.25, -3e-4])
        .collect();
    let sources = closest_gauss_point_sources(&x_old, &old.tets, &x_new, &new.tets).unwrap();
    let copied = copy_rows(&history, 3, &sources);
    assert!(copied.chunks_exact(3).all(|r| r == [1.0f32, 0.25, -3e-4]));
}
