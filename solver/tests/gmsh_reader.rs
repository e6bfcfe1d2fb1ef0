//! Gmsh 4.1 reader against small meshes in `cases/meshes/test/`.
//!
//! `cube_sparse.msh` is hand-written: a unit cube cut into six positive tetrahedra around the
//! diagonal (0,0,0)-(1,1,1), with sparse, shuffled node tags, a geometry-only node (tag 50) and
//! physical groups in every dimension. `cube_sparse_bin.msh` is the same file saved by Gmsh 4.8.4
//! as binary (`gmsh cube_sparse.msh -0 -format msh41 -bin -o cube_sparse_bin.msh`), which keeps
//! the tags. The `cube_gmsh*` files and the error cases come from `cube.geo` (commands there).

use std::path::{Path, PathBuf};

use impact_solver::mesh::gmsh::{parse_msh, read_msh, GmshError};
use impact_solver::mesh::{Mesh, DEFAULT_MIN_ALTITUDE_RATIO};
use impact_solver::SolverError;

fn path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/meshes/test")
        .join(name)
}

fn read(name: &str) -> Mesh {
    read_msh(&path(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// The error message, after checking it is a `MeshRead` that names `name`.
fn message_of(result: impact_solver::error::Result<Mesh>, name: &str) -> String {
    match result {
        Err(e @ SolverError::MeshRead { .. }) => {
            let message = e.to_string();
            assert!(message.contains(name), "`{message}` does not name `{name}`");
            message
        }
        Err(e) => panic!("expected MeshRead, got {e}"),
        Ok(mesh) => panic!("expected an error, read {} tets", mesh.element_count()),
    }
}

fn read_err(name: &str) -> String {
    message_of(read_msh(&path(name)), name)
}

fn assert_same(a: &Mesh, b: &Mesh) {
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.tets, b.tets);
    assert_eq!(a.node_sets, b.node_sets);
}

#[test]
fn ascii_cube_with_sparse_tags() {
    let mesh = read("cube_sparse.msh");
    // File order, without the geometry-only node (tag 50): tags 7, 3, 12, 30, 99, 21, 15, 4.
    let expected_nodes = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [1.0, 0.0, 1.0],
    ];
    assert_eq!(mesh.node_count(), 8);
    for (node, expected) in mesh.nodes.iter().zip(expected_nodes) {
        assert_eq!(node.as_slice(), expected);
    }
    // Element 104 is `7 3 99 4` in the file: tags map to ids, order kept.
    assert_eq!(mesh.element_count(), 6);
    assert_eq!(
        mesh.tets,
        [
            [0, 1, 2, 4],
            [0, 1, 4, 7],
            [0, 3, 4, 2],
            [0, 3, 6, 4],
            [0, 5, 7, 4],
            [0, 5, 4, 6]
        ]
    );
    let sets: Vec<(&str, &[u32])> = mesh
        .node_sets
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_slice()))
        .collect();
    assert_eq!(
        sets,
        [
            ("2:7", &[4, 5, 6, 7][..]),
            ("bottom", &[0, 1, 2, 3][..]),
            ("corner", &[0][..]),
            ("edge", &[0, 1][..]),
            ("solid", &[0, 1, 2, 3, 4, 5, 6, 7][..]),
        ]
    );
    assert!((mesh.volume() - 1.0).abs() < 1e-12, "{}", mesh.volume());
    mesh.validate("cube_sparse", DEFAULT_MIN_ALTITUDE_RATIO)
        .unwrap();
}

#[test]
fn binary_cube_with_sparse_tags_matches_ascii() {
    assert_same(&read("cube_sparse_bin.msh"), &read("cube_sparse.msh"));
}

