//! The output writers produce files that read back to exactly what was written: the CSV
//! through `HistoryTable::read_csv`, the VTK files through a small independent XML and
//! base64 reader below (so a bug in the writer cannot hide behind the same bug in a reader).

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use impact_solver::output::{write_vtu, FieldData, FieldFrame, HistoryTable, PvdWriter};
use impact_solver::{SolverError, Vector3};

/// A fresh directory per test, so parallel tests and earlier runs never share files.
fn temp_dir(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "impact-output-{name}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---------------------------------------------------------------------------------------------
// A minimal XML reader: enough to check nesting and pull out elements, attributes and text.

#[derive(Debug)]
struct Element {
    name: String,
    attributes: HashMap<String, String>,
    text: String,
    children: Vec<Element>,
}

impl Element {
    fn child(&self, name: &str) -> &Element {
        self.children
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("<{}> has no <{name}>", self.name))
    }

    fn attr(&self, name: &str) -> &str {
        self.attributes
            .get(name)
            .unwrap_or_else(|| panic!("<{}> has no attribute {name}", self.name))
    }

    /// The `DataArray` child called `name`.
    fn array(&self, name: &str) -> &Element {
        self.children
            .iter()
            .find(|c| c.name == "DataArray" && c.attr("Name") == name)
            .unwrap_or_else(|| panic!("<{}> has no DataArray {name}", self.name))
    }
}

fn unescape(text: &str) -> String {
    text.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

/// Parses a document, panicking on mismatched or unclosed tags.
fn parse_xml(text: &str) -> Element {
    let mut stack = vec![Element {
        name: "#document".into(),
        attributes: HashMap::new(),
        text: String::new(),
        children: Vec::new(),
    }];
    let mut rest = text;
    while let Some(open) = rest.find('<') {
        stack.last_mut().unwrap().text.push_str(&rest[..open]);
        let close = rest[open..].find('>').expect("unterminated tag") + open;
        let tag = &rest[open + 1..close];
        rest = &rest[close + 1..];
        if tag.starts_with('?') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            let element = stack.pop().unwrap();
            assert_eq!(element.name, name.trim(), "mismatched closing tag");
            stack.last_mut().unwrap().children.push(element);
            continue;
        }
        let self_closing = tag.ends_with('/');
        let tag = tag.trim_end_matches('/');
        let (name, mut attrs) = tag.split_once(char::is_whitespace).unwrap_or((tag, ""));
        let mut attributes = HashMap::new();
        loop {
            attrs = attrs.trim_start();
            if attrs.is_empty() {
                break;
            }
            let (key, after) = attrs.split_once("=\"").expect("attribute without value");
            let (value, after) = after.split_once('"').expect("unterminated attribute");
            assert!(
                attributes
                    .insert(key.trim().to_string(), unescape(value))
                    .is_none(),
                "duplicate attribute {key}"
            );
            attrs = after;
        }
        let element = Element {
            name: name.to_string(),
            attributes,
            text: String::new(),
            children: Vec::new(),
        };
        if self_closing {
            stack.last_mut().unwrap().children.push(element);
        } else {
            stack.push(element);
        }
    }
    assert!(rest.trim().is_empty(), "text after the root element");
    assert_eq!(stack.len(), 1, "unclosed <{}>", stack.last().unwrap().name);
    let mut document = stack.pop().unwrap();
    assert_eq!(document.children.len(), 1, "exactly one root element");
    document.children.pop().unwrap()
}

fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {:?}", c as char),
    };
    let text = text.trim().as_bytes();
    assert_eq!(text.len() % 4, 0, "base64 length is a multiple of 4");
    let mut bytes = Vec::new();
    for quad in text.chunks(4) {
        let padding = quad.iter().filter(|&&c| c == b'=').count();
        let mut word = 0u32;
        for &c in quad {
            word = word << 6 | if c == b'=' { 0 } else { u32::from(value(c)) };
        }
        bytes.extend_from_slice(&word.to_be_bytes()[1..4 - padding]);
    }
    bytes
}

/// The payload of an inline binary array, after checking its UInt64 byte-count header.
fn payload(array: &Element) -> Vec<u8> {
    assert_eq!(array.attr("format"), "binary");
    let bytes = base64_decode(&array.text);
    let (header, data) = bytes.split_at(8);
    let count = u64::from_le_bytes(header.try_into().unwrap());
    assert_eq!(
        count as usize,
        data.len(),
        "header counts the payload bytes"
    );
    data.to_vec()
}

