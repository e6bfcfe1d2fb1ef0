//! Pictures of the beam cases (CATALOGUE "Validation: the thesis' plain concrete beam", issue 7):
//! the crack pattern seen from the side (x-y) at a few instants and at the end, the energy
//! transformation (thesis Figs 10.11-10.14), contact force and support reactions against time,
//! the force components of (6.48) on the beam (Fig. 10.16), and the load-displacement curve of
//! a static case; plus the "Beam: failure modes" comparison of the cases side by side.
//!
//! The pictures need the displacement snapshots, which only exist while the case runs: the
//! runner calls [`record`] once per case, which returns the extra plots (they go into
//! `results.json` with the case's own) and writes a [`BeamRecord`] (the side-view rasters, the
//! outline, supports and impactor footprint) as `beam-<variant>.json` into the case's output
//! folder `<run>/cases/<id>/`, with one SVG file per picture next to it. `impact-vv report`
//! reads the records back from there ([`load`]), so the page stays self-contained.

use std::ops::Range;
use std::path::{Path, PathBuf};

use impact_solver::model::Problem;
use impact_solver::scene::{Analysis, MeshSource, Scene};
use impact_solver::Vector3;
use serde::{Deserialize, Serialize};

pub mod section;

use super::format::{self, num};
use crate::execute::Execution;
use crate::results::{CaseResult, PlotData, RunResults, Series};

/// The body the pictures are of.
pub const BEAM_BODY: &str = "beam";
/// Instants of the filmstrip (s), before the final state.
pub const FILMSTRIP: [f64; 4] = [2.0e-4, 5.0e-4, 1.0e-3, 2.0e-3];
/// Name of the metric whose value and reference the failure-mode comparison shows, if present.
pub const FAILURE_MODE_METRIC: &str = "failure_mode";

/// The crack indicator `eps_1 / eps_r` of the beam seen from the side at one instant: per cell of
/// an `nx` x `ny` grid over the beam's x-y outline, the largest value of the elements whose
/// centroid lies in it (the maximum over the width).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SideView {
    /// Time of the state (s); NaN for the final state of a static analysis.
    #[serde(deserialize_with = "crate::results::lenient::f64")]
    pub time: f64,
    /// Whether this is the final state of the run.
    pub last: bool,
    pub nx: usize,
    pub ny: usize,
    /// Row-major, row 0 at the bottom of the beam; NaN (`null`) where no element lies.
    #[serde(deserialize_with = "crate::results::lenient::vec")]
    pub values: Vec<f64>,
}

/// What a beam case records for its pictures (see the module's documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeamRecord {
    pub case: String,
    pub variant: String,
    /// Lower-left corner of the beam's side view (x, y) (m).
    pub origin: [f64; 2],
    /// Length and height of the beam (m).
    pub size: [f64; 2],
    /// x ranges of the supports (constraints on bottom nodes of the beam) (m).
    pub supports: Vec<[f64; 2]>,
    /// x range of the other bodies (the hammer, a load plate) (m).
    pub footprint: Option<[f64; 2]>,
    /// Largest initial speed of the other bodies (m/s); `None` for a static case.
    pub speed: Option<f64>,
    /// Peak of the contact force (or of the load of a static case), absolute value (N).
    pub peak_force: Option<f64>,
    /// What `peak_force` is: `peak contact force` or `peak load`.
    pub peak_force_label: String,
    /// The filmstrip, the final state last.
    pub frames: Vec<SideView>,
}

/// The largest value per side-view cell of the elements `elements` of the mesh `reference`/`tets`
/// whose centroid falls in it: a grid of `nx` x `ny` cells over `[origin, origin + size]` in
/// x-y, row-major, row 0 at the bottom. Non-finite values are ignored; empty cells are NaN.
pub fn rasterise(
    reference: &[Vector3<f64>],
    tets: &[[u32; 4]],
    elements: Range<usize>,
    values: &[f64],
    origin: [f64; 2],
    size: [f64; 2],
    (nx, ny): (usize, usize),
) -> Vec<f64> {
    let mut grid = vec![f64::NAN; nx * ny];
    if nx == 0 || ny == 0 {
        return grid;
    }
    for e in elements {
        let Some(&v) = values.get(e) else { continue };
        if !v.is_finite() {
            continue;
        }
        let c = tets[e]
            .iter()
            .fold(Vector3::zeros(), |a, &n| a + reference[n as usize])
            / 4.0;
        let cell = |x: f64, lo: f64, len: f64, n: usize| {
            (((x - lo) / len * n as f64).floor().max(0.0) as usize).min(n - 1)
        };
        let i = cell(c.x, origin[0], size[0], nx);
        let j = cell(c.y, origin[1], size[1], ny);
        let slot = &mut grid[j * nx + i];
        *slot = slot.max(v);
    }
    grid
}

