//! Field output for ParaView: one VTK XML UnstructuredGrid (`.vtu`) file per frame and a
//! `.pvd` collection that gives the frames their times.
//!
//! Files use `version="1.0"` with `header_type="UInt64"` and inline `format="binary"` arrays:
//! each array is base64 of an 8-byte little-endian byte count followed by the raw
//! little-endian values, encoded as one stream (what VTK and meshio write for uncompressed
//! data). Binary keeps files about a third the size of ASCII and loses no precision.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use super::history::{create_parent, write_f64};
use crate::error::{Result, SolverError};

/// VTK's cell type code for a linear tetrahedron.
const VTK_TETRA: u8 = 10;

/// One field value per point or per cell.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldData {
    /// One number per entity (damage, pressure, ...).
    Scalar(Vec<f64>),
    /// Three components per entity (displacement, velocity, force).
    Vector(Vec<[f64; 3]>),
    /// Six components per entity in Voigt order xx, yy, zz, xy, yz, xz, which is also the
    /// order VTK expects for symmetric tensors.
    SymmetricTensor(Vec<[f64; 6]>),
    /// Integer labels (material id, element state, rank).
    Int(Vec<i32>),
}

impl FieldData {
    /// Number of entities (points or cells) the field covers.
    pub fn len(&self) -> usize {
        match self {
            FieldData::Scalar(v) => v.len(),
            FieldData::Vector(v) => v.len(),
            FieldData::SymmetricTensor(v) => v.len(),
            FieldData::Int(v) => v.len(),
        }
    }

    /// True when the field covers no entity.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One snapshot of the mesh and its fields, borrowed from the solver state so that writing
/// a frame copies nothing but the field vectors the caller chose to assemble.
#[derive(Debug, Clone)]
pub struct FieldFrame<'a> {
    /// Simulated time of the snapshot in s; stored in the file as `TimeValue` and in the PVD.
    pub time: f64,
    /// Current (deformed) positions, so ParaView shows the deformed shape without a warp filter.
    pub points: &'a [Vector3<f64>],
    /// Node indices of each tetrahedron, in the solver's positive-volume order (same as VTK's).
    pub tets: &'a [[u32; 4]],
    /// Index of `tets[0]` among the frame's cells: 0 where `tets` holds every cell; a rank's
    /// first element where it holds that rank's elements only (then only pieces of those
    /// cells are written, [`crate::output::pieces::frame_piece`]).
    pub first_cell: usize,
    /// Named fields with one value per point.
    pub point_data: Vec<(String, FieldData)>,
    /// Named fields with one value per tetrahedron.
    pub cell_data: Vec<(String, FieldData)>,
}

impl FieldFrame<'_> {
    /// The cell field called `name`, if the frame has one.
    pub fn cell_field(&self, name: &str) -> Option<&FieldData> {
        self.cell_data
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, field)| field)
    }
}

/// Writes one frame as a `.vtu` file, creating parent directories.
///
/// The frame is checked first, so a malformed frame (a field of the wrong length, a tet
/// pointing past the points, two fields with one name) is an error and leaves no file behind.
pub fn write_vtu(path: &Path, frame: &FieldFrame) -> Result<()> {
    check_frame(frame)?;
    create_parent(path)?;
    let io_error = |source| SolverError::Write {
        path: path.to_path_buf(),
        source,
    };
    let file = File::create(path).map_err(io_error)?;
    let mut out = BufWriter::new(file);
    write_vtu_body(&mut out, frame)
        .and_then(|()| out.flush())
        .map_err(io_error)
}

fn check_frame(frame: &FieldFrame) -> Result<()> {
    let n_points = frame.points.len();
    if let Some((tet, node)) = frame.tets.iter().enumerate().find_map(|(i, tet)| {
        tet.iter()
            .find(|&&n| n as usize >= n_points)
            .map(|&n| (i, n))
    }) {
        return Err(SolverError::InvalidScene {
            entity: "output mesh".into(),
            message: format!(
                "tet {tet} refers to point {node} but the frame has {n_points} points"
            ),
        });
    }
    for (kind, fields, expected) in [
        ("point", &frame.point_data, n_points),
        ("cell", &frame.cell_data, frame.tets.len()),
    ] {
        for (i, (name, data)) in fields.iter().enumerate() {
            let invalid = |message: String| SolverError::InvalidScene {
                entity: format!("output field {name}"),
                message,
            };
            if data.len() != expected {
                return Err(invalid(format!(
                    "{kind} field has {} values but the frame has {expected} {kind}s",
                    data.len()
                )));
            }
            if fields[..i].iter().any(|(other, _)| other == name) {
                // ParaView would silently show only one of them.
                return Err(invalid(format!("two {kind} fields share this name")));
            }
        }
    }
    Ok(())
}

