//! Sphere meshes of the Hertz impact benchmark (`cases/meshes/spheres/`, made by `sphere.geo`).
//!
//! Two identical spheres, R = 50 mm, E = 1 GPa, nu = 0.3, rho = 1200 kg/m^3, collide head-on along
//! x at 10 m/s; the Hertz contact radius is about 8 mm, so each mesh is refined around its
//! contact pole P = (R, 0, 0). For each level this checks that the file reads and validates
//! (every tetrahedron positive as written: nothing is flipped here), that the volume and the
//! surface approximate the ball, that the pole is fine enough to resolve the contact patch, and
//! that the node sets the harness may use exist. It prints the figures quoted in the folder's
//! README.md, among them the critical time step, which sets the cost of the benchmark.
//!
//! Run with `cargo test --release -p impact-solver --test sphere_meshes -- --nocapture` to see
//! them.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use impact_references::analytic::hertz_impact;
use impact_solver::material::IsotropicElastic;
use impact_solver::mesh::gmsh::read_msh;
use impact_solver::mesh::{
    boundary_faces, boundary_nodes, element_quality, Mesh, DEFAULT_MIN_ALTITUDE_RATIO,
};

/// Sphere radius (m).
const R: f64 = 0.05;
/// Hertz contact radius of the benchmark (m).
const CONTACT_RADIUS: f64 = 0.008;
/// Straight-line distance from the pole that defines the "pole" cap in `sphere.geo` (m).
const CAP_DISTANCE: f64 = 0.02;
/// Faces and elements farther than this from the pole have reached the far size at every level
/// (the coarse size field reaches it at 75 mm).
const FAR_DISTANCE: f64 = 0.075;

const MATERIAL: IsotropicElastic = IsotropicElastic {
    density: 1200.0,
    youngs_modulus: 1.0e9,
    poisson_ratio: 0.3,
};

/// What each refinement level must achieve.
struct Level {
    name: &'static str,
    /// Nominal element size at the pole and far from it (m), as set in `sphere.geo`.
    pole_size: f64,
    far_size: f64,
    /// Bound on |V - 4/3 pi R^3| / (4/3 pi R^3).
    max_volume_error: f64,
    /// Bound on the mean edge length of the boundary faces within the contact radius (m).
    max_pole_edge: f64,
    /// Least number of boundary faces within the contact radius.
    min_pole_faces: usize,
    /// Least (smallest altitude / longest edge) over the elements.
    min_altitude_ratio: f64,
}

const COARSE: Level = Level {
    name: "coarse",
    pole_size: 0.003,
    far_size: 0.012,
    max_volume_error: 0.01,
    max_pole_edge: 0.0033,
    min_pole_faces: 20,
    min_altitude_ratio: 0.12,
};

const MEDIUM: Level = Level {
    name: "medium",
    pole_size: 0.002,
    far_size: 0.009,
    max_volume_error: 0.006,
    max_pole_edge: 0.0022,
    min_pole_faces: 20,
    min_altitude_ratio: 0.12,
};

const FINE: Level = Level {
    name: "fine",
    pole_size: 0.0014,
    far_size: 0.007,
    max_volume_error: 0.004,
    max_pole_edge: 0.00155,
    min_pole_faces: 20,
    min_altitude_ratio: 0.12,
};

fn mesh_path(level: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/meshes/spheres")
        .join(format!("sphere_{level}.msh"))
}

fn pole() -> Vector3<f64> {
    Vector3::new(R, 0.0, 0.0)
}

/// Mean of the edge lengths over a set of edges given as node pairs.
fn mean_length(mesh: &Mesh, edges: &[(u32, u32)]) -> f64 {
    let sum: f64 = edges
        .iter()
        .map(|&(a, b)| (mesh.nodes[a as usize] - mesh.nodes[b as usize]).norm())
        .sum();
    sum / edges.len() as f64
}

