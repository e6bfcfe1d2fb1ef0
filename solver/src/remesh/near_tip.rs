//! The stress of the remeshed body near a probe (a penetrator's tip), a few steps before and
//! after each remeshing (issue 21; thesis 10.4.2.2 and Fig. 10.24: the transfer of the damage
//! variables causes local stress oscillations that die out within a few steps).
//!
//! At a step, the elements measured are those of the remeshed body whose centroid, at current
//! coordinates, lies within `radius` of the probe's centre (the mean current position of the
//! probe's nodes); of their Cauchy stresses the row gives the largest von Mises stress and the
//! volume-weighted means of the von Mises stress and of the pressure `-tr(sigma)/3` (weights:
//! the model's reference volumes, the volumes at the last remeshing). The rows go to
//! `<stem>_near_tip.csv` ([`NEAR_TIP_CSV_HEADER`]): for remeshing `k` (from 1), the `steps`
//! steps before it (`offset` -steps to -1, on the old mesh; -1 is the state it remeshed), the
//! state right after the transfer (`offset` 0, same time, no step yet: the transferred stress)
//! and the `steps` steps after it (`offset` 1 to steps). A step may belong to two windows (after
//! one remeshing and before the next): it then has a row in each. The rows of a window are
//! written as they are known, so a run that fails keeps them.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::record::RemeshRecord;
use super::watch::{LineFile, NearTipMarks, RemeshWatch, WatchMarks};
use crate::dynamics::{ExplicitSolver, RunState};
use crate::error::{Result, SolverError};
use crate::material::{Deformation, ElementState};
use crate::model::MaterialHistory;
use crate::problem::Problem;

/// What is recorded (`analysis.explicit.remeshing.near_tip`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NearTipSpec {
    /// Name of the probe whose nodes' mean current position is the centre (a scene probe: the
    /// nail's tip).
    pub probe: String,
    /// Radius of the sphere about the centre holding the elements measured (m): a few element
    /// sizes, so that the elements at the tip are in it as the tip moves.
    pub radius: f64,
    /// Steps recorded before and after each remeshing.
    #[serde(default = "default_steps")]
    pub steps: usize,
}

fn default_steps() -> usize {
    20
}

impl NearTipSpec {
    /// The index of the probe in `problem`; an unknown probe or a radius that is not positive
    /// is an error naming the field.
    pub fn probe_index(&self, problem: &Problem) -> Result<usize> {
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.near_tip.radius".into(),
                message: format!("must be positive, got {}", self.radius),
            });
        }
        problem
            .probes
            .iter()
            .position(|p| p.name == self.probe && !p.nodes.is_empty())
            .ok_or_else(|| SolverError::InvalidScene {
                entity: "analysis.explicit.remeshing.near_tip.probe".into(),
                message: format!(
                    "no probe `{}` with nodes in the scene (its probes: {})",
                    self.probe,
                    problem
                        .probes
                        .iter()
                        .map(|p| p.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })
    }
}

/// The header of `<stem>_near_tip.csv`: the remeshing (from 1), the offset in steps from it,
/// the step, time (s), elements measured, largest and mean von Mises stress (Pa), mean
/// pressure (Pa); the means volume-weighted. Without elements (none within the radius) the three
/// stress cells are empty: the mean and largest value of an empty set do not exist, and an empty
/// cell is what CSV readers (and the report's) take as a missing value.
pub const NEAR_TIP_CSV_HEADER: &str =
    "remeshing,offset,step,time,elements,max_von_mises,mean_von_mises,mean_pressure";

/// The stress near the probe at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NearTipRow {
    /// Steps completed.
    pub step: usize,
    /// Time (s).
    pub time: f64,
    /// Elements measured.
    pub elements: usize,
    /// Their largest von Mises stress (Pa); this and the means are NaN without elements.
    pub max_von_mises: f64,
    /// Their volume-weighted mean von Mises stress (Pa).
    pub mean_von_mises: f64,
    /// Their volume-weighted mean pressure `-tr(sigma)/3` (Pa).
    pub mean_pressure: f64,
}

/// The von Mises stress of a Cauchy stress `[xx, yy, zz, xy, yz, xz]` (Pa):
/// `sqrt(((s_xx - s_yy)^2 + (s_yy - s_zz)^2 + (s_zz - s_xx)^2) / 2 + 3 (s_xy^2 + s_yz^2 + s_xz^2))`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, xz] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + xz * xz))
        .sqrt()
}

