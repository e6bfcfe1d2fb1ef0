//! Scene files: the example parses and builds; bad input gives its specific message.

use impact_solver::scene::{build_problem, Scene};
use impact_solver::SolverError;

const EXAMPLE: &str = include_str!("../../cases/examples/confined-column.yaml");

#[test]
fn the_example_scene_builds() {
    let scene = Scene::from_yaml(EXAMPLE, "example.yaml").unwrap();
    let problem = build_problem(&scene).unwrap();
    assert_eq!(problem.model.element_count(), 6 * 100 * 2 * 2);
    assert_eq!(problem.constraints.len(), 5);
    assert_eq!(problem.probes[0].nodes.len(), 9);
}

fn error_of(text: &str) -> String {
    match Scene::from_yaml(text, "bad.yaml").and_then(|s| build_problem(&s).map(|_| ())) {
        Err(e @ SolverError::InvalidScene { .. }) => e.to_string(),
        other => panic!("expected an InvalidScene error, got {other:?}"),
    }
}

#[test]
fn an_unknown_key_is_named_with_its_line() {
    let text = EXAMPLE.replace("    material:\n", "    materail_typo: 1\n    material:\n");
    let msg = error_of(&text);
    assert!(
        msg.contains("bad.yaml") && msg.contains("materail_typo") && msg.contains("line"),
        "{msg}"
    );
}

#[test]
fn malformed_yaml_is_reported_with_its_line() {
    let msg = error_of("name: [unclosed\nbodies: []\n");
    assert!(msg.contains("line"), "{msg}");
}

#[test]
fn a_negative_density_is_refused() {
    let msg = error_of(&EXAMPLE.replace("density: 2300", "density: -2300"));
    assert!(msg.contains("density must be positive"), "{msg}");
}

#[test]
fn a_selector_that_picks_nothing_is_refused() {
    let msg = error_of(&EXAMPLE.replace(
        "point: [0.5, 0, 0], normal: [1, 0, 0]",
        "point: [7.5, 0, 0], normal: [1, 0, 0]",
    ));
    assert!(
        msg.contains("picks no node") && msg.contains("probe `mid`"),
        "{msg}"
    );
}

#[test]
fn an_unknown_body_is_refused() {
    let msg = error_of(&EXAMPLE.replacen("body: column", "body: colum", 1));
    assert!(msg.contains("no body named `colum`"), "{msg}");
}

#[test]
fn a_missing_mesh_file_is_refused() {
    let text = EXAMPLE.replace(
        "box: { origin: [0, 0, 0], size: [1.0, 0.05, 0.05], divisions: [100, 2, 2] }",
        "gmsh: does/not/exist.msh",
    );
    let scene = Scene::from_yaml(&text, "bad.yaml").unwrap();
    let err = build_problem(&scene).unwrap_err();
    assert!(matches!(err, SolverError::MeshRead { .. }), "{err}");
    assert!(err.to_string().contains("does/not/exist.msh"));
}

const REGION_SCENE: &str = "
name: region
bodies:
  - name: prism
    mesh: { box: { origin: [0, 0, 0], size: [0.3, 0.1, 0.1], divisions: [6, 2, 2] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.18 } }
    regions:
      - name: band
        centroid_box: { min: [0.1, 0, 0], max: [0.15, 0.1, 0.1] }
        material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.18 } }
boundary_conditions:
  - { body: prism, nodes: boundary, motion: { fixed: [x] } }
analysis: { static: { load_steps: 1 } }
";

