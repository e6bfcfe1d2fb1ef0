//! What a beam case records while it runs: the side-view rasters of the crack indicator, the
//! outline, supports, footprint and peak force ([`BeamRecord`]), written and read back as JSON.

use std::ops::Range;
use std::path::{Path, PathBuf};

use impact_solver::problem::Problem;
use impact_solver::scene::{MeshSource, Scene};
use impact_solver::Vector3;
use serde::{Deserialize, Serialize};

use super::plots::{bounds, contact_column, plots, tip_plots};
use super::side_view::{side_view_svg, SIDE_VIEW_WIDTH};
use super::{BEAM_BODY, FILMSTRIP};
use crate::report::section::Page;
use crate::results::{file_safe, CaseResult, PlotData, RecordError};
use impact_solver::analysis::Execution;

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
    /// Whether this is the state the failure mode is judged in at the end of the contact.
    #[serde(default)]
    pub contact_end: bool,
    /// Number of grid cells along the beam (x).
    pub nx: usize,
    /// Number of grid cells over the beam's height (y).
    pub ny: usize,
    /// Row-major, row 0 at the bottom of the beam; NaN (`null`) where no element lies.
    #[serde(deserialize_with = "crate::results::lenient::vec")]
    pub values: Vec<f64>,
}

/// What a beam case records for its pictures (see the module's documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeamRecord {
    /// Id of the case that recorded it.
    pub case: String,
    /// Name of the variant that recorded it.
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
    /// The beam's mesh in words: `box 60 x 12 x 6` (with the mirrored axes of its split, if
    /// any) or the Gmsh file's name.
    #[serde(default)]
    pub mesh: String,
    /// The failure mode judged at the end of the contact, `None` without a contact force
    /// that ends (a static case).
    #[serde(default)]
    pub contact_end: Option<JudgedMode>,
    /// The failure mode of the final state.
    #[serde(default)]
    pub mode_at_end: Option<String>,
    /// The bending-crack tip of the per-layer measure this record had before the two tips,
    /// `[t (s), height reached (m), speed (m/s)]` per snapshot: read back from older results,
    /// no longer written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tip: Vec<[f64; 3]>,
    /// The bending-crack tips (`crate::beam::crack_tip_report`), `None` without a crack-tip
    /// reading (no snapshots, no concrete beam).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack_tip: Option<crate::beam::CrackTipReport>,
    /// Rayleigh wave speed of the beam's concrete `c_R` (m/s).
    #[serde(default)]
    pub rayleigh_speed: Option<f64>,
    /// The elastic column's demand against the rate-enhanced Kupfer envelope
    /// (`crate::beam::column_demand`), for an impact on calibrated concrete; `None` otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column_demand: Option<crate::beam::column_demand::ColumnDemand>,
    /// Why the column's demand is missing from an impact case, if it could not be computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column_demand_error: Option<String>,
}

/// A failure mode judged at the end of the contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JudgedMode {
    /// End of the contact: the contact force below 1 % of its peak (s).
    pub contact_end: f64,
    /// Time of the snapshot judged, the first at or after `contact_end` (s).
    pub time: f64,
    /// The mode's name (`crate::beam::FailureMode::name`).
    pub mode: String,
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
    let volume: f64 = elements.clone().map(|e| problem.model.volume(e)).sum();
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
    let mut plots = plots(scene, problem, run, existing);
    let record = beam_record(case, scene, problem, run, body);
    plots.extend(tip_plots(&record));
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
    let x_range = |xs: &mut dyn Iterator<Item = f64>| {
        xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), x| {
            (a.min(x), z.max(x))
        })
    };
    let mut supports: Vec<[f64; 2]> = problem
        .constraints
        .iter()
        .filter(|c| {
            !c.nodes.is_empty()
                && c.nodes.iter().all(|&n| {
                    b.nodes.contains(&(n as usize)) && model.reference[n as usize].y < lo.y + tol
                })
        })
        .filter_map(|c| {
            let (a, z) = x_range(&mut c.nodes.iter().map(|&n| model.reference[n as usize].x));
            (z - a > tol).then_some([a, z])
        })
        .collect();
    // Bodies wholly under the beam's bottom face (support plates the beam rests on) are
    // supports too, not part of the impactor's footprint.
    let under: Vec<usize> = (0..model.bodies.len())
        .filter(|&o| {
            o != body && {
                let nodes = model.bodies[o].nodes.clone();
                !nodes.is_empty() && model.reference[nodes].iter().all(|p| p.y < lo.y + tol)
            }
        })
        .collect();
    for &o in &under {
        let nodes = model.bodies[o].nodes.clone();
        let (a, z) = x_range(&mut model.reference[nodes].iter().map(|p| p.x));
        supports.push([a, z]);
    }
    let others: Vec<usize> = (0..model.node_count())
        .filter(|n| {
            !b.nodes.contains(n) && !under.iter().any(|&o| model.bodies[o].nodes.contains(n))
        })
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
            contact_end: false,
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
    let judged = judged_modes(problem, run);
    if let Some(j) = &judged.0 {
        if let Some(s) = snapshots.iter().find(|s| s.time == j.time) {
            let at = frames.partition_point(|f| f.time < s.time);
            if frames.get(at).is_some_and(|f| f.time == s.time) {
                frames[at].contact_end = true;
            } else {
                let mut f = frame(&s.u, s.time, false);
                f.contact_end = true;
                frames.insert(at, f);
            }
        }
    }
    frames.push(frame(&run.u, end, true));
    let spec = crate::beam::BeamSpec::default();
    let crack_tip = crate::beam::crack_tip_report(problem, snapshots, &spec).ok();
    let speed = (speed > 0.0 && peak_force_label != "peak load").then_some(speed);
    let demand = speed.map(|_| crate::beam::column_demand::column_demand(scene, problem, &spec));
    BeamRecord {
        case: case.id.clone(),
        variant: case.variant.clone(),
        origin,
        size,
        supports,
        footprint,
        speed,
        peak_force,
        peak_force_label,
        frames,
        mesh: mesh_words(scene),
        contact_end: judged.0,
        mode_at_end: judged.1,
        tip: Vec::new(),
        crack_tip,
        rayleigh_speed: Some(crate::reference::analytic::rayleigh_wave_speed(
            &b.material.constants(),
        )),
        column_demand_error: demand
            .as_ref()
            .and_then(|d| d.as_ref().err().map(ToString::to_string)),
        column_demand: demand.and_then(Result::ok),
    }
}