/// Unique edges of the given triangles or tetrahedra.
fn unique_edges<const N: usize>(cells: impl Iterator<Item = [u32; N]>) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = cells
        .flat_map(|c| {
            let mut e = Vec::new();
            for i in 0..N {
                for j in i + 1..N {
                    e.push((c[i].min(c[j]), c[i].max(c[j])));
                }
            }
            e
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Figures of one mesh, printed and checked.
#[derive(Debug)]
struct Stats {
    volume_error: f64,
    min_altitude: f64,
    critical_time_step: f64,
}

fn check(level: &Level) -> Stats {
    let path = mesh_path(level.name);
    let name = format!("sphere_{}", level.name);
    let mesh = read_msh(&path).unwrap_or_else(|e| panic!("{e}"));
    let bytes = std::fs::metadata(&path).unwrap().len();

    // Orientation and shape, as the solver checks them; then the actual worst shape.
    mesh.validate(&name, DEFAULT_MIN_ALTITUDE_RATIO)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut min_altitude = f64::INFINITY;
    let mut min_ratio = f64::INFINITY;
    let mut max_edge_ratio: f64 = 0.0;
    for e in 0..mesh.element_count() {
        let q = element_quality(&mesh.element_nodes(e));
        min_altitude = min_altitude.min(q.min_altitude);
        min_ratio = min_ratio.min(q.min_altitude / q.max_edge);
        max_edge_ratio = max_edge_ratio.max(q.edge_ratio);
    }
    // (smallest altitude / longest edge) is sqrt(2/3) = 0.816 for the regular tetrahedron.
    // The worst elements set the critical time step: keep their altitude above 0.3 times the
    // pole size (sphere.geo's OptimizeThreshold = 0.6 gives 0.42 to 0.45).
    assert!(
        min_altitude >= 0.3 * level.pole_size,
        "{name}: smallest altitude {:.3} mm is below 0.3 x the pole size {} mm",
        1e3 * min_altitude,
        1e3 * level.pole_size
    );
    assert!(
        min_ratio >= level.min_altitude_ratio,
        "{name}: worst altitude/edge ratio {min_ratio:.3} < {}",
        level.min_altitude_ratio
    );

    // Volume of the ball: the flat facets cut a little off, less as the surface gets finer.
    let exact = 4.0 / 3.0 * PI * R.powi(3);
    let volume = mesh.volume();
    let volume_error = (volume - exact).abs() / exact;
    assert!(
        volume_error <= level.max_volume_error,
        "{name}: volume {volume:.6e} m^3 is off the ball's {exact:.6e} by {:.3} %, more than {} %",
        100.0 * volume_error,
        100.0 * level.max_volume_error
    );

    // The boundary is the sphere: its nodes on it, all nodes inside it.
    let faces = boundary_faces(&mesh);
    let surface = boundary_nodes(&faces);
    let off_surface = surface
        .iter()
        .map(|&n| (mesh.nodes[n as usize].norm() - R).abs())
        .fold(0.0, f64::max);
    assert!(
        off_surface < 1e-4,
        "{name}: a boundary node lies {off_surface:.3e} m off the sphere"
    );
    let outside = mesh
        .nodes
        .iter()
        .map(|x| x.norm() - R)
        .fold(f64::MIN, f64::max);
    assert!(
        outside < 1e-9,
        "{name}: a node lies {outside:.3e} m outside the sphere"
    );
    // Outward normals (the reader keeps Gmsh's order, so this checks Gmsh's orientation too).
    for f in &faces {
        let [a, b, c] = f.nodes.map(|n| mesh.nodes[n as usize]);
        let normal = (b - a).cross(&(c - a));
        assert!(
            normal.dot(&((a + b + c) / 3.0)) > 0.0,
            "{name}: boundary face {:?} points inwards",
            f.nodes
        );
    }

    // The contact patch: boundary faces whose centroid lies within the Hertz contact radius.
    let p = pole();
    let centroid = |nodes: &[u32]| {
        nodes
            .iter()
            .map(|&n| mesh.nodes[n as usize])
            .sum::<Vector3<f64>>()
            / nodes.len() as f64
    };
    let near: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| f.nodes)
        .filter(|f| (centroid(f) - p).norm() < CONTACT_RADIUS)
        .collect();
    let pole_edge = mean_length(&mesh, &unique_edges(near.iter().copied()));
    let far_faces: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| f.nodes)
        .filter(|f| (centroid(f) - p).norm() > FAR_DISTANCE)
        .collect();
    let far_surface_edge = mean_length(&mesh, &unique_edges(far_faces.into_iter()));
    let far_tets = mesh
        .tets
        .iter()
        .copied()
        .filter(|t| (centroid(t) - p).norm() > FAR_DISTANCE);
    let far_volume_edge = mean_length(&mesh, &unique_edges(far_tets));
    let pole_tets = mesh
        .tets
        .iter()
        .copied()
        .filter(|t| (centroid(t) - p).norm() < CONTACT_RADIUS);
    let pole_volume_edge = mean_length(&mesh, &unique_edges(pole_tets));
    assert!(
        near.len() >= level.min_pole_faces,
        "{name}: only {} boundary faces within {} mm of the pole",
        near.len(),
        1e3 * CONTACT_RADIUS
    );
    assert!(
        pole_edge < level.max_pole_edge,
        "{name}: boundary edges within {} mm of the pole average {:.3} mm, not below {} mm",
        1e3 * CONTACT_RADIUS,
        1e3 * pole_edge,
        1e3 * level.max_pole_edge
    );

    // Node sets from the physical groups of sphere.geo.
    let set = |s: &str| {
        mesh.node_sets
            .get(s)
            .unwrap_or_else(|| panic!("{name}: no node set `{s}`"))
    };
    assert_eq!(
        set("sphere").len(),
        mesh.node_count(),
        "{name}: `sphere` misses nodes"
    );
    let tip = set("pole_tip");
    assert_eq!(tip.len(), 1, "{name}: `pole_tip` should hold one node");
    assert!(
        (mesh.nodes[tip[0] as usize] - p).norm() < 1e-12,
        "{name}: `pole_tip` is not at P"
    );
    let cap = set("pole");
    for &n in cap {
        let x = mesh.nodes[n as usize];
        assert!(
            (x - p).norm() < CAP_DISTANCE + 1e-9 && (x.norm() - R).abs() < 1e-4,
            "{name}: `pole` node {n} at {x:?} is not on the 20 mm cap"
        );
    }
    assert!(
        cap.contains(&tip[0]),
        "{name}: `pole` does not hold the pole node"
    );
    // The faces of the cap: every boundary face whose nodes are all in `pole`.
    let cap_faces = faces
        .iter()
        .filter(|f| f.nodes.iter().all(|n| cap.binary_search(n).is_ok()))
        .count();

    let c_d = MATERIAL.dilatational_wave_speed();
    let critical_time_step = min_altitude / c_d;
    println!(
        "{name}: {} bytes, {} nodes, {} tets, {} boundary faces ({} nodes), \
         `pole` cap {} nodes / {} faces",
        bytes,
        mesh.node_count(),
        mesh.element_count(),
        faces.len(),
        surface.len(),
        cap.len(),
        cap_faces
    );
    println!(
        "{name}:   volume {volume:.6e} m^3 (ball {exact:.6e}, error {:.3} %), boundary nodes \
         within {:.1e} m of the sphere",
        100.0 * volume_error,
        off_surface
    );
    println!(
        "{name}:   within {} mm of the pole: {} boundary faces, mean surface edge {:.3} mm, \
         mean volume edge {:.3} mm (nominal {} mm)",
        1e3 * CONTACT_RADIUS,
        near.len(),
        1e3 * pole_edge,
        1e3 * pole_volume_edge,
        1e3 * level.pole_size
    );
    println!(
        "{name}:   beyond {} mm of the pole: mean surface edge {:.3} mm, mean volume edge {:.3} mm \
         (nominal {} mm)",
        1e3 * FAR_DISTANCE,
        1e3 * far_surface_edge,
        1e3 * far_volume_edge,
        1e3 * level.far_size
    );
    println!(
        "{name}:   worst element: altitude/edge {min_ratio:.3}, edge ratio {max_edge_ratio:.2}; \
         min altitude {:.4} mm; c_d = {c_d:.1} m/s; dt_cr = min altitude / c_d = {:.4e} s",
        1e3 * min_altitude,
        critical_time_step
    );
    Stats {
        volume_error,
        min_altitude,
        critical_time_step,
    }
}