/// The side-view grid of a body: the box mesh's divisions when the scene meshes it as a box,
/// otherwise cells of the size of a cube holding six elements.
fn grid_of(scene: &Scene, problem: &Problem, body: usize, size: [f64; 2]) -> (usize, usize) {
    if let Some(spec) = scene.bodies.iter().find(|b| b.name == BEAM_BODY) {
        if let MeshSource::Box(b) = &spec.mesh {
            return (b.divisions[0].max(1), b.divisions[1].max(1));
        }
    }
    let elements = problem.model.bodies[body].elements.clone();
    let volume: f64 = problem.model.volume[elements.clone()].iter().sum();
    let h = (6.0 * volume / elements.len().max(1) as f64).cbrt();
    let n = |l: f64| ((l / h).round() as usize).max(1);
    (n(size[0]), n(size[1]))
}

/// Runs at the end of a case: the extra plots of a beam case (a body `beam` of microplane
/// concrete; empty for other scenes), and its
/// pictures written into `out` (the case's output folder) as `beam-<variant>.json` and SVG
/// files. `existing` are the case's own plots: a generated plot drawing the same curves as one
/// of them is left out.
pub fn record(
    case: &CaseResult,
    scene: &Scene,
    problem: &Problem,
    run: &Execution,
    out: Option<&Path>,
    existing: &[PlotData],
) -> Vec<PlotData> {
    let Some(body) = problem.model.body_index(BEAM_BODY) else {
        return Vec::new();
    };
    // Only the concrete beam of the catalogue: other scenes may call an elastic body `beam`.
    if problem.model.bodies[body].material.name() != "microplane" {
        return Vec::new();
    }
    let plots = plots(scene, problem, run, existing);
    let record = beam_record(case, scene, problem, run, body);
    if let Some(dir) = out {
        // The pictures are a by-product: a folder that cannot be written loses them, not the case.
        let _ = write_record(dir, &record);
    }
    plots
}

/// The record of the beam `body` after `run`.
fn beam_record(
    case: &CaseResult,
    scene: &Scene,
    problem: &Problem,
    run: &Execution,
    body: usize,
) -> BeamRecord {
    let model = &problem.model;
    let b = &model.bodies[body];
    let (lo, hi) = bounds(&model.reference[b.nodes.clone()]);
    let origin = [lo.x, lo.y];
    let size = [hi.x - lo.x, hi.y - lo.y];
    let (nx, ny) = grid_of(scene, problem, body, size);
    let tol = 1e-6 * size[1].max(f64::MIN_POSITIVE);
    let supports = problem
        .constraints
        .iter()
        .filter(|c| {
            !c.nodes.is_empty()
                && c.nodes.iter().all(|&n| {
                    b.nodes.contains(&(n as usize)) && model.reference[n as usize].y < lo.y + tol
                })
        })
        .filter_map(|c| {
            let xs = c.nodes.iter().map(|&n| model.reference[n as usize].x);
            let (a, z) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), x| {
                (a.min(x), z.max(x))
            });
            (z - a > tol).then_some([a, z])
        })
        .collect();
    let others: Vec<usize> = (0..model.node_count())
        .filter(|n| !b.nodes.contains(n))
        .collect();
    let footprint = (!others.is_empty()).then(|| {
        let (a, z) = others
            .iter()
            .map(|&n| model.reference[n].x)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), x| {
                (a.min(x), z.max(x))
            });
        [a, z]
    });
    let speed = others
        .iter()
        .map(|&n| problem.initial_velocity[n].norm())
        .fold(0.0f64, f64::max);
    let (peak_force, peak_force_label) = peak_force(problem, run);
    let frame = |u: &[Vector3<f64>], time: f64, last: bool| {
        let crack = model.element_fields(u).crack_indicator;
        SideView {
            time,
            last,
            nx,
            ny,
            values: rasterise(
                &model.reference,
                &model.tets,
                b.elements.clone(),
                &crack,
                origin,
                size,
                (nx, ny),
            ),
        }
    };
    let snapshots = run.snapshots();
    let end = run.summary.as_ref().map_or(f64::NAN, |s| s.time);
    let mut frames: Vec<SideView> = Vec::new();
    for t in FILMSTRIP {
        if !(t < end) {
            continue;
        }
        let nearest = snapshots
            .iter()
            .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()));
        if let Some(s) = nearest {
            if frames.last().is_none_or(|f| f.time != s.time) {
                frames.push(frame(&s.u, s.time, false));
            }
        }
    }
    frames.push(frame(&run.u, end, true));
    BeamRecord {
        case: case.id.clone(),
        variant: case.variant.clone(),
        origin,
        size,
        supports,
        footprint,
        speed: (speed > 0.0 && peak_force_label != "peak load").then_some(speed),
        peak_force,
        peak_force_label,
        frames,
    }
}