#[test]
fn gmsh_generated_cube_binary_matches_ascii() {
    let mesh = read("cube_gmsh.msh");
    assert_same(&read("cube_gmsh_bin.msh"), &mesh);
    assert_eq!((mesh.node_count(), mesh.element_count()), (14, 24));
    assert!((mesh.volume() - 1.0).abs() < 1e-12, "{}", mesh.volume());
    mesh.validate("cube_gmsh", DEFAULT_MIN_ALTITUDE_RATIO)
        .unwrap();

    let names: Vec<&str> = mesh.node_sets.keys().map(String::as_str).collect();
    assert_eq!(names, ["2:7", "bottom", "origin", "solid"]);
    let z = |set: &str| -> Vec<f64> {
        mesh.node_sets[set]
            .iter()
            .map(|&n| mesh.nodes[n as usize].z)
            .collect()
    };
    assert_eq!(z("bottom"), [0.0; 5]);
    assert_eq!(z("2:7"), [1.0; 5]);
    let origin = &mesh.node_sets["origin"];
    assert_eq!(origin.len(), 1);
    assert_eq!(mesh.nodes[origin[0] as usize].as_slice(), [0.0; 3]);
    assert_eq!(mesh.node_sets["solid"], (0..14).collect::<Vec<u32>>());
}

#[test]
fn format_2_2_is_rejected_with_the_export_option() {
    let message = read_err("cube_v22.msh");
    assert!(message.contains("2.2 is not supported"), "{message}");
    assert!(message.contains("-format msh41"), "{message}");
}

#[test]
fn truncated_files_are_rejected() {
    let message = read_err("cube_truncated.msh");
    assert!(message.contains("truncated"), "{message}");

    let binary = std::fs::read(path("cube_gmsh_bin.msh")).unwrap();
    for len in [30, binary.len() / 3, binary.len() / 2, binary.len() - 20] {
        let message = message_of(parse_msh(&binary[..len], "cut_bin.msh"), "cut_bin.msh");
        assert!(message.contains("truncated"), "{len} bytes: {message}");
    }
}

#[test]
fn a_file_without_tetrahedra_is_rejected() {
    let message = read_err("cube_surface_only.msh");
    assert!(message.contains("no linear tetrahedra"), "{message}");
    assert!(message.contains("gmsh -3"), "{message}");
}

#[test]
fn a_missing_file_is_rejected() {
    read_err("no_such_mesh.msh");
}

#[test]
fn an_element_with_an_unknown_node_is_rejected() {
    let text = std::fs::read_to_string(path("cube_sparse.msh")).unwrap();
    let broken = text.replace("120 7 21 99 15", "120 7 21 99 16");
    let message = message_of(parse_msh(broken.as_bytes(), "broken.msh"), "broken.msh");
    assert!(
        message.contains("element 120 refers to node tag 16"),
        "{message}"
    );
}

#[test]
fn quadratic_tetrahedra_are_rejected() {
    let tet10 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n3 1 0 10\n\
                 1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n\
                 0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n$EndNodes\n\
                 $Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    let message = message_of(parse_msh(tet10.as_bytes(), "tet10.msh"), "tet10.msh");
    assert!(message.contains("only linear tetrahedra"), "{message}");
}

/// The reader's errors are values a caller can match on, each naming what is wrong.
#[test]
fn errors_are_typed() {
    let reason = |result: impact_solver::error::Result<Mesh>| match result {
        Err(SolverError::MeshRead { reason, .. }) => reason,
        Err(e) => panic!("expected MeshRead, got {e}"),
        Ok(_) => panic!("expected an error"),
    };
    assert_eq!(
        reason(read_msh(&path("cube_v22.msh"))),
        GmshError::UnsupportedVersion("2.2".into())
    );
    assert_eq!(
        reason(read_msh(&path("cube_surface_only.msh"))),
        GmshError::NoTetrahedra
    );
    assert!(matches!(
        reason(read_msh(&path("no_such_mesh.msh"))),
        GmshError::Read(_)
    ));
    assert_eq!(
        reason(parse_msh(b"solid cube\n", "stl.msh")),
        GmshError::NotGmsh
    );
    let text = std::fs::read_to_string(path("cube_sparse.msh")).unwrap();
    let broken = text.replace("120 7 21 99 15", "120 7 21 99 16");
    assert_eq!(
        reason(parse_msh(broken.as_bytes(), "broken.msh")),
        GmshError::UnknownNode {
            element: 120,
            tag: 16
        }
    );
}