/// A material region takes the elements whose centroid lies in its box into a body of its own
/// that shares the parent's nodes: the same material there gives bitwise the same forces as the
/// undivided body, and `boundary` still means the outer surface of the whole mesh.
#[test]
fn a_material_region_shares_the_nodes_of_its_body() {
    let scene = Scene::from_yaml(REGION_SCENE, "region.yaml").unwrap();
    let problem = build_problem(&scene).unwrap();
    let model = &problem.model;
    assert_eq!(model.bodies.len(), 2);
    assert_eq!(model.element_count(), 6 * 6 * 2 * 2);
    assert_eq!(model.bodies[1].name, "band");
    assert_eq!(model.bodies[1].elements.len(), 6 * 2 * 2);
    assert!(model.bodies[1].nodes.is_empty());
    assert_eq!(model.node_count(), 7 * 3 * 3);
    // Boundary nodes of the whole 6 x 2 x 2 box: all but the 5 interior ones.
    assert_eq!(problem.constraints[0].nodes.len(), 7 * 3 * 3 - 5);

    let whole = REGION_SCENE
        .split("    regions:")
        .next()
        .unwrap()
        .to_string()
        + "boundary_conditions: []\nanalysis: { static: { load_steps: 1 } }\n";
    let plain = build_problem(&Scene::from_yaml(&whole, "plain.yaml").unwrap()).unwrap();
    let u: Vec<_> = model
        .reference
        .iter()
        .map(|x| nalgebra::Vector3::new(1e-4 * x.y * x.x, 2e-4 * x.z, -1e-4 * x.x * x.x))
        .collect();
    let (mut f, mut g) = (
        vec![nalgebra::Vector3::zeros(); u.len()],
        vec![nalgebra::Vector3::zeros(); u.len()],
    );
    assert_eq!(model.internal_forces(&u, &mut f).unwrap(), None);
    assert_eq!(plain.model.internal_forces(&u, &mut g).unwrap(), None);
    for (a, b) in f.iter().zip(&g) {
        assert!((a - b).norm() <= 1e-9 * b.norm().max(1.0), "{a} {b}");
    }
}

#[test]
fn a_region_that_holds_no_element_is_refused() {
    let text = REGION_SCENE.replace(
        "min: [0.1, 0, 0], max: [0.15, 0.1, 0.1]",
        "min: [1, 1, 1], max: [2, 2, 2]",
    );
    let msg = error_of(&text);
    assert!(
        msg.contains("region `band`") && msg.contains("no element"),
        "{msg}"
    );
}

const MIRROR_SCENE: &str = "
name: mirror
bodies:
  - name: beam
    mesh: { box: { origin: [0, 0, 0], size: [0.4, 0.1, 0.1], divisions: [4, 1, 2], mirror: [x, z] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.18 } }
analysis: { static: { load_steps: 1 } }
";

/// `mirror: [x, z]` on a box reaches the generator: the mesh is the mirrored one, not the
/// Kuhn split of the scene without the key.
#[test]
fn a_box_reads_its_mirror_axes() {
    use impact_solver::mesh::{box_mesh, Axis};
    let scene = Scene::from_yaml(MIRROR_SCENE, "mirror.yaml").unwrap();
    let impact_solver::scene::MeshSource::Box(b) = &scene.bodies[0].mesh else {
        panic!("a box mesh")
    };
    assert_eq!(b.mirror, [Axis::X, Axis::Z]);
    let problem = build_problem(&scene).unwrap();
    let mirrored = box_mesh(&b.spec());
    assert_eq!(*problem.model.tets, *mirrored.tets);
    let plain = build_problem(
        &Scene::from_yaml(&MIRROR_SCENE.replace(", mirror: [x, z]", ""), "plain.yaml").unwrap(),
    )
    .unwrap();
    assert_ne!(*plain.model.tets, *mirrored.tets);
}

#[test]
fn an_odd_division_along_a_mirrored_axis_is_refused() {
    let msg = error_of(&MIRROR_SCENE.replace("divisions: [4, 1, 2]", "divisions: [5, 1, 2]"));
    assert!(
        msg.contains("body `beam` mesh.box.mirror")
            && msg.contains("5 divisions along x")
            && msg.contains("use an even number of divisions along x"),
        "{msg}"
    );
}

#[test]
fn a_symmetry_plane_takes_the_coordinate_of_its_nodes_and_refuses_nodes_off_one_plane() {
    let text = EXAMPLE.replacen(
        "    motion: { fixed: [y] }",
        "    motion: { symmetry: y }",
        1,
    );
    let problem = build_problem(&Scene::from_yaml(&text, "sym.yaml").unwrap()).unwrap();
    assert_eq!(
        problem.constraints[0].motion,
        impact_solver::model::Motion::Symmetry {
            axis: 1,
            value: 0.0
        }
    );
    // The z = 0 face's nodes span y from 0 to 0.05 m: no plane normal to y.
    let msg = error_of(&EXAMPLE.replacen(
        "    motion: { fixed: [z] }",
        "    motion: { symmetry: y }",
        1,
    ));
    assert!(
        msg.contains("rollers_z") && msg.contains("one plane normal to axis 1"),
        "{msg}"
    );
}