/// The beam's mesh in words (see [`BeamRecord::mesh`]).
fn mesh_words(scene: &Scene) -> String {
    match scene
        .bodies
        .iter()
        .find(|b| b.name == BEAM_BODY)
        .map(|b| &b.mesh)
    {
        Some(MeshSource::Box(b)) => {
            let [nx, ny, nz] = b.divisions;
            let mirror: Vec<&str> = b.mirror.iter().map(|a| a.name()).collect();
            if mirror.is_empty() {
                format!("box {nx} x {ny} x {nz}")
            } else {
                format!(
                    "box {nx} x {ny} x {nz}, split mirrored about {}",
                    mirror.join(", ")
                )
            }
        }
        Some(MeshSource::Gmsh(path)) => format!(
            "gmsh {}",
            path.file_name().map_or_else(
                || path.display().to_string(),
                |f| f.to_string_lossy().into()
            )
        ),
        None => String::new(),
    }
}

/// The failure mode at the end of the contact (when the contact force ends) and at the end of
/// the run.
fn judged_modes(problem: &Problem, run: &Execution) -> (Option<JudgedMode>, Option<String>) {
    use crate::beam::{failure_mode_judged, BeamSpec, JudgedAt};
    let at_end = failure_mode_judged(problem, &BeamSpec::default(), run)
        .ok()
        .map(|j| j.0.name().to_string());
    let Some(column) = contact_column(problem, run) else {
        return (None, at_end);
    };
    let spec = BeamSpec {
        at: JudgedAt::ContactEnd {
            column: column.clone(),
            fraction: 0.01,
        },
        ..BeamSpec::default()
    };
    let contact = crate::beam::cracks::contact_end(run, &column, 0.01)
        .ok()
        .and_then(|end| {
            let (mode, _, _, time) = failure_mode_judged(problem, &spec, run).ok()?;
            Some(JudgedMode {
                contact_end: end,
                time,
                mode: mode.name().to_string(),
            })
        });
    (contact, at_end)
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

/// The file a case's record is written to, in the case's output folder.
pub fn record_path(case_dir: &Path, variant: &str) -> PathBuf {
    case_dir.join(format!("beam-{}.json", file_safe(variant)))
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

/// The records of a run's cases, read back from its folder: `(case index, record)`; a record
/// file that does not read is left to the page's error block ([`Page::read`]).
pub fn load(page: &Page<'_>) -> Vec<(usize, BeamRecord)> {
    page.results
        .cases
        .iter()
        .enumerate()
        .filter_map(|(i, c)| Some((i, page.read(load_one(page.run_dir, c))?)))
        .collect()
}

/// The record of one case: `None` if it wrote none, an error naming the case and the file if
/// the file does not read as a record.
pub fn load_one(run_dir: &Path, c: &CaseResult) -> Result<Option<BeamRecord>, RecordError> {
    let path = record_path(&crate::results::case_dir(run_dir, &c.id), &c.variant);
    let error = |message: String| RecordError {
        case: c.label(),
        key: path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        message,
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(error(e.to_string())),
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| error(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::super::side_view::{bin_colour, STEPS};
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
            mirror: Vec::new(),
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
            mesh: "box 60 x 12 x 6".into(),
            contact_end: None,
            mode_at_end: None,
            tip: Vec::new(),
            crack_tip: None,
            rayleigh_speed: None,
            column_demand: None,
            column_demand_error: None,
        };
        let frame = SideView {
            time: 1e-3,
            last: true,
            contact_end: false,
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
}