/// Lower and upper corners of a point cloud.
fn bounds(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    points.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// The peak of the first contact pair's force on the beam (`<pair>_force_y`), or of the load
/// of a static case (`load_plate_reaction_y`), with what it is.
fn peak_force(problem: &Problem, run: &Execution) -> (Option<f64>, String) {
    let Some(history) = &run.history else {
        return (None, String::new());
    };
    let peak = |c: &str| {
        history.column(c).map(|y| {
            y.iter()
                .filter(|v| v.is_finite())
                .fold(0.0f64, |a, v| a.max(v.abs()))
        })
    };
    // A static case may press its load plate through contact: its load comes first.
    if let Some(f) = peak("load_plate_reaction_y") {
        return (Some(f), "peak load".into());
    }
    if let Some(f) = contact_column(problem, run).and_then(|c| peak(&c)) {
        return (Some(f), "peak contact force".into());
    }
    (None, String::new())
}

/// The history column of the vertical contact force of the first pair with the beam.
fn contact_column(problem: &Problem, run: &Execution) -> Option<String> {
    let history = run.history.as_ref()?;
    problem
        .contact
        .iter()
        .map(|p| format!("{}_force_y", p.name))
        .chain(std::iter::once("impact_force_y".to_string()))
        .find(|c| history.columns().contains(c))
}

/// The file a case's record is written to, in the case's output folder.
pub fn record_path(case_dir: &Path, variant: &str) -> PathBuf {
    case_dir.join(format!("beam-{}.json", file_safe(variant)))
}

fn file_safe(s: &str) -> String {
    s.replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "_")
}

/// Writes the record and one SVG per frame into `dir`.
fn write_record(dir: &Path, record: &BeamRecord) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let json = serde_json::to_string(record).map_err(std::io::Error::other)?;
    std::fs::write(record_path(dir, &record.variant), json + "\n")?;
    for (i, f) in record.frames.iter().enumerate() {
        let name = if f.last {
            format!("beam-{}-crack-final.svg", file_safe(&record.variant))
        } else {
            format!("beam-{}-crack-{i}.svg", file_safe(&record.variant))
        };
        std::fs::write(dir.join(name), side_view_svg(record, f, SIDE_VIEW_WIDTH))?;
    }
    Ok(())
}

/// The records of a run's cases, read back from its folder: `(case index, record)`.
pub fn load(run_dir: &Path, results: &RunResults) -> Vec<(usize, BeamRecord)> {
    results
        .cases
        .iter()
        .enumerate()
        .filter_map(|(i, c)| Some((i, load_one(run_dir, c)?)))
        .collect()
}

/// The record of one case, if it wrote one.
pub fn load_one(run_dir: &Path, c: &CaseResult) -> Option<BeamRecord> {
    let path = record_path(&crate::results::case_dir(run_dir, &c.id), &c.variant);
    let text = std::fs::read_to_string(path).ok()?;
    serde_json::from_str(&text).ok()
}

// ---------------------------------------------------------------------------------------------
// Plots

