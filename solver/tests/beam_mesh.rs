//! The unstructured beam mesh of the mesh-objectivity check (`cases/meshes/beam/`, made by
//! `beam.geo`): the thesis beam, 3000 x 600 x 300 mm, in Delaunay tetrahedra of about 50 mm, with
//! lines of nodes imprinted where the structured case `beam/static-3pt` selects its supports, pins,
//! loading plate and mid-span probe.
//!
//! Checks that the file reads and validates (every tetrahedron positive as written), that it fills
//! the box (volume to 1e-9, bounding box exact), that every element is small enough for the crack
//! band of the thesis concrete, and that the box selectors of the case pick exactly the nodes on the
//! imprinted lines (seven per line, 50 mm apart), as on the structured 50 mm mesh. Run with
//! `cargo test --release -p impact-solver --test beam_mesh -- --nocapture` for the figures quoted
//! in the folder's README.md.

use std::path::Path;

use nalgebra::Vector3;

use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::mesh::gmsh::read_msh;
use impact_solver::mesh::{element_quality, Mesh, DEFAULT_MIN_ALTITUDE_RATIO};

const SIZE: [f64; 3] = [3.0, 0.6, 0.3];

fn beam() -> Mesh {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../cases/meshes/beam/beam_50mm.msh"
    );
    read_msh(Path::new(path)).unwrap_or_else(|e| panic!("{e}"))
}

/// Nodes in the closed box `[min, max]`, with the scene selector's tolerance (1e-9 of the body
/// size).
fn in_box(mesh: &Mesh, min: [f64; 3], max: [f64; 3]) -> Vec<Vector3<f64>> {
    let tol = 1e-9 * SIZE[0];
    mesh.nodes
        .iter()
        .filter(|x| (0..3).all(|a| x[a] >= min[a] - tol && x[a] <= max[a] + tol))
        .copied()
        .collect()
}

#[test]
fn the_beam_mesh_reads_validates_and_fills_the_box() {
    let mesh = beam();
    mesh.validate("beam_50mm.msh", DEFAULT_MIN_ALTITUDE_RATIO)
        .unwrap_or_else(|e| panic!("{e}"));
    let volume = SIZE.iter().product::<f64>();
    let error = mesh.volume() / volume - 1.0;
    assert!(error.abs() < 1e-9, "volume {} m^3", mesh.volume());
    let (lo, hi) = mesh.bounding_box();
    for a in 0..3 {
        assert!(
            lo[a].abs() < 1e-12 && (hi[a] - SIZE[a]).abs() < 1e-12,
            "{lo} {hi}"
        );
    }
    // Every node is used by an element (the reader keeps no loose nodes for a volume group).
    let mut used = vec![false; mesh.node_count()];
    for tet in &mesh.tets {
        for &n in tet {
            used[n as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
    assert_eq!(
        mesh.node_sets.get("beam").map(Vec::len),
        Some(mesh.node_count())
    );

    // Sizes and shapes, with the crack-band size h = (6 V)^(1/3) of the microplane model.
    let (mut h_min, mut h_max, mut h_sum) = (f64::INFINITY, 0.0f64, 0.0);
    let (mut altitude, mut ratio) = (f64::INFINITY, f64::INFINITY);
    for e in 0..mesh.element_count() {
        let x = mesh.element_nodes(e);
        let q = element_quality(&x);
        let v = (x[1] - x[0]).cross(&(x[2] - x[0])).dot(&(x[3] - x[0])) / 6.0;
        let h = MicroplaneConcrete::element_size(v);
        h_min = h_min.min(h);
        h_max = h_max.max(h);
        h_sum += h;
        altitude = altitude.min(q.min_altitude);
        ratio = ratio.min(q.min_altitude / q.max_edge);
    }
    let h_mean = h_sum / mesh.element_count() as f64;
    println!(
        "{} nodes, {} tetrahedra, volume error {error:.1e}",
        mesh.node_count(),
        mesh.element_count()
    );
    println!(
        "h = (6V)^(1/3): min {:.1} mm, mean {:.1} mm, max {:.1} mm",
        h_min * 1e3,
        h_mean * 1e3,
        h_max * 1e3
    );
    println!(
        "min altitude {:.2} mm, worst altitude / longest edge {ratio:.3}",
        altitude * 1e3
    );
    assert!((0.045..0.06).contains(&h_mean), "mean h {h_mean}");
    assert!(ratio > 0.15, "worst altitude / edge {ratio}");

    // The crack band of the thesis concrete admits every element (the limit is 100 mm since the
    // softening ends in Hordijk's tail: a larger element would snap back).
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../cases/materials/thesis-concrete.yaml"
    );
    let parameters =
        impact_solver::material::read_microplane_file(Path::new(path)).expect("material file");
    let model = MicroplaneConcrete::new(parameters).unwrap();
    println!(
        "crack-band limit of thesis-concrete: {:.1} mm",
        model.largest_element() * 1e3
    );
    assert!(h_max < model.largest_element());
    assert!(model.crack_band(h_max).is_ok());
}

#[test]
fn the_case_selectors_pick_the_imprinted_lines() {
    let mesh = beam();
    let (w, top) = (SIZE[2], SIZE[1]);
    // One line across the width: exactly seven nodes, at z = 0, 0.05, ..., 0.3.
    let line = |x: f64, y: f64| {
        let mut nodes = in_box(&mesh, [x, y, 0.0], [x, y, w]);
        assert_eq!(nodes.len(), 7, "line x = {x}, y = {y}");
        nodes.sort_by(|a, b| a.z.total_cmp(&b.z));
        for (k, n) in nodes.iter().enumerate() {
            assert!((n.z - 0.05 * k as f64).abs() < 1e-12, "line x = {x}: {n}");
            assert!(
                (n.x - x).abs() < 1e-12 && (n.y - y).abs() < 1e-12,
                "line x = {x}: {n}"
            );
        }
    };
    for x in [0.05, 0.10, 0.15, 1.50, 2.85, 2.90, 2.95] {
        line(x, 0.0);
    }
    for k in 0..7 {
        line(1.35 + 0.05 * k as f64, top);
    }
    // The strips of the case hold no node between the lines: the same counts as the structured
    // 50 mm mesh (3 lines x 7 per support, 7 x 7 under the plate).
    assert_eq!(in_box(&mesh, [0.05, 0.0, 0.0], [0.15, 0.0, w]).len(), 21);
    assert_eq!(in_box(&mesh, [2.85, 0.0, 0.0], [2.95, 0.0, w]).len(), 21);
    assert_eq!(in_box(&mesh, [1.35, top, 0.0], [1.65, top, w]).len(), 49);
    // The pins: one node each, at the middle of the middle support line.
    assert_eq!(in_box(&mesh, [0.1, 0.0, 0.15], [0.1, 0.0, 0.15]).len(), 1);
    assert_eq!(in_box(&mesh, [2.9, 0.0, 0.15], [2.9, 0.0, 0.15]).len(), 1);
}