/// The Cauchy stress `[xx, yy, zz, xy, yz, xz]` (Pa) of element `e` at displacement `u`: that
/// of the last update for a body with a history (`history`), otherwise the material's stress at
/// `F` (with the deformation carried from before a remeshing); `None` where it has none (an
/// inverted element, or no history given).
fn cauchy(
    problem: &Problem,
    history: Option<&MaterialHistory>,
    e: usize,
    u: &[Vector3<f64>],
) -> Option<[f64; 6]> {
    let m = &problem.model;
    let b = m.body_of(e);
    let body = &m.bodies[b];
    let local = e - body.elements.start;
    if body.material.history_len() > 0 {
        let h = history?.bodies.get(b)?.as_ref()?;
        return h.stress(local);
    }
    let f = m.deformation_gradient(e, u);
    let p = body.material.update(
        local,
        &Deformation::at_rest(f - Matrix3::identity()),
        ElementState::stateless(),
    )?;
    let s = p * f.transpose() / f.determinant();
    Some(crate::kinematics::voigt(&(0.5 * (s + s.transpose()))))
}

/// The row of the state `u` (with `history`) at `step` and `time`, for the elements of body
/// `body` within `radius` of the mean current position of probe `probe`'s nodes.
pub fn measure_near_tip(
    problem: &Problem,
    body: usize,
    probe: usize,
    radius: f64,
    (u, history): (&[Vector3<f64>], Option<&MaterialHistory>),
    (step, time): (usize, f64),
) -> NearTipRow {
    let m = &problem.model;
    let x = |n: u32| m.reference[n as usize] + u[n as usize];
    let nodes = &problem.probes[probe].nodes;
    let centre = nodes.iter().fold(Vector3::zeros(), |a, &n| a + x(n)) / nodes.len().max(1) as f64;
    let (mut count, mut max, mut volume, mut vm, mut pressure) = (0, f64::NAN, 0.0, 0.0, 0.0);
    for e in m.bodies[body].elements.clone() {
        let c = m.tets[e].iter().fold(Vector3::zeros(), |a, &n| a + x(n)) / 4.0;
        if (c - centre).norm() > radius {
            continue;
        }
        let Some(s) = cauchy(problem, history, e, u) else {
            continue;
        };
        let v = m.volume(e);
        let mises = von_mises(&s);
        count += 1;
        max = if max.is_nan() { mises } else { max.max(mises) };
        volume += v;
        vm += v * mises;
        pressure -= v * (s[0] + s[1] + s[2]) / 3.0;
    }
    let mean = |sum: f64| {
        if volume > 0.0 {
            sum / volume
        } else {
            f64::NAN
        }
    };
    NearTipRow {
        step,
        time,
        elements: count,
        max_von_mises: max,
        mean_von_mises: mean(vm),
        mean_pressure: mean(pressure),
    }
}

/// One line of the CSV; the stress cells are empty when no element was measured.
fn line(remeshing: usize, offset: i64, r: &NearTipRow) -> String {
    let stresses = if r.elements == 0 {
        ",,".to_string()
    } else {
        format!(
            "{:e},{:e},{:e}",
            r.max_von_mises, r.mean_von_mises, r.mean_pressure
        )
    };
    format!(
        "{remeshing},{offset},{},{:e},{},{stresses}",
        r.step, r.time, r.elements
    )
}

/// The watch that records the rows and writes them (see the module's documentation).
pub struct NearTipStress {
    spec: NearTipSpec,
    body: usize,
    probe: usize,
    file: LineFile,
    /// The last `steps` rows, oldest first.
    recent: VecDeque<NearTipRow>,
    /// The remeshings made.
    remeshings: usize,
    /// Steps still to record after the last remeshing.
    after: usize,
    /// Every line written after the header, for a checkpoint (a few per step about each
    /// remeshing).
    lines: Vec<String>,
}

impl NearTipStress {
    /// The watch of `spec` on body `body` of `problem` (the problem the run starts from),
    /// writing `path`; an unknown probe or a bad radius is an error.
    pub fn new(spec: NearTipSpec, problem: &Problem, body: usize, path: &Path) -> Result<Self> {
        let probe = spec.probe_index(problem)?;
        Ok(Self {
            recent: VecDeque::with_capacity(spec.steps + 1),
            spec,
            body,
            probe,
            file: LineFile::create(path, NEAR_TIP_CSV_HEADER)?,
            remeshings: 0,
            after: 0,
            lines: Vec::new(),
        })
    }