/// The plots of a beam case from its history: energy transformation, contact force, support
/// reactions, the force components of (6.48), and a static load-displacement curve.
fn plots(
    scene: &Scene,
    problem: &Problem,
    run: &Execution,
    existing: &[PlotData],
) -> Vec<PlotData> {
    let Some(history) = &run.history else {
        return Vec::new();
    };
    let Some(time) = history.column("time") else {
        return Vec::new();
    };
    let has = |c: &str| history.columns().iter().any(|x| x == c);
    let series = |name: &str, y: Vec<f64>| Series {
        name: name.to_string(),
        x: time.clone(),
        y,
    };
    let column = |c: &str| history.column(c).map(|y| series(c, y));
    let plot = |title: &str, y_label: &str, series: Vec<Series>| PlotData {
        title: title.to_string(),
        x_label: "time (s)".into(),
        y_label: y_label.to_string(),
        series,
        reference_lines: Vec::new(),
        log_log: false,
    };
    let already = |names: &[String]| {
        existing
            .iter()
            .any(|p| names.iter().all(|n| p.series.iter().any(|s| &s.name == n)))
    };
    let mut out = Vec::new();

    // Energy transformation: the kinetic energies of the bodies, the internal and friction work
    // and their sum.
    let mut energy_columns: Vec<String> = problem
        .model
        .bodies
        .iter()
        .map(|b| format!("{}_kinetic", b.name))
        .filter(|c| has(c))
        .collect();
    energy_columns.extend(
        ["internal_work", "friction_work"]
            .into_iter()
            .filter(|c| has(c))
            .map(String::from),
    );
    if energy_columns.len() >= 2 && energy_columns.iter().any(|c| c.ends_with("_kinetic")) {
        let mut curves: Vec<Series> = energy_columns.iter().filter_map(|c| column(c)).collect();
        let total: Vec<f64> = (0..time.len())
            .map(|k| curves.iter().map(|s| s.y[k]).sum())
            .collect();
        let total_name = if has("external_work") {
            "total = sum (external work, e.g. gravity, not included)"
        } else {
            "total = sum"
        };
        curves.push(series(total_name, total));
        out.push(plot(
            "Energy transformation (thesis Figs 10.11-10.14)",
            "energy (J)",
            curves,
        ));
    }

    // Contact force and support reactions.
    let contact = contact_column(problem, run);
    if let Some(c) = &contact {
        if !already(std::slice::from_ref(c)) {
            if let Some(s) = column(c) {
                out.push(plot(
                    "Contact force, beam on impactor (thesis Fig. 10.15)",
                    "force (N)",
                    vec![s],
                ));
            }
        }
    }
    let reactions: Vec<String> = support_names(problem)
        .iter()
        .map(|n| format!("{n}_reaction_y"))
        .filter(|c| has(c))
        .collect();
    if !reactions.is_empty() && !already(&reactions) {
        out.push(plot(
            "Support reactions (thesis Fig. 10.17)",
            "force (N)",
            reactions.iter().filter_map(|c| column(c)).collect(),
        ));
    }

    // The force components of (6.48) on the beam in y.
    let momentum = format!("{BEAM_BODY}_momentum_y");
    if let (Some(c), Some(p)) = (&contact, history.column(&momentum)) {
        if !reactions.is_empty() && time.len() >= 3 {
            let contact_on_beam: Vec<f64> = history
                .column(c)
                .unwrap_or_default()
                .iter()
                .map(|f| -f)
                .collect();
            let inertial = central_differences(&time, &p);
            let internal: Vec<f64> = (0..time.len())
                .map(|k| {
                    -reactions
                        .iter()
                        .filter_map(|r| history.column(r))
                        .map(|y| y[k])
                        .sum::<f64>()
                })
                .collect();
            let damping_coefficient = match &scene.analysis {
                Analysis::Explicit(s) => s.damping,
                Analysis::Release { explicit, .. } => explicit.damping,
                Analysis::Static(_) => 0.0,
            };
            // Mass-proportional damping C = a M: its resultant on the beam is a p.
            let damping: Vec<f64> = p.iter().map(|p| damping_coefficient * p).collect();
            let sum: Vec<f64> = (0..time.len())
                .map(|k| inertial[k] + internal[k] + damping[k])
                .collect();
            let damping_name = if damping_coefficient == 0.0 {
                "damping (none in this scene: 0)".to_string()
            } else {
                format!("damping a p (a = {} 1/s)", num(damping_coefficient))
            };
            // The beam's weight: the components balance contact plus weight.
            let beam = &problem.model.bodies[problem.model.body_index(BEAM_BODY).unwrap_or(0)];
            let beam_mass: f64 = problem.model.mass[beam.nodes.clone()].iter().sum();
            let weight = problem.gravity.map_or(0.0, |g| g.y * beam_mass);
            let sum_name = if weight == 0.0 {
                "inertial + internal + damping".to_string()
            } else {
                format!(
                    "inertial + internal + damping (= contact + weight {} kN)",
                    format::num(weight / 1e3)
                )
            };
            let title = "Forces on the beam in y, (6.48) (thesis Fig. 10.16)";
            out.push(plot(
                title,
                "force (N)",
                vec![
                    series("inertial dp/dt", inertial),
                    series("internal = -sum of reactions", internal),
                    series(&damping_name, damping),
                    series(&sum_name, sum),
                    series("contact on beam", contact_on_beam),
                ],
            ));
        }
    }

    // Static load against mid-span displacement (thesis Fig. 10.5), unless the case draws it.
    if let (Some(load), Some(disp)) = (
        history.column("load_plate_reaction_y"),
        history.column("midspan_y"),
    ) {
        let drawn = existing.iter().any(|p| p.x_label.contains("midspan_y"));
        if !drawn {
            out.push(PlotData {
                title: "Load against mid-span displacement (thesis Fig. 10.5)".into(),
                x_label: "midspan_y (m)".into(),
                y_label: "load_plate_reaction_y (N)".into(),
                series: vec![Series {
                    name: "load plate reaction".into(),
                    x: disp,
                    y: load,
                }],
                reference_lines: Vec::new(),
                log_log: false,
            });
        }
    }
    out
}

