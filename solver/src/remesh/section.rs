//! Pictures of a remeshing run's mesh in a plane (issue 21; thesis Fig. 10.22, the nail's
//! penetration with its progressive mesh adaptations): at the start, after each remeshing and
//! at the end, the boundary triangles of every body that lie in an axis-aligned plane (a
//! symmetry plane of a quarter model, through the impact), at their current coordinates,
//! within a window.
//!
//! A face lies in the plane when its three nodes' reference coordinate along the axis equals
//! the plane's value exactly. On a symmetry plane the nodes are held normal to it, so their
//! current coordinate is their reference one bit for bit, and a remeshing's new nodes there are
//! midpoints of edges in the plane, which keep it exactly; a tolerance would only let in faces
//! that merely come near the plane.
//!
//! Each picture is written when it is taken, as `<stem>_mesh_<k>.json` ([`SectionFrame`],
//! `k` from 0), so a run that fails or is stopped keeps the pictures it took; the picture at
//! the end of a run that fails is of the last step completed.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::record::RemeshRecord;
use super::watch::{RemeshWatch, WatchMarks};
use crate::dynamics::{ExplicitSolver, RunState};
use crate::error::{Result, SolverError};
use crate::mesh::Axis;
use crate::model::Model;
use crate::problem::Problem;

/// Where the pictures are taken (`analysis.explicit.remeshing.section`): the plane
/// `axis = value` and, optionally, a window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// The axis normal to the plane.
    pub axis: Axis,
    /// The plane's coordinate along `axis` (m); 0 by default.
    #[serde(default)]
    pub value: f64,
    /// Lower and upper corners of a box in current coordinates (m): only the triangles with a
    /// node inside it are kept, and the picture shows the box's extent in the plane. None: the
    /// whole plane.
    #[serde(default)]
    pub window: Option<[[f64; 3]; 2]>,
}

impl SectionSpec {
    /// The coordinates a picture is drawn in, horizontal then vertical: `z, y` on a plane normal
    /// to x, `x, z` normal to y, `x, y` normal to z (y, the usual up, stays vertical where it
    /// can).
    pub fn drawing_axes(&self) -> [Axis; 2] {
        match self.axis {
            Axis::X => [Axis::Z, Axis::Y],
            Axis::Y => [Axis::X, Axis::Z],
            Axis::Z => [Axis::X, Axis::Y],
        }
    }