    /// Writes `lines` and keeps them.
    fn write(&mut self, lines: Vec<String>) {
        self.file.write_lines(lines.iter().cloned());
        self.lines.extend(lines);
    }

    /// The file's path, or the first error met writing it.
    pub fn finish(self) -> Result<PathBuf> {
        self.file.finish()
    }
}

impl RemeshWatch for NearTipStress {
    fn step(&mut self, problem: &Problem, solver: &ExplicitSolver<'_>) {
        if self.spec.steps == 0 {
            return;
        }
        let row = measure_near_tip(
            problem,
            self.body,
            self.probe,
            self.spec.radius,
            (&solver.whole(&solver.u), Some(solver.history())),
            (solver.step, solver.time),
        );
        if self.after > 0 {
            let offset = (self.spec.steps + 1 - self.after) as i64;
            self.write(vec![line(self.remeshings, offset, &row)]);
            self.after -= 1;
        }
        if self.recent.len() == self.spec.steps {
            self.recent.pop_front();
        }
        self.recent.push_back(row);
    }

    fn remeshed(&mut self, _record: &RemeshRecord, problem: &Problem, state: &RunState) {
        self.remeshings += 1;
        let k = self.remeshings;
        let n = self.recent.len() as i64;
        let before = self
            .recent
            .drain(..)
            .enumerate()
            .map(|(i, r)| line(k, i as i64 - n, &r));
        let transferred = measure_near_tip(
            problem,
            self.body,
            self.probe,
            self.spec.radius,
            (&state.u, Some(&state.history)),
            (state.step, state.time),
        );
        let lines: Vec<String> = before
            .chain(std::iter::once(line(k, 0, &transferred)))
            .collect();
        self.write(lines);
        self.after = self.spec.steps;
    }

    fn marks(&self, marks: &mut WatchMarks) {
        marks.near_tip = Some(NearTipMarks {
            lines: self.lines.clone(),
            recent: self.recent.iter().copied().collect(),
            after: self.after,
        });
    }

    /// The file rewritten with the lines before the checkpoint, the window of the last steps
    /// and the count of remeshings restored.
    fn resumed(
        &mut self,
        _problem: &Problem,
        _solver: &ExplicitSolver<'_>,
        records: &[RemeshRecord],
        marks: &WatchMarks,
    ) {
        let Some(m) = &marks.near_tip else {
            return;
        };
        self.write(m.lines.clone());
        self.recent = m.recent.iter().copied().collect();
        self.after = m.after;
        self.remeshings = records.len();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{build_problem, Scene};

    /// A 0.1 m elastic cube of 6 tetrahedra with a probe on its corner node at the origin.
    fn cube() -> Problem {
        let scene = Scene::from_yaml(
            "name: cube
bodies:
  - name: block
    mesh: { box: { origin: [0, 0, 0], size: [0.1, 0.1, 0.1], divisions: [1, 1, 1] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
probes:
  - { name: tip, body: block, nodes: { nodes: [0] }, quantity: displacement }
analysis: { explicit: { end_time: 1.0e-6 } }
",
            "near-tip test",
        )
        .expect("the test scene reads");
        build_problem(&scene).expect("the test scene builds")
    }

    /// No centroid lies within 1 mm of the corner (the nearest is about 35 mm away): the row
    /// counts no element, and its line leaves the three stress cells empty, not NaN. With a
    /// radius over the whole cube, every element is measured (at rest: zero stress) and the
    /// cells are numbers.
    #[test]
    fn no_element_within_the_radius_gives_empty_stress_cells() {
        let p = cube();
        let u = vec![Vector3::zeros(); p.model.reference.len()];
        let probe = p
            .probes
            .iter()
            .position(|q| q.name == "tip")
            .expect("probe");
        let none = measure_near_tip(&p, 0, probe, 1e-3, (&u, None), (3, 2e-6));
        assert_eq!(none.elements, 0);
        let text = line(1, -2, &none);
        assert_eq!(text, "1,-2,3,2e-6,0,,,");
        assert!(!text.contains("NaN"), "{text}");
        assert_eq!(
            text.split(',').count(),
            NEAR_TIP_CSV_HEADER.split(',').count()
        );

        let all = measure_near_tip(&p, 0, probe, 1.0, (&u, None), (3, 2e-6));
        assert_eq!(all.elements, p.model.tets.len());
        assert_eq!(
            line(1, -2, &all),
            format!("1,-2,3,2e-6,{},0e0,0e0,0e0", all.elements)
        );
    }
}