/// Names of the constraints that hold bottom nodes of the beam over a stretch of x (the supports,
/// not pins at single nodes).
fn support_names(problem: &Problem) -> Vec<String> {
    let model = &problem.model;
    let Some(body) = model.body_index(BEAM_BODY) else {
        return Vec::new();
    };
    let b = &model.bodies[body];
    let (lo, hi) = bounds(&model.reference[b.nodes.clone()]);
    let tol = 1e-6 * (hi.y - lo.y).max(f64::MIN_POSITIVE);
    problem
        .constraints
        .iter()
        .filter(|c| {
            c.nodes.len() > 1
                && c.nodes.iter().all(|&n| {
                    b.nodes.contains(&(n as usize)) && model.reference[n as usize].y < lo.y + tol
                })
        })
        .map(|c| c.name.clone())
        .collect()
}

/// `dy/dt` by central differences (one-sided at the ends).
pub fn central_differences(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len().min(y.len());
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            if b == a {
                0.0
            } else {
                (y[b] - y[a]) / (t[b] - t[a])
            }
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// The side view as SVG

/// Width of a full-size side view (px).
pub const SIDE_VIEW_WIDTH: u32 = 720;
/// Width of a filmstrip picture (px).
pub const FILMSTRIP_WIDTH: u32 = 340;
/// Number of colour steps from 0 to 1; values of 1 and more get their own colour.
const STEPS: usize = 10;

/// The colour bin of a value: `0..STEPS` for `[0, 1)`, `STEPS` for cracked (1 and more).
fn bin(v: f64) -> Option<usize> {
    if !v.is_finite() {
        return None;
    }
    Some(if v >= 1.0 {
        STEPS
    } else {
        ((v.max(0.0) * STEPS as f64) as usize).min(STEPS - 1)
    })
}

/// The colour of a bin: pale yellow through orange to red below 1, dark crimson for cracked.
fn bin_colour(b: usize) -> String {
    if b >= STEPS {
        return "#5a0016".into();
    }
    let t = (b as f64 + 0.5) / STEPS as f64;
    // Pale grey-yellow (uncracked) -> yellow -> orange -> red.
    let stops = [
        (0.0, [245.0, 245.0, 235.0]),
        (0.35, [254.0, 217.0, 118.0]),
        (0.7, [253.0, 141.0, 60.0]),
        (1.0, [215.0, 25.0, 28.0]),
    ];
    let k = stops.windows(2).position(|w| t <= w[1].0).unwrap_or(2);
    let (a, b) = (stops[k], stops[k + 1]);
    let s = (t - a.0) / (b.0 - a.0);
    let c: Vec<u8> = (0..3)
        .map(|i| (a.1[i] + s * (b.1[i] - a.1[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The title of a frame: the case and the time.
pub fn frame_title(record: &BeamRecord, f: &SideView) -> String {
    let when = if f.time.is_finite() {
        format!("t = {} ms", format::num(1e3 * f.time))
    } else {
        "final state".to_string()
    };
    let case = match record.speed {
        Some(v) => format!("{} ({} m/s)", record.case, format::num(v)),
        None => record.case.clone(),
    };
    if f.last {
        format!("{case}: crack pattern at the end, {when}")
    } else {
        format!("{case}: crack pattern, {when}")
    }
}

/// The side view of one frame as a self-contained SVG `width` px wide: cells coloured by
/// `eps_1/eps_r`, the beam's outline, the supports (triangles below), the impactor's footprint
/// (a bar above), the time in the title and the colour legend below.
pub fn side_view_svg(record: &BeamRecord, f: &SideView, width: u32) -> String {
    let small = width < 500;
    let font = if small { 11.0 } else { 13.0 };
    let margin = if small { 8.0 } else { 16.0 };
    let w = width as f64;
    let scale = (w - 2.0 * margin) / record.size[0].max(f64::MIN_POSITIVE);
    let beam_h = record.size[1] * scale;
    let title_h = font * 2.0;
    let top_band = font * 0.9 + 4.0; // the footprint bar
    let y_top = title_h + top_band;
    let support_h = font * 0.9 + 4.0;
    let legend_y = y_top + beam_h + support_h + 6.0;
    let legend_h = font * 2.6;
    let height = legend_y + legend_h;
    let px = |x: f64| margin + (x - record.origin[0]) * scale;
    // y up: row 0 at the bottom.
    let py = |y: f64| y_top + beam_h - (y - record.origin[1]) * scale;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{h:.0}\" \
         viewBox=\"0 0 {width} {h:.0}\" font-family=\"sans-serif\" font-size=\"{font}\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{cx:.1}\" y=\"{ty:.1}\" text-anchor=\"middle\" font-size=\"{tf:.1}\">{title}</text>\n",
        h = height.ceil(),
        cx = w / 2.0,
        ty = font * 1.3,
        tf = font * 1.1,
        title = format::html(&frame_title(record, f)),
    );
    // Cells, merged along x where neighbours share a colour.
    let (nx, ny) = (f.nx, f.ny);
    let (cw, ch) = (
        record.size[0] / nx.max(1) as f64,
        record.size[1] / ny.max(1) as f64,
    );
    s.push_str("<g shape-rendering=\"crispEdges\">\n");
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            let Some(b) = f.values.get(j * nx + i).copied().and_then(bin) else {
                i += 1;
                continue;
            };
            let mut k = i + 1;
            while k < nx && f.values.get(j * nx + k).copied().and_then(bin) == Some(b) {
                k += 1;
            }
            let (x0, x1) = (
                px(record.origin[0] + i as f64 * cw),
                px(record.origin[0] + k as f64 * cw),
            );
            let (y1, y0) = (
                py(record.origin[1] + j as f64 * ch),
                py(record.origin[1] + (j + 1) as f64 * ch),
            );
            s.push_str(&format!(
                "<rect x=\"{x0:.2}\" y=\"{y0:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{}\"/>\n",
                x1 - x0,
                y1 - y0,
                bin_colour(b)
            ));
            i = k;
        }
    }
    s.push_str("</g>\n");
    // Outline.
    s.push_str(&format!(
        "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"none\" stroke=\"#222\" stroke-width=\"1.2\"/>\n",
        px(record.origin[0]),
        py(record.origin[1] + record.size[1]),
        record.size[0] * scale,
        beam_h
    ));
    // Supports: triangles under the bottom face.
    let bottom = py(record.origin[1]);
    for [a, b] in &record.supports {
        let (xa, xb) = (px(*a), px(*b));
        let mid = 0.5 * (xa + xb);
        let half = (0.5 * (xb - xa)).max(support_h * 0.6);
        s.push_str(&format!(
            "<polygon points=\"{mid:.2},{bottom:.2} {:.2},{:.2} {:.2},{:.2}\" fill=\"#555\"/>\n",
            mid - half,
            bottom + support_h - 2.0,
            mid + half,
            bottom + support_h - 2.0
        ));
    }
    // Impactor footprint: a hatched bar above the top face.
    if let Some([a, b]) = record.footprint {
        let top = py(record.origin[1] + record.size[1]);
        s.push_str(&format!(
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"#4a7bb7\" fill-opacity=\"0.55\" stroke=\"#1f3f73\"><title>impactor footprint</title></rect>\n",
            px(a),
            top - top_band + 2.0,
            (b - a) * scale,
            top_band - 3.0
        ));
    }
    // Legend: the colour steps from 0 to 1 and the cracked colour.
    let lw = (w - 2.0 * margin) * if small { 0.55 } else { 0.45 };
    let step_w = lw / STEPS as f64;
    let sh = font * 0.9;
    for b in 0..STEPS {
        s.push_str(&format!(
            "<rect x=\"{:.2}\" y=\"{legend_y:.2}\" width=\"{:.2}\" height=\"{sh:.2}\" fill=\"{}\"/>\n",
            margin + b as f64 * step_w,
            step_w + 0.3,
            bin_colour(b)
        ));
    }
    s.push_str(&format!(
        "<rect x=\"{margin:.2}\" y=\"{legend_y:.2}\" width=\"{lw:.2}\" height=\"{sh:.2}\" fill=\"none\" stroke=\"#444\" stroke-width=\"0.6\"/>\n"
    ));
    let crack_x = margin + lw + 10.0;
    s.push_str(&format!(
        "<rect x=\"{crack_x:.2}\" y=\"{legend_y:.2}\" width=\"{sh:.2}\" height=\"{sh:.2}\" fill=\"{}\" stroke=\"#444\" stroke-width=\"0.6\"/>\n\
         <text x=\"{:.2}\" y=\"{:.2}\">≥ 1 cracked</text>\n",
        bin_colour(STEPS),
        crack_x + sh + 4.0,
        legend_y + sh * 0.85
    ));
    let label_y = legend_y + sh + font + 1.0;
    s.push_str(&format!(
        "<text x=\"{margin:.2}\" y=\"{label_y:.2}\">0</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\" text-anchor=\"middle\">0.5</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\" text-anchor=\"end\">1</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\">{}</text>\n",
        margin + lw / 2.0,
        margin + lw,
        crack_x,
        if small {
            "eps_1/eps_r"
        } else {
            "eps_1/eps_r, max over the width"
        }
    ));
    s.push_str("</svg>\n");
    s
}

// ---------------------------------------------------------------------------------------------
// Failure modes side by side

/// One case of the failure-mode comparison.
pub struct FailureRow<'a> {
    pub case: &'a CaseResult,
    pub record: &'a BeamRecord,
    /// The `failure_mode` metric, if the case has one.
    pub metric: Option<&'a crate::results::MetricResult>,
}

/// The beam cases of a run in comparison order: static ones (no speed) first, then by speed
/// (then by id). Cases with a refinement sweep are left out: they repeat a velocity on another
/// mesh (their pictures stay in their own section).
pub fn failure_rows<'a>(
    results: &'a RunResults,
    records: &'a [(usize, BeamRecord)],
) -> Vec<FailureRow<'a>> {
    let mut rows: Vec<FailureRow<'a>> = records
        .iter()
        .filter_map(|(i, r)| {
            let case = results.cases.get(*i).filter(|c| c.sweep.is_none())?;
            Some(FailureRow {
                case,
                record: r,
                metric: case.metrics.iter().find(|m| m.name == FAILURE_MODE_METRIC),
            })
        })
        .collect();
    rows.sort_by(|a, b| {
        let key = |r: &FailureRow<'_>| r.record.speed.unwrap_or(-1.0);
        key(a)
            .total_cmp(&key(b))
            .then_with(|| a.case.id.cmp(&b.case.id))
    });
    rows
}