#[test]
fn coarse() {
    check(&COARSE);
}

#[test]
fn medium() {
    check(&MEDIUM);
}

#[test]
fn fine() {
    check(&FINE);
}

/// Hertz's solution for the benchmark (`references/analytic.rs`): maximum approach (m), contact
/// radius (m) and contact duration (s) of two identical spheres meeting at `speed`.
fn hertz(speed: f64) -> (f64, f64, f64) {
    let mass = MATERIAL.density * 4.0 / 3.0 * PI * R.powi(3);
    let h = hertz_impact(&MATERIAL, R, mass, speed);
    (h.max_approach, h.contact_radius, h.duration)
}

/// Refining brings the volume closer to the ball's and shrinks the critical step; prints what a
/// run of the benchmark costs at each level.
#[test]
fn levels_converge() {
    let stats: Vec<Stats> = [COARSE, MEDIUM, FINE].iter().map(check).collect();
    for pair in stats.windows(2) {
        assert!(pair[1].volume_error < pair[0].volume_error, "{stats:?}");
        assert!(pair[1].min_altitude < pair[0].min_altitude, "{stats:?}");
    }
    let (approach, radius, duration) = hertz(10.0);
    assert!(
        (radius - CONTACT_RADIUS).abs() < 0.5e-3,
        "the Hertz contact radius is {:.2} mm, not about {} mm",
        1e3 * radius,
        1e3 * CONTACT_RADIUS
    );
    println!(
        "Hertz at 10 m/s: approach {:.3} mm, contact radius {:.3} mm, contact duration {:.4e} s",
        1e3 * approach,
        1e3 * radius,
        duration
    );
    for (level, s) in [COARSE, MEDIUM, FINE].iter().zip(&stats) {
        // The solver's default step is 0.9 dt_cr.
        println!(
            "{}: dt_cr = {:.4e} s, {:.0} steps of 0.9 dt_cr per contact duration",
            level.name,
            s.critical_time_step,
            duration / (0.9 * s.critical_time_step)
        );
    }
}