// Node tags as written in the file. mshio drops a block's tags when the `$Nodes` header's range
// is dense; the reader reads them back (findings S3). One tetrahedron whose nodes are listed
// out of tag order: the coordinates each tag has in the file are the reference.

/// The unit corner tetrahedron: tag `t` (1 to 4) at `TET_BY_TAG[t - 1]`; element `1 2 3 4` has
/// volume +1/6 (the scalar triple product of the edges from tag 1 is +1).
const TET_BY_TAG: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// An ASCII 4.1 file: one volume block listing `tags` with `coords`, header range 1-4 (dense),
/// and the element `1 2 3 4`.
fn ascii_tet(tags: [u64; 4], coords: [[f64; 3]; 4]) -> String {
    let mut text = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n");
    for t in tags {
        text += &format!("{t}\n");
    }
    for [x, y, z] in coords {
        text += &format!("{x} {y} {z}\n");
    }
    text + "$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n"
}

/// The same file in binary 4.1 (`4.1 1 8`, little-endian, 8-byte size_t), laid out as the Gmsh
/// manual's "MSH file format" section gives it.
fn binary_tet(tags: [u64; 4], coords: [[f64; 3]; 4]) -> Vec<u8> {
    let size = |v: u64| v.to_le_bytes();
    let int = |v: i32| v.to_le_bytes();
    let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
    b.extend(int(1));
    b.extend(b"\n$EndMeshFormat\n$Nodes\n");
    [1, 4, 1, 4].iter().for_each(|&v| b.extend(size(v)));
    [3, 1, 0].iter().for_each(|&v| b.extend(int(v)));
    b.extend(size(4));
    tags.iter().for_each(|&t| b.extend(size(t)));
    coords
        .iter()
        .flatten()
        .for_each(|v| b.extend(v.to_le_bytes()));
    b.extend(b"\n$EndNodes\n$Elements\n");
    [1, 1, 1, 1].iter().for_each(|&v| b.extend(size(v)));
    [3, 1, 4].iter().for_each(|&v| b.extend(int(v)));
    b.extend(size(1));
    [1, 1, 2, 3, 4].iter().for_each(|&v| b.extend(size(v)));
    b.extend(b"\n$EndElements\n");
    b
}

/// Tags 2, 1, 3, 4 listed in that order, each with its own coordinates.
fn permuted() -> ([u64; 4], [[f64; 3]; 4]) {
    let tags = [2, 1, 3, 4];
    (tags, tags.map(|t| TET_BY_TAG[t as usize - 1]))
}