/// Whether the peak contact force rises monotonically with the impact velocity, in words with
/// the numbers; `None` with fewer than two impact cases with a peak force.
pub fn monotonic_statement(rows: &[FailureRow<'_>]) -> Option<String> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.record.speed?, r.record.peak_force?)))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let rising = pts.windows(2).all(|w| w[1].1 > w[0].1);
    let list: Vec<String> = pts
        .iter()
        .map(|(v, f)| format!("{} m/s: {} kN", num(*v), num(f / 1e3)))
        .collect();
    Some(format!(
        "The peak contact force {} with the impact velocity ({}).",
        if rising {
            "rises monotonically"
        } else {
            "does NOT rise monotonically"
        },
        list.join(", ")
    ))
}

/// The metric in words: `measured mixed (2), expected bending (1): fail` where its reference
/// source names the codes (`code 0 none, 1 bending, ...`); otherwise the numbers and the source.
pub fn metric_text(m: &crate::results::MetricResult) -> String {
    let verdict = if m.pass { "pass" } else { "fail" };
    match (
        code_name(&m.reference_source, m.value),
        code_name(&m.reference_source, m.reference),
    ) {
        (Some(v), Some(r)) => format!(
            "measured {v} ({}), expected {r} ({}): {verdict}",
            num(m.value),
            num(m.reference)
        ),
        _ => {
            let mut t = format!(
                "{} (reference {}, {verdict})",
                num(m.value),
                num(m.reference)
            );
            if !m.reference_source.is_empty() {
                t.push_str(&format!("; {}", m.reference_source));
            }
            t
        }
    }
}

/// The name of an integer code `v` where `text` lists the codes as `code 0 none, 1 bending, ...`.
fn code_name(text: &str, v: f64) -> Option<String> {
    if v.fract() != 0.0 || !v.is_finite() {
        return None;
    }
    let list = &text[text.find("code ")? + 5..];
    let list = list.split([')', ';']).next()?;
    list.split(',').find_map(|item| {
        let mut words = item.split_whitespace();
        let code: f64 = words.next()?.parse().ok()?;
        (code == v).then(|| words.collect::<Vec<_>>().join(" "))
    })
}

/// The failure-mode comparison in Markdown for `summary.md`; empty without beam pictures.
pub fn markdown(results: &RunResults, records: &[(usize, BeamRecord)]) -> Option<String> {
    let rows = failure_rows(results, records);
    if rows.is_empty() {
        return None;
    }
    let mut md = String::from(
        "| case | velocity (m/s) | peak force (kN) | failure_mode |\n|---|---:|---:|---|\n",
    );
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            format::markdown_cell(&r.case.id),
            r.record.speed.map_or("static".into(), num),
            r.record.peak_force.map_or("—".into(), |f| num(f / 1e3)),
            r.metric
                .map_or("—".into(), |m| format::markdown_cell(&metric_text(m))),
        ));
    }
    if let Some(s) = monotonic_statement(&rows) {
        md.push_str(&format!("\n{s}\n"));
    }
    Some(md)
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_solver::mesh::{box_mesh, BoxSpec};

    /// A box mesh of 6 x 3 x 2 cells where one column of elements (cells with i = 2, all j and
    /// all k) is cracked: the side view shows exactly that column at >= 1, zeros elsewhere.
    #[test]
    fn one_cracked_column_gives_exactly_that_column() {
        let (nx, ny, nz) = (6, 3, 2);
        let spec = BoxSpec {
            origin: [1.0, -0.5, 0.0],
            size: [3.0, 0.6, 0.3],
            divisions: [nx, ny, nz],
        };
        let mesh = box_mesh(&spec);
        let cell_w = spec.size[0] / nx as f64;
        let values: Vec<f64> = mesh
            .tets
            .iter()
            .map(|t| {
                let c = t
                    .iter()
                    .fold(Vector3::zeros(), |a, &n| a + mesh.nodes[n as usize])
                    / 4.0;
                let i = ((c.x - spec.origin[0]) / cell_w).floor() as usize;
                // Only the front layer of the column (k = 0) is cracked, the back one less: the
                // maximum over the width must be taken.
                let front = c.z < spec.size[2] / nz as f64;
                match (i == 2, front) {
                    (true, true) => 1.5,
                    (true, false) => 0.2,
                    _ => 0.0,
                }
            })
            .collect();
        let grid = rasterise(
            &mesh.nodes,
            &mesh.tets,
            0..mesh.tets.len(),
            &values,
            [spec.origin[0], spec.origin[1]],
            [spec.size[0], spec.size[1]],
            (nx, ny),
        );
        for j in 0..ny {
            for i in 0..nx {
                let v = grid[j * nx + i];
                if i == 2 {
                    assert!(v >= 1.0, "cell ({i}, {j}) = {v}");
                } else {
                    assert_eq!(v, 0.0, "cell ({i}, {j})");
                }
            }
        }
        // The picture paints that column (and only it) in the cracked colour.
        let record = BeamRecord {
            case: "test".into(),
            variant: "default".into(),
            origin: [spec.origin[0], spec.origin[1]],
            size: [spec.size[0], spec.size[1]],
            supports: vec![[1.05, 1.15]],
            footprint: Some([2.35, 2.65]),
            speed: Some(2.0),
            peak_force: Some(1.0e5),
            peak_force_label: "peak contact force".into(),
            frames: Vec::new(),
        };
        let frame = SideView {
            time: 1e-3,
            last: true,
            nx,
            ny,
            values: grid,
        };
        let svg = side_view_svg(&record, &frame, SIDE_VIEW_WIDTH);
        let cracked = format!("fill=\"{}\"", bin_colour(STEPS));
        // One cell per row plus the legend swatch.
        assert_eq!(svg.matches(&cracked).count(), ny + 1, "{svg}");
        assert!(svg.contains("t = 1 ms"));
    }

    #[test]
    fn code_names_are_read_from_the_reference_source() {
        let text =
            "failure mode `bending` (thesis 10.3.2; code 0 none, 1 bending, 2 mixed, 3 shear)";
        assert_eq!(code_name(text, 2.0).as_deref(), Some("mixed"));
        assert_eq!(code_name(text, 1.5), None);
        assert_eq!(code_name("no codes", 1.0), None);
    }

    #[test]
    fn central_differences_of_a_line_are_its_slope() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 3.0, 5.0, 7.0];
        assert_eq!(central_differences(&t, &y), vec![2.0; 4]);
    }
}