    /// A window whose lower corner is not below its upper one on every axis, or a value that is
    /// not finite, is an error naming the field.
    pub fn check(&self) -> Result<()> {
        let invalid = |field: &str, message: String| SolverError::InvalidScene {
            entity: format!("analysis.explicit.remeshing.section.{field}"),
            message,
        };
        if !self.value.is_finite() {
            return Err(invalid(
                "value",
                format!("must be finite, got {}", self.value),
            ));
        }
        if let Some([lo, hi]) = self.window {
            if (0..3).any(|i| !(lo[i] <= hi[i])) {
                return Err(invalid(
                    "window",
                    format!(
                        "is [lower corner, upper corner]: {lo:?} is not below {hi:?} on every axis"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Index of an axis in a coordinate vector.
fn index(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

/// One body's triangles in a picture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionBody {
    /// The body's name.
    pub name: String,
    /// Whether it is the body that is remeshed.
    pub remeshed: bool,
    /// Its number of elements (all of them, not only those in the picture).
    pub elements: usize,
    /// Its boundary triangles in the plane and the window, at current coordinates, in the
    /// drawing axes: `[h0, v0, h1, v1, h2, v2]` (m).
    pub triangles: Vec<[f64; 6]>,
}

/// One picture (`<stem>_mesh_<k>.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionFrame {
    /// Time of the state shown (s).
    pub time: f64,
    /// Remeshings made before this state.
    pub remeshings: usize,
    /// What the state is: `start`, `remeshing` (right after one) or `end` (of the run, or the
    /// last step completed by a run that failed).
    pub event: String,
    /// The axis normal to the plane.
    pub axis: Axis,
    /// The plane's coordinate (m).
    pub value: f64,
    /// The drawing axes, horizontal then vertical ([`SectionSpec::drawing_axes`]).
    pub drawing_axes: [Axis; 2],
    /// The window's extent in the drawing axes, `[[h_min, v_min], [h_max, v_max]]` (m), if
    /// one was given.
    pub window: Option<[[f64; 2]; 2]>,
    /// Every body with a face in the plane, in model order.
    pub bodies: Vec<SectionBody>,
}

/// The faces of one mesh that lie in the plane, per body, and the nodes they use.
#[derive(Debug, Clone, Default)]
struct PlaneFaces {
    /// Per body: its faces in the plane (global node ids).
    faces: Vec<Vec<[u32; 3]>>,
    /// Every node of those faces, ascending.
    nodes: Vec<u32>,
}

impl PlaneFaces {
    /// The boundary faces of every body of `model` whose three nodes' reference coordinate
    /// along `axis` is `value`. A face in the plane is on the boundary when one element alone
    /// has it; only the elements with three nodes in the plane can have such a face, so only
    /// they are counted.
    fn of(model: &Model, axis: Axis, value: f64) -> Self {
        let a = index(axis);
        let on = |n: u32| model.reference[n as usize][a] == value;
        let mut faces = Vec::with_capacity(model.bodies.len());
        for body in &model.bodies {
            let mut count: std::collections::BTreeMap<[u32; 3], (u32, [u32; 3])> =
                std::collections::BTreeMap::new();
            for tet in &model.tets[body.elements.clone()] {
                if tet.iter().filter(|&&n| on(n)).count() < 3 {
                    continue;
                }
                for face in crate::mesh::TET_FACES {
                    let nodes = face.map(|i| tet[i]);
                    if nodes.iter().all(|&n| on(n)) {
                        count
                            .entry(crate::mesh::face_key(nodes))
                            .or_insert((0, nodes))
                            .0 += 1;
                    }
                }
            }
            faces.push(
                count
                    .into_values()
                    .filter(|(c, _)| *c == 1)
                    .map(|(_, f)| f)
                    .collect(),
            );
        }
        let mut nodes: Vec<u32> = faces.iter().flatten().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        Self { faces, nodes }
    }
}

/// The watch that takes the pictures and writes them into a folder (see the module's
/// documentation).
pub struct SectionPictures {
    spec: SectionSpec,
    /// The remeshed body (index in the model).
    body: usize,
    dir: PathBuf,
    stem: String,
    /// The faces of the current mesh.
    plane: PlaneFaces,
    /// Names and element counts of the current mesh's bodies.
    bodies: Vec<(String, usize)>,
    /// The last step seen: its time and the current coordinates of `plane.nodes`.
    last: Option<(f64, Vec<Vector3<f64>>)>,
    remeshings: usize,
    written: Vec<PathBuf>,
    error: Option<SolverError>,
}

impl SectionPictures {
    /// Pictures of `spec` of the model whose body `body` is remeshed, written into `dir`
    /// (created if needed) as `<stem>_mesh_<k>.json`.
    pub fn new(spec: SectionSpec, body: usize, dir: &Path, stem: &str) -> Result<Self> {
        spec.check()?;
        std::fs::create_dir_all(dir).map_err(|source| SolverError::Write {
            path: dir.to_path_buf(),
            source,
        })?;
        Ok(Self {
            spec,
            body,
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            plane: PlaneFaces::default(),
            bodies: Vec::new(),
            last: None,
            remeshings: 0,
            written: Vec::new(),
            error: None,
        })
    }

    /// The mesh of `problem` becomes the current one.
    fn set_mesh(&mut self, problem: &Problem) {
        let m = &problem.model;
        self.plane = PlaneFaces::of(m, self.spec.axis, self.spec.value);
        self.bodies = m
            .bodies
            .iter()
            .map(|b| (b.name.clone(), b.elements.len()))
            .collect();
        self.last = None;
    }

    /// The picture of the current mesh with its plane nodes at `x` (aligned with
    /// `plane.nodes`).
    pub fn frame(&self, time: f64, event: &str, x: &[Vector3<f64>]) -> SectionFrame {
        let [h, v] = self.spec.drawing_axes().map(index);
        let at = |n: u32| {
            let k = self.plane.nodes.binary_search(&n).unwrap_or_default();
            x.get(k).copied().unwrap_or_else(Vector3::zeros)
        };
        let inside = |p: &Vector3<f64>| {
            self.spec
                .window
                .is_none_or(|[lo, hi]| (0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i]))
        };
        let bodies = self
            .plane
            .faces
            .iter()
            .zip(&self.bodies)
            .enumerate()
            .filter(|(_, (faces, _))| !faces.is_empty())
            .map(|(b, (faces, (name, elements)))| SectionBody {
                name: name.clone(),
                remeshed: b == self.body,
                elements: *elements,
                triangles: faces
                    .iter()
                    .filter_map(|f| {
                        let p = f.map(at);
                        p.iter()
                            .any(inside)
                            .then(|| [p[0][h], p[0][v], p[1][h], p[1][v], p[2][h], p[2][v]])
                    })
                    .collect(),
            })
            .collect();
        SectionFrame {
            time,
            remeshings: self.remeshings,
            event: event.to_string(),
            axis: self.spec.axis,
            value: self.spec.value,
            drawing_axes: self.spec.drawing_axes(),
            window: self
                .spec
                .window
                .map(|[lo, hi]| [[lo[h], lo[v]], [hi[h], hi[v]]]),
            bodies,
        }
    }

    /// Current coordinates of the plane's nodes at displacement `u` of `model`.
    fn current(&self, model: &Model, u: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        self.plane
            .nodes
            .iter()
            .map(|&n| model.reference[n as usize] + u[n as usize])
            .collect()
    }

    /// Writes `frame` as the next `<stem>_mesh_<k>.json`; a failure is kept for
    /// [`Self::finish`].
    fn write(&mut self, frame: &SectionFrame) {
        if self.error.is_some() {
            return;
        }
        let path = self
            .dir
            .join(format!("{}_mesh_{}.json", self.stem, self.written.len()));
        let text = serde_json::to_string(frame).map_err(std::io::Error::other);
        match text.and_then(|t| std::fs::write(&path, t + "\n")) {
            Ok(()) => self.written.push(path),
            Err(source) => self.error = Some(SolverError::Write { path, source }),
        }
    }

    /// Takes the picture at the end and returns the files written, or the first error met.
    /// `end` is the problem and state a run ended with; `None` for a run that failed, whose
    /// picture is then of the last step completed (none if no step completed since the start
    /// or the last remeshing, whose picture stands for it).
    pub fn finish(mut self, end: Option<(&Problem, &RunState)>) -> Result<Vec<PathBuf>> {
        let frame = match end {
            Some((problem, state)) => {
                self.set_mesh(problem);
                let x = self.current(&problem.model, &state.u);
                Some(self.frame(state.time, "end", &x))
            }
            None => self
                .last
                .as_ref()
                .map(|(time, x)| self.frame(*time, "end", x)),
        };
        if let Some(frame) = frame {
            self.write(&frame);
        }
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.written),
        }
    }
}

impl RemeshWatch for SectionPictures {
    fn start(&mut self, problem: &Problem) {
        self.set_mesh(problem);
        let x = self.current(
            &problem.model,
            &vec![Vector3::zeros(); problem.model.node_count()],
        );
        let frame = self.frame(0.0, "start", &x);
        self.write(&frame);
    }

    fn step(&mut self, problem: &Problem, solver: &ExplicitSolver<'_>) {
        // Every step: the buffer of the last one is refilled, not allocated again.
        let m = &problem.model;
        let (time, x) = self.last.get_or_insert_with(|| (0.0, Vec::new()));
        *time = solver.time;
        x.clear();
        x.extend(
            self.plane
                .nodes
                .iter()
                .map(|&n| m.reference[n as usize] + solver.u[n as usize]),
        );
    }

    fn remeshed(&mut self, _record: &RemeshRecord, problem: &Problem, state: &RunState) {
        self.remeshings += 1;
        self.set_mesh(problem);
        let x = self.current(&problem.model, &state.u);
        let frame = self.frame(state.time, "remeshing", &x);
        self.write(&frame);
    }
    /// The pictures before the checkpoint stay (the start's and one per remeshing, numbered
    /// so); the plane is cut from the current mesh and the last step's positions taken from the
    /// restored solver, as [`Self::step`] left them.
    fn resumed(
        &mut self,
        problem: &Problem,
        solver: &ExplicitSolver<'_>,
        records: &[RemeshRecord],
        _marks: &WatchMarks,
    ) {
        self.remeshings = records.len();
        self.written = (0..=records.len())
            .map(|k| self.dir.join(format!("{}_mesh_{k}.json", self.stem)))
            .collect();
        self.set_mesh(problem);
        self.step(problem, solver);
    }
}