/// Each node of the element has the coordinates its tag has in the file, and the element is
/// positive.
fn assert_read_by_tag(mesh: &Mesh) {
    assert_eq!(mesh.element_count(), 1);
    for (k, &node) in mesh.tets[0].iter().enumerate() {
        assert_eq!(
            mesh.nodes[node as usize].as_slice(),
            TET_BY_TAG[k],
            "tag {}",
            k + 1
        );
    }
    assert!(
        (mesh.volume() - 1.0 / 6.0).abs() < 1e-15,
        "{}",
        mesh.volume()
    );
    mesh.validate("tet", DEFAULT_MIN_ALTITUDE_RATIO)
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn the_binary_test_writer_reads_as_the_ascii_file() {
    let (tags, coords) = ([1, 2, 3, 4], TET_BY_TAG);
    let ascii = parse_msh(ascii_tet(tags, coords).as_bytes(), "tet.msh").unwrap();
    let binary = parse_msh(&binary_tet(tags, coords), "tet_bin.msh").unwrap();
    assert_same(&binary, &ascii);
    assert_read_by_tag(&ascii);
}

#[test]
fn dense_tags_out_of_order_are_read_as_written() {
    let (tags, coords) = permuted();
    let ascii = parse_msh(ascii_tet(tags, coords).as_bytes(), "permuted.msh")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_read_by_tag(&ascii);
    let binary =
        parse_msh(&binary_tet(tags, coords), "permuted_bin.msh").unwrap_or_else(|e| panic!("{e}"));
    assert_read_by_tag(&binary);
}

#[test]
fn a_repeated_dense_tag_is_refused_naming_it() {
    // Tags 1 1 3 4: no node 2, and element 1 refers to it.
    let tags = [1, 1, 3, 4];
    let reason = |result: impact_solver::error::Result<Mesh>, name: &str| {
        let message = message_of(result, name);
        assert!(message.contains("node tag 1 is defined twice"), "{message}");
        message
    };
    reason(
        parse_msh(ascii_tet(tags, TET_BY_TAG).as_bytes(), "twice.msh"),
        "twice.msh",
    );
    reason(
        parse_msh(&binary_tet(tags, TET_BY_TAG), "twice_bin.msh"),
        "twice_bin.msh",
    );
    match parse_msh(&binary_tet(tags, TET_BY_TAG), "twice_bin.msh") {
        Err(SolverError::MeshRead { reason, .. }) => {
            assert_eq!(reason, GmshError::RepeatedNodeTag(1))
        }
        other => panic!("expected RepeatedNodeTag, got {other:?}"),
    }
}

#[test]
fn node_tag_zero_is_refused() {
    // A dense header (1-4) over the listed tags 0 2 3 4, and a sparse one (1-9) over 0 2 3 9.
    let dense = ascii_tet([0, 2, 3, 4], TET_BY_TAG);
    let sparse = dense
        .replace("1 4 1 4\n", "1 4 1 9\n")
        .replace("\n4\n0 0 0", "\n9\n0 0 0")
        .replace("1 1 2 3 4\n", "1 2 2 3 9\n");
    assert!(
        sparse.contains("1 4 1 9\n3 1 0 4\n0\n2\n3\n9\n"),
        "{sparse}"
    );
    for (text, name) in [(dense, "zero.msh"), (sparse, "zero_sparse.msh")] {
        let message = message_of(parse_msh(text.as_bytes(), name), name);
        assert!(message.contains("node tag 0"), "{message}");
        assert!(message.contains("entity 3:1"), "{message}");
    }
    let message = message_of(
        parse_msh(&binary_tet([0, 2, 3, 4], TET_BY_TAG), "zero_bin.msh"),
        "zero_bin.msh",
    );
    assert!(message.contains("node tag 0"), "{message}");
}

#[test]
fn malformed_files_name_the_place() {
    // One element more than the block announces: mshio stops without a location of its own.
    let text = std::fs::read_to_string(path("cube_sparse.msh")).unwrap();
    let extra = text.replace("120 7 21 99 15\n", "120 7 21 99 15\n121 7 21 99 15\n");
    let line = extra.lines().position(|l| l == "121 7 21 99 15").unwrap() + 1;
    let message = message_of(parse_msh(extra.as_bytes(), "extra.msh"), "extra.msh");
    assert!(
        message.contains(&format!("line {line}, in `$Elements`")),
        "{message}"
    );
    assert!(message.contains("`121 7 21 99 15`"), "{message}");
    assert!(message.contains("`$EndElements`"), "{message}");

    // The same in binary: an element's five size_t more than announced, at a known byte.
    let mut binary = binary_tet([1, 2, 3, 4], TET_BY_TAG);
    let at = binary.len() - b"\n$EndElements\n".len();
    let element: Vec<u8> = [2u64, 1, 2, 3, 4]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    binary.splice(at..at, element);
    let message = message_of(parse_msh(&binary, "extra_bin.msh"), "extra_bin.msh");
    assert!(
        message.contains(&format!("byte {at}, in `$Elements`")),
        "{message}"
    );
}

/// The hint of a missing file says where relative paths start: at the folder of the file that
/// names the mesh (the scene or case loaders resolve them so), not the working directory.
#[test]
fn a_missing_file_says_where_relative_paths_start() {
    let message = read_err("no_such_mesh.msh");
    assert!(
        message.contains("folder of the scene or case file"),
        "{message}"
    );
    assert!(!message.contains("working directory"), "{message}");
}