fn as_f64(array: &Element) -> Vec<f64> {
    assert_eq!(array.attr("type"), "Float64");
    payload(array)
        .chunks(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

fn as_i64(array: &Element) -> Vec<i64> {
    assert_eq!(array.attr("type"), "Int64");
    payload(array)
        .chunks(8)
        .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

fn as_i32(array: &Element) -> Vec<i32> {
    assert_eq!(array.attr("type"), "Int32");
    payload(array)
        .chunks(4)
        .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

// ---------------------------------------------------------------------------------------------

#[test]
fn csv_round_trip_is_bitwise() {
    let dir = temp_dir("csv");
    let path = dir.join("nested/energies.csv");
    let mut table = HistoryTable::new(vec![
        "time".into(),
        "kinetic energy".into(),
        "force, \"z\"".into(),
    ]);
    table.push(vec![0.0, 1e-300, -5e-324]);
    table.push(vec![1.0 / 3.0, f64::MAX, -1.234_567_890_123_456_7e-7]);
    table.push(vec![0.1 + 0.2, 6.02214076e23, f64::MIN_POSITIVE]);
    table.push(vec![12345.678, f64::INFINITY, 1e15]);
    table.write_csv(&path).unwrap();

    let read = HistoryTable::read_csv(&path).unwrap();
    assert_eq!(read.columns(), table.columns());
    assert_eq!(read.rows().len(), table.rows().len());
    for (a, b) in read.rows().iter().zip(table.rows()) {
        let bits = |row: &[f64]| row.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b));
    }
    assert_eq!(
        read.column("kinetic energy").unwrap(),
        vec![1e-300, f64::MAX, 6.02214076e23, f64::INFINITY]
    );
    assert!(read.column("missing").is_none());

    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("time,kinetic energy,\"force, \"\"z\"\"\"\n"));
    assert!(
        text.len() < 300,
        "short numbers, not 1e-300 spelled out:\n{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[should_panic(expected = "2 values but the table has 3 columns")]
fn ragged_history_row_panics() {
    let mut table = HistoryTable::new(vec!["a".into(), "b".into(), "c".into()]);
    table.push(vec![1.0, 2.0]);
}

/// Two tets sharing the face 1-2-3.
fn two_tets() -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
    let points = vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(1.0, 1.0, 1.0),
    ];
    (points, vec![[0, 1, 2, 3], [1, 2, 3, 4]])
}

#[test]
fn vtu_holds_every_field_kind_exactly() {
    let (points, tets) = two_tets();
    let displacement: Vec<[f64; 3]> = (0..5)
        .map(|i| [i as f64, -(i as f64) * 1e-300, 0.1 * i as f64])
        .collect();
    let stress = vec![
        [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        [-1e9, 2.5e8, 0.0, 1.0 / 3.0, f64::MIN_POSITIVE, -7.0],
    ];
    let frame = FieldFrame {
        time: 1.25e-6,
        points: &points,
        tets: &tets,
        first_cell: 0,
        point_data: vec![
            (
                "displacement".into(),
                FieldData::Vector(displacement.clone()),
            ),
            (
                "mass".into(),
                FieldData::Scalar(vec![0.5, 1.5, 2.5, 3.5, 4.5]),
            ),
        ],
        cell_data: vec![
            ("stress".into(), FieldData::SymmetricTensor(stress.clone())),
            ("damage <&\"'>".into(), FieldData::Scalar(vec![0.0, 0.75])),
            ("material".into(), FieldData::Int(vec![7, -1])),
        ],
    };
    let dir = temp_dir("vtu");
    let path = dir.join("sub/frame.vtu");
    write_vtu(&path, &frame).unwrap();

    let root = parse_xml(&std::fs::read_to_string(&path).unwrap());
    assert_eq!(root.name, "VTKFile");
    assert_eq!(root.attr("type"), "UnstructuredGrid");
    assert_eq!(root.attr("version"), "1.0");
    assert_eq!(root.attr("header_type"), "UInt64");
    assert_eq!(root.attr("byte_order"), "LittleEndian");
    let grid = root.child("UnstructuredGrid");
    assert_eq!(
        as_f64(grid.child("FieldData").array("TimeValue")),
        [1.25e-6]
    );
    let piece = grid.child("Piece");
    assert_eq!(piece.attr("NumberOfPoints"), "5");
    assert_eq!(piece.attr("NumberOfCells"), "2");

    let coordinates = piece.child("Points").array("Points");
    assert_eq!(coordinates.attr("NumberOfComponents"), "3");
    let expected: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    assert_eq!(as_f64(coordinates), expected);

    let cells = piece.child("Cells");
    assert_eq!(
        as_i64(cells.array("connectivity")),
        [0, 1, 2, 3, 1, 2, 3, 4]
    );
    assert_eq!(as_i64(cells.array("offsets")), [4, 8]);
    let types = cells.array("types");
    assert_eq!(types.attr("type"), "UInt8");
    assert_eq!(payload(types), [10, 10]);

    let point_data = piece.child("PointData");
    let u = point_data.array("displacement");
    assert_eq!(u.attr("NumberOfComponents"), "3");
    let expected: Vec<f64> = displacement.iter().flatten().copied().collect();
    assert_eq!(as_f64(u), expected);
    assert_eq!(as_f64(point_data.array("mass")), [0.5, 1.5, 2.5, 3.5, 4.5]);

    let cell_data = piece.child("CellData");
    let sigma = cell_data.array("stress");
    assert_eq!(sigma.attr("NumberOfComponents"), "6");
    for (i, component) in ["XX", "YY", "ZZ", "XY", "YZ", "XZ"].iter().enumerate() {
        assert_eq!(sigma.attr(&format!("ComponentName{i}")), *component);
    }
    let expected: Vec<f64> = stress.iter().flatten().copied().collect();
    assert_eq!(as_f64(sigma), expected);
    assert_eq!(as_f64(cell_data.array("damage <&\"'>")), [0.0, 0.75]);
    assert_eq!(as_i32(cell_data.array("material")), [7, -1]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn pvd_lists_frames_in_order_with_their_times() {
    let (points, tets) = two_tets();
    let dir = temp_dir("pvd");
    let mut writer = PvdWriter::new(&dir, "impact").unwrap();
    assert_eq!(writer.frame_count(), 0);
    // An empty collection exists from the start, so even a run that writes no frame leaves
    // no stale collection behind.
    let empty = parse_xml(&std::fs::read_to_string(dir.join("impact.pvd")).unwrap());
    assert!(empty.child("Collection").children.is_empty());

    let times = [0.0, 2.5e-7, 1e-6];
    for (i, &time) in times.iter().enumerate() {
        let frame = FieldFrame {
            time,
            points: &points,
            tets: &tets,
            first_cell: 0,
            point_data: vec![("index".into(), FieldData::Int(vec![i as i32; 5]))],
            cell_data: vec![],
        };
        let path = writer.write_frame(&frame).unwrap();
        assert_eq!(path, dir.join(format!("impact_{i:05}.vtu")));
        assert!(path.is_file());
        assert_eq!(writer.frame_count(), i + 1);
    }

    let root = parse_xml(&std::fs::read_to_string(writer.pvd_path()).unwrap());
    assert_eq!(root.attr("type"), "Collection");
    let datasets = &root.child("Collection").children;
    assert_eq!(datasets.len(), 3);
    for (i, (dataset, &time)) in datasets.iter().zip(&times).enumerate() {
        assert_eq!(dataset.name, "DataSet");
        assert_eq!(dataset.attr("timestep").parse::<f64>().unwrap(), time);
        let file = dataset.attr("file");
        assert_eq!(file, format!("impact_{i:05}.vtu"), "relative name");
        let vtu = parse_xml(&std::fs::read_to_string(dir.join(file)).unwrap());
        let time_value = vtu.child("UnstructuredGrid").child("FieldData");
        assert_eq!(as_f64(time_value.array("TimeValue")), [time]);
    }
    assert!(!dir.join("impact.pvd.tmp").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn malformed_frames_are_errors_and_write_nothing() {
    let (points, tets) = two_tets();
    let dir = temp_dir("mismatch");
    let path = dir.join("bad.vtu");
    let frame = |point_data, cell_data| FieldFrame {
        time: 0.0,
        points: &points,
        tets: &tets,
        first_cell: 0,
        point_data,
        cell_data,
    };

    let short = frame(
        vec![("speed".into(), FieldData::Scalar(vec![1.0; 4]))],
        vec![],
    );
    match write_vtu(&path, &short) {
        Err(SolverError::InvalidScene { entity, message }) => {
            assert_eq!(entity, "output field speed");
            assert!(
                message.contains("4 values") && message.contains("5 points"),
                "{message}"
            );
        }
        other => panic!("expected InvalidScene, got {other:?}"),
    }

    let long = frame(
        vec![],
        vec![(
            "stress".into(),
            FieldData::SymmetricTensor(vec![[0.0; 6]; 3]),
        )],
    );
    assert!(matches!(
        write_vtu(&path, &long),
        Err(SolverError::InvalidScene { entity, .. }) if entity == "output field stress"
    ));

    let twice = frame(
        vec![],
        vec![
            ("damage".into(), FieldData::Scalar(vec![0.0; 2])),
            ("damage".into(), FieldData::Int(vec![0; 2])),
        ],
    );
    assert!(write_vtu(&path, &twice).is_err());

    let bad_tets = [[0, 1, 2, 5]];
    let out_of_range = FieldFrame {
        time: 0.0,
        points: &points,
        tets: &bad_tets,
        first_cell: 0,
        point_data: vec![],
        cell_data: vec![],
    };
    assert!(write_vtu(&path, &out_of_range).is_err());
    assert!(!path.exists(), "a rejected frame leaves no file");

    // Through the collection writer the frame is neither written nor counted.
    let mut writer = PvdWriter::new(&dir, "run").unwrap();
    assert!(writer.write_frame(&short).is_err());
    assert_eq!(writer.frame_count(), 0);
    assert!(!dir.join("run_00000.vtu").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The frames of an explicit run carry the crack indicator `eps_1 / (w_cr / L)` of every element
/// and the microplane rate factor (0 on elastic bodies), and the stresses of microplane bodies
/// from their history.
#[test]
fn run_frames_carry_the_crack_indicator_and_the_rate_factor() {
    use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
    use impact_solver::material::{read_microplane_file, IsotropicElastic, MaterialModel};
    use impact_solver::mesh::{box_mesh, BoxSpec};
    use impact_solver::model::Model;
    use impact_solver::problem::Problem;

    let cube = |x: f64| {
        box_mesh(&BoxSpec {
            origin: [x, 0.0, 0.0],
            size: [0.05; 3],
            divisions: [1, 1, 1],
            mirror: Vec::new(),
        })
    };
    let concrete = read_microplane_file(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/materials/thesis-concrete.yaml"),
    )
    .unwrap();
    let steel = IsotropicElastic {
        density: 7800.0,
        youngs_modulus: 200e9,
        poisson_ratio: 0.3,
    };
    let mut model = Model::new(vec![
        (
            "steel".into(),
            cube(0.0),
            MaterialModel::LinearElastic(steel),
        ),
        (
            "concrete".into(),
            cube(0.2),
            MaterialModel::Microplane(concrete),
        ),
    ])
    .unwrap();
    model.crack_indicator.crack_width = 1e-4;
    let mut problem = Problem::new(model);
    // Both cubes stretched along x at 2 /s (free, so they then vibrate): strains of some 1e-5,
    // below the tensile peak of the concrete.
    for (v, x) in problem
        .initial_velocity
        .iter_mut()
        .zip(&problem.model.reference)
    {
        let left = if x.x < 0.1 { 0.0 } else { 0.2 };
        *v = Vector3::new(2.0 * (x.x - left), 0.0, 0.0);
    }
    let dir = temp_dir("run-fields");
    let mut settings = ExplicitSettings::new(1.0);
    settings.max_steps = Some(10);
    let output = OutputSettings {
        dir: Some(dir.clone()),
        stem: "run".into(),
        fields: true,
    };
    let mut solver = ExplicitSolver::new(&problem, settings, output).unwrap();
    let summary = solver.run(&mut |_| {}).unwrap();
    let last = summary
        .written
        .iter()
        .rfind(|p| p.extension().is_some_and(|e| e == "vtu"))
        .unwrap();
    let root = parse_xml(&std::fs::read_to_string(last).unwrap());
    let cells = root
        .child("UnstructuredGrid")
        .child("Piece")
        .child("CellData");
    let eps_1 = as_f64(cells.array("max_principal_strain"));
    let crack = as_f64(cells.array("crack_indicator"));
    let rate = as_f64(cells.array("rate_factor"));
    let stress = as_f64(cells.array("cauchy_stress"));
    let body = as_i32(cells.array("body"));
    assert_eq!(crack.len(), 12);
    for e in 0..12 {
        // Element size (6 V)^(1/3) = 0.05 m for the six tetrahedra of a 5 cm cube.
        let expected = eps_1[e] / (1e-4 / 0.05);
        assert!(eps_1[e] > 1e-6, "element {e} is stretched");
        assert!(
            (crack[e] - expected).abs() <= 1e-12 * expected,
            "element {e}"
        );
        match body[e] {
            0 => assert_eq!(rate[e], 0.0),
            _ => assert!(rate[e] > 1.0 && rate[e] < 2.0, "rate factor {}", rate[e]),
        }
        let xx = stress[6 * e];
        assert!(xx.is_finite() && xx != 0.0, "element {e}: sigma_xx {xx}");
    }
    // The microplane stresses are the history's.
    let history = solver.history().bodies[1].as_ref().unwrap();
    assert_eq!(&stress[36..42], &history.cauchy[0]);
    std::fs::remove_dir_all(&dir).unwrap();
}