fn write_vtu_body(out: &mut impl Write, frame: &FieldFrame) -> std::io::Result<()> {
    writeln!(out, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        out,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(out, "  <UnstructuredGrid>")?;
    // ParaView reads `TimeValue` field data as the time of a lone .vtu opened without the PVD.
    writeln!(out, "    <FieldData>")?;
    write_array(
        out,
        r#"type="Float64" Name="TimeValue" NumberOfTuples="1""#,
        &f64_bytes(std::iter::once(frame.time)),
    )?;
    writeln!(out, "    </FieldData>")?;
    writeln!(
        out,
        r#"    <Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
        frame.points.len(),
        frame.tets.len()
    )?;
    for (section, fields) in [
        ("PointData", &frame.point_data),
        ("CellData", &frame.cell_data),
    ] {
        writeln!(out, "      <{section}>")?;
        for (name, data) in fields {
            write_field(out, name, data)?;
        }
        writeln!(out, "      </{section}>")?;
    }
    writeln!(out, "      <Points>")?;
    write_array(
        out,
        r#"type="Float64" Name="Points" NumberOfComponents="3""#,
        &f64_bytes(frame.points.iter().flat_map(|p| [p.x, p.y, p.z])),
    )?;
    writeln!(out, "      </Points>")?;
    writeln!(out, "      <Cells>")?;
    let connectivity = frame.tets.iter().flatten().map(|&n| i64::from(n));
    write_array(
        out,
        r#"type="Int64" Name="connectivity""#,
        &i64_bytes(connectivity),
    )?;
    let offsets = (1..=frame.tets.len() as i64).map(|i| 4 * i);
    write_array(out, r#"type="Int64" Name="offsets""#, &i64_bytes(offsets))?;
    write_array(
        out,
        r#"type="UInt8" Name="types""#,
        &vec![VTK_TETRA; frame.tets.len()],
    )?;
    writeln!(out, "      </Cells>")?;
    writeln!(out, "    </Piece>")?;
    writeln!(out, "  </UnstructuredGrid>")?;
    writeln!(out, "</VTKFile>")
}

/// The attributes of a field's `DataArray` (type, name, components), which the `.pvtu` of a
/// distributed run repeats for its pieces.
pub(super) fn field_attributes(name: &str, data: &FieldData) -> String {
    let name = escape_xml(name);
    match data {
        FieldData::Scalar(_) => format!(r#"type="Float64" Name="{name}""#),
        FieldData::Vector(_) => format!(r#"type="Float64" Name="{name}" NumberOfComponents="3""#),
        // Named components make ParaView offer the tensor components by their meaning
        // rather than as 0..5.
        FieldData::SymmetricTensor(_) => format!(
            r#"type="Float64" Name="{name}" NumberOfComponents="6" ComponentName0="XX" ComponentName1="YY" ComponentName2="ZZ" ComponentName3="XY" ComponentName4="YZ" ComponentName5="XZ""#
        ),
        FieldData::Int(_) => format!(r#"type="Int32" Name="{name}""#),
    }
}

fn write_field(out: &mut impl Write, name: &str, data: &FieldData) -> std::io::Result<()> {
    let attributes = field_attributes(name, data);
    let bytes = match data {
        FieldData::Scalar(v) => f64_bytes(v.iter().copied()),
        FieldData::Vector(v) => f64_bytes(v.iter().flatten().copied()),
        FieldData::SymmetricTensor(v) => f64_bytes(v.iter().flatten().copied()),
        FieldData::Int(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
    };
    write_array(out, &attributes, &bytes)
}

/// Writes one inline binary `DataArray` element holding `bytes` (already little-endian).
fn write_array(out: &mut impl Write, attributes: &str, bytes: &[u8]) -> std::io::Result<()> {
    let mut block = Vec::with_capacity(8 + bytes.len());
    block.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    block.extend_from_slice(bytes);
    write!(out, r#"        <DataArray {attributes} format="binary">"#)?;
    out.write_all(base64(&block).as_bytes())?;
    writeln!(out, "</DataArray>")
}

fn f64_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_le_bytes).collect()
}

fn i64_bytes(values: impl Iterator<Item = i64>) -> Vec<u8> {
    values.flat_map(i64::to_le_bytes).collect()
}

/// Standard base64 (RFC 4648) with padding, as VTK's inline binary format expects.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let triple = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                text.push(ALPHABET[(triple >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                text.push('=');
            }
        }
    }
    text
}

/// Escapes text for use inside a double-quoted XML attribute.
pub(super) fn escape_xml(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            _ => escaped.push(c),
        }
    }
    escaped
}

