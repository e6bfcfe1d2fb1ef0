//! Field frames of a distributed run (`crate::distributed`): each rank writes its piece of every
//! frame, rank 0 the `.pvtu` that joins them and the `.pvd` of those (VTK's parallel XML formats,
//! which ParaView opens as one data set).

use std::ops::Range;
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use super::observer::RunObserver;
use super::vtu::{escape_xml, field_attributes, write_vtu, FieldData, FieldFrame, PvdWriter};
use crate::error::{Result, SolverError};

/// The observer of one rank: frame `i` of rank `r` goes to `<dir>/<stem>_<i:05>_<r>.vtu` (the
/// rank's elements and the nodes they use), and rank 0 writes `<dir>/<stem>_<i:05>.pvtu` naming
/// the pieces of all ranks and lists it in `<stem>.pvd`.
#[derive(Debug)]
pub struct PieceFrames {
    dir: PathBuf,
    stem: String,
    rank: usize,
    size: usize,
    /// This rank's elements (cells of the whole frame).
    cells: Range<usize>,
    /// Rank 0's collection.
    collection: Option<PvdWriter>,
    frames: usize,
}

impl PieceFrames {
    /// The observer of rank `rank` of `size`, whose elements are `cells`.
    pub fn new(
        dir: &Path,
        stem: &str,
        rank: usize,
        size: usize,
        cells: Range<usize>,
    ) -> Result<Self> {
        let collection = if rank == 0 {
            Some(PvdWriter::new(dir, stem)?)
        } else {
            std::fs::create_dir_all(dir).map_err(|source| SolverError::Write {
                path: dir.to_path_buf(),
                source,
            })?;
            None
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            rank,
            size,
            cells,
            collection,
            frames: 0,
        })
    }

    /// The observer of a resumed run: the frames `listed` (time, `.pvtu` name) were written
    /// before, the next one is numbered after them, and rank 0's collection starts with them.
    pub fn resumed(
        dir: &Path,
        stem: &str,
        rank: usize,
        size: usize,
        cells: Range<usize>,
        listed: &[(f64, String)],
    ) -> Result<Self> {
        let mut frames = Self::new(dir, stem, rank, size, cells)?;
        frames.frames = listed.len();
        if let Some(collection) = frames.collection.as_mut() {
            for (time, file) in listed {
                collection.add_file(*time, file.clone())?;
            }
        }
        Ok(frames)
    }

    /// The name of the next frame's `.pvtu` (the name the collection lists).
    pub fn next_name(&self) -> String {
        format!("{}_{:05}.pvtu", self.stem, self.frames)
    }

    fn piece_name(&self, frame: usize, rank: usize) -> String {
        format!("{}_{frame:05}_{rank}.vtu", self.stem)
    }

    /// The `.pvtu` of frame `index`: the arrays of `frame` (names, types, components) and the
    /// pieces of every rank.
    fn pvtu_text(&self, frame: &FieldFrame, index: usize) -> String {
        let mut text = String::from(concat!(
            "<?xml version=\"1.0\"?>\n",
            "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" ",
            "header_type=\"UInt64\">\n",
            "  <PUnstructuredGrid GhostLevel=\"0\">\n",
        ));
        for (section, fields) in [
            ("PPointData", &frame.point_data),
            ("PCellData", &frame.cell_data),
        ] {
            text.push_str(&format!("    <{section}>\n"));
            for (name, data) in fields {
                text.push_str(&format!(
                    "      <PDataArray {}/>\n",
                    field_attributes(name, data)
                ));
            }
            text.push_str(&format!("    </{section}>\n"));
        }
        text.push_str(concat!(
            "    <PPoints>\n",
            "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n",
            "    </PPoints>\n",
        ));
        for rank in 0..self.size {
            text.push_str(&format!(
                "    <Piece Source=\"{}\"/>\n",
                escape_xml(&self.piece_name(index, rank))
            ));
        }
        text.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
        text
    }
}

/// One rank's part of a frame ([`frame_piece`]), owning what the frame borrows.
#[derive(Debug)]
pub struct FramePiece {
    /// The points the piece's cells use, in ascending order of their index in the frame.
    pub points: Vec<Vector3<f64>>,
    /// The piece's cells over `points`.
    pub tets: Vec<[u32; 4]>,
    /// The point fields at `points`.
    pub point_data: Vec<(String, FieldData)>,
    /// The cell fields of the piece's cells.
    pub cell_data: Vec<(String, FieldData)>,
}