/// Writes the frames of one run and keeps a ParaView collection (`.pvd`) of them current.
///
/// Frame `i` goes to `<dir>/<stem>_<i:05>.vtu`. The `.pvd` is rewritten after every frame
/// (through a temporary file and a rename), so a run that stops early, even by a crash
/// mid-write, still leaves a collection that opens and lists every finished frame.
#[derive(Debug)]
pub struct PvdWriter {
    dir: PathBuf,
    stem: String,
    /// Time and file name (relative to `dir`) of each frame written so far.
    frames: Vec<(f64, String)>,
}

impl PvdWriter {
    /// Creates `dir` if needed and writes an empty `<stem>.pvd`, replacing any collection
    /// left there by an earlier run so it cannot be mistaken for this one.
    pub fn new(dir: &Path, stem: &str) -> Result<Self> {
        let writer = Self {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            frames: Vec::new(),
        };
        std::fs::create_dir_all(dir).map_err(|source| SolverError::Write {
            path: dir.to_path_buf(),
            source,
        })?;
        writer.write_pvd()?;
        Ok(writer)
    }

    /// Writes `frame` as the next `.vtu` file, updates the collection and returns the path of
    /// the `.vtu` file.
    pub fn write_frame(&mut self, frame: &FieldFrame) -> Result<PathBuf> {
        let file_name = format!("{}_{:05}.vtu", self.stem, self.frames.len());
        let path = self.dir.join(&file_name);
        write_vtu(&path, frame)?;
        self.add_file(frame.time, file_name)?;
        Ok(path)
    }

    /// Lists `file_name` (relative to the folder, written by the caller: a `.pvtu` of the pieces
    /// of a distributed run) as the next frame, at `time`, and updates the collection.
    pub fn add_file(&mut self, time: f64, file_name: String) -> Result<()> {
        self.frames.push((time, file_name));
        self.write_pvd()
    }

    /// Number of frames written so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Path of the collection file, for logs and reports.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(format!("{}.pvd", self.stem))
    }

    fn write_pvd(&self) -> Result<()> {
        let mut text = String::from(concat!(
            "<?xml version=\"1.0\"?>\n",
            "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n",
            "  <Collection>\n",
        ));
        for (time, file) in &self.frames {
            text.push_str("    <DataSet timestep=\"");
            write_f64(&mut text, *time);
            text.push_str(&format!(
                "\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                escape_xml(file)
            ));
        }
        text.push_str("  </Collection>\n</VTKFile>\n");

        let path = self.pvd_path();
        let temporary = self.dir.join(format!("{}.pvd.tmp", self.stem));
        let io_error = |source| SolverError::Write {
            path: path.clone(),
            source,
        };
        std::fs::write(&temporary, text).map_err(io_error)?;
        std::fs::rename(&temporary, &path).map_err(io_error)
    }
}

#[cfg(test)]
mod tests {
    use super::{base64, FieldData, FieldFrame};

    #[test]
    fn cell_fields_are_found_by_name() {
        let frame = FieldFrame {
            time: 0.0,
            points: &[],
            tets: &[],
            first_cell: 0,
            point_data: vec![("displacement".into(), FieldData::Scalar(vec![1.0]))],
            cell_data: vec![
                ("body".into(), FieldData::Int(vec![3])),
                ("crack_indicator".into(), FieldData::Scalar(vec![0.5])),
            ],
        };
        assert!(matches!(
            frame.cell_field("crack_indicator"),
            Some(FieldData::Scalar(v)) if v == &[0.5]
        ));
        assert!(matches!(frame.cell_field("body"), Some(FieldData::Int(v)) if v == &[3]));
        // Point fields are not cell fields.
        assert!(frame.cell_field("displacement").is_none());
    }

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, encoded) in cases {
            assert_eq!(base64(plain.as_bytes()), encoded, "input {plain:?}");
        }
    }
}