/// The part of `frame` over its cells `cells`: those cells, the points they use (in ascending
/// order of their index in `frame`), and every field restricted to them.
pub fn frame_piece(frame: &FieldFrame, cells: Range<usize>) -> FramePiece {
    let mut new_index = vec![u32::MAX; frame.points.len()];
    let stored = cells.start - frame.first_cell..cells.end - frame.first_cell;
    for tet in &frame.tets[stored.clone()] {
        for &n in tet {
            new_index[n as usize] = 0;
        }
    }
    let mut used = Vec::new();
    for (n, index) in new_index.iter_mut().enumerate() {
        if *index == 0 {
            *index = used.len() as u32;
            used.push(n);
        }
    }
    let points = used.iter().map(|&n| frame.points[n]).collect();
    let tets = frame.tets[stored]
        .iter()
        .map(|tet| tet.map(|n| new_index[n as usize]))
        .collect();
    let pick = |data: &FieldData, at: &mut dyn Iterator<Item = usize>| match data {
        FieldData::Scalar(v) => FieldData::Scalar(at.map(|i| v[i]).collect()),
        FieldData::Vector(v) => FieldData::Vector(at.map(|i| v[i]).collect()),
        FieldData::SymmetricTensor(v) => FieldData::SymmetricTensor(at.map(|i| v[i]).collect()),
        FieldData::Int(v) => FieldData::Int(at.map(|i| v[i]).collect()),
    };
    let point_data = frame
        .point_data
        .iter()
        .map(|(name, data)| (name.clone(), pick(data, &mut used.iter().copied())))
        .collect();
    let cell_data = frame
        .cell_data
        .iter()
        .map(|(name, data)| (name.clone(), pick(data, &mut cells.clone())))
        .collect();
    FramePiece {
        points,
        tets,
        point_data,
        cell_data,
    }
}

impl RunObserver for PieceFrames {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> Result<Option<PathBuf>> {
        let index = self.frames;
        let name = self.next_name();
        self.frames += 1;
        let part = frame_piece(frame, self.cells.clone());
        let piece = FieldFrame {
            time: frame.time,
            points: &part.points,
            tets: &part.tets,
            first_cell: 0,
            point_data: part.point_data,
            cell_data: part.cell_data,
        };
        let path = self.dir.join(self.piece_name(index, self.rank));
        write_vtu(&path, &piece)?;
        if self.collection.is_none() {
            return Ok(Some(path));
        }
        let text = self.pvtu_text(frame, index);
        let pvtu = self.dir.join(&name);
        std::fs::write(&pvtu, text).map_err(|source| SolverError::Write {
            path: pvtu.clone(),
            source,
        })?;
        if let Some(collection) = self.collection.as_mut() {
            collection.add_file(frame.time, name)?;
        }
        Ok(Some(pvtu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two cubes' worth of tetrahedra over 12 points, with point and cell fields that name their
    /// entity.
    fn frame_parts() -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
        let points = (0..12)
            .map(|i| Vector3::new(i as f64, (i % 3) as f64, (i % 4) as f64))
            .collect();
        let tets = vec![
            [0, 1, 2, 3],
            [1, 2, 3, 4],
            [4, 5, 6, 7],
            [2, 6, 8, 9],
            [9, 10, 11, 0],
        ];
        (points, tets)
    }

    #[test]
    fn pieces_hold_their_cells_the_points_those_use_and_every_field_of_both() {
        let (points, tets) = frame_parts();
        let frame = FieldFrame {
            time: 0.5,
            points: &points,
            tets: &tets,
            first_cell: 0,
            point_data: vec![
                ("id".into(), FieldData::Int((0..12).collect())),
                (
                    "u".into(),
                    FieldData::Vector((0..12).map(|i| [i as f64, 0.0, -(i as f64)]).collect()),
                ),
            ],
            cell_data: vec![
                (
                    "e".into(),
                    FieldData::Scalar((0..5).map(|e| 10.0 * e as f64).collect()),
                ),
                (
                    "s".into(),
                    FieldData::SymmetricTensor((0..5).map(|e| [e as f64; 6]).collect()),
                ),
            ],
        };
        let mut covered = 0;
        for cells in [0..2, 2..2, 2..5] {
            let FramePiece {
                points: p,
                tets: t,
                point_data: pd,
                cell_data: cd,
            } = frame_piece(&frame, cells.clone());
            let FieldData::Int(ids) = &pd[0].1 else {
                panic!("the id field stays an integer field")
            };
            // Points in ascending original order, each used by a cell of the piece.
            assert!(ids.windows(2).all(|w| w[0] < w[1]));
            for (k, &id) in ids.iter().enumerate() {
                assert_eq!(p[k], points[id as usize]);
                assert!(
                    t.iter().flatten().any(|&n| n as usize == k),
                    "point {id} unused"
                );
            }
            let FieldData::Vector(u) = &pd[1].1 else {
                panic!("vector field")
            };
            for (k, &id) in ids.iter().enumerate() {
                assert_eq!(u[k], [id as f64, 0.0, -(id as f64)]);
            }
            // Cells map back to the original connectivity, with their own values.
            for (local, global) in cells.clone().enumerate() {
                let back = t[local].map(|n| ids[n as usize] as u32);
                assert_eq!(back, tets[global]);
            }
            assert_eq!(
                cd[0].1,
                FieldData::Scalar(cells.clone().map(|e| 10.0 * e as f64).collect())
            );
            assert_eq!(
                cd[1].1,
                FieldData::SymmetricTensor(cells.clone().map(|e| [e as f64; 6]).collect())
            );
            covered += t.len();
        }
        assert_eq!(covered, tets.len());
    }
}
