//! Elastic three-point bending of the thesis beam against scikit-fem (issue 8).
//!
//! The case's scene (a linear elastic beam on support strips, the nodes under a loading plate
//! pushed down) is turned into a request for `references/crosscheck/skfem_beam.py`, which solves
//! the same boundary-value problem with quadratic tetrahedra on several meshes and extrapolates
//! to its converged value. The same scene is solved here by our implicit static solver on
//! `implicit_levels` and by our explicit solver (the scene's own analysis, a slow ramp and a
//! damped hold). Compared at the prescribed plate displacement: the deflection at the named
//! points and the support reactions.
//!
//! The plate's and supports' edges, where a prescribed displacement meets a free surface, make
//! the stresses singular like `r^-1/2`, so forces (energy-like) converge only like `h` for linear
//! and quadratic elements alike (scikit-fem's sequence shows order 1.0), while the deflection
//! converges much faster. Our reactions are therefore also judged extrapolated to `h -> 0` at
//! order 1 from our two finest levels, `F = F_2 + (F_2 - F_1) / (r - 1)`.

use std::collections::BTreeMap;
use std::time::Instant;

use impact_solver::model::Problem;
use impact_solver::scene::{
    build_problem, Analysis, Component, MaterialSpec, MeshSource, MotionSpec, Scene, Selector,
};
use impact_solver::statics::{solve_static, StaticSettings};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use super::cache::{cache_path, obtain, Provenance};
use crate::results::RecordTable;

/// The `crosscheck: { elastic_beam: ... }` entry of a case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticBeamSpec {
    /// The cache file of scikit-fem's answer, in `references/crosscheck/cache/`.
    pub cache: String,
    /// The beam: a body of the scene with a box mesh at the origin.
    pub body: String,
    /// Boundary conditions that hold strips of the bottom face vertically.
    pub supports: Vec<String>,
    /// The boundary condition that pushes the strip of the top face under the plate down.
    pub plate: String,
    /// Point constraints that remove the rigid-body motion (they carry no load).
    pub pins: Vec<String>,
    /// Points (mesh nodes at every level) whose vertical deflection is compared.
    pub deflection_points: BTreeMap<String, [f64; 3]>,
    /// scikit-fem's meshes (hexahedral cells per axis, each cut into tetrahedra), coarse to fine.
    pub reference_levels: Vec<[usize; 3]>,
    /// Our implicit static solver's meshes, coarse to fine; the finest is judged.
    pub implicit_levels: Vec<[usize; 3]>,
    /// Our explicit solver's meshes (the scene's analysis), coarse to fine; the finest is judged.
    pub explicit_levels: Vec<[usize; 3]>,
}

/// The values one solution gives at the prescribed plate displacement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeamValues {
    /// Which solution: `scikit-fem P2, converged`, `implicit P1 60x12x6`, ...
    pub label: String,
    /// Vertical deflection at each point (m).
    pub deflection: BTreeMap<String, f64>,
    /// Vertical reaction of each support on the beam (N).
    pub reaction: BTreeMap<String, f64>,
    /// Plate force over plate displacement (N/m).
    pub stiffness: f64,
    pub elements: usize,
    pub seconds: f64,
}

/// A box selector's corners, or an error naming the condition.
fn box_of<'s>(
    scene: &'s Scene,
    name: &str,
) -> Result<([f64; 3], [f64; 3], &'s MotionSpec), String> {
    let c = scene
        .boundary_conditions
        .iter()
        .find(|c| c.name.as_deref() == Some(name))
        .ok_or_else(|| format!("the scene has no boundary condition `{name}`"))?;
    match &c.nodes {
        Selector::Box { min, max } => Ok((*min, *max, &c.motion)),
        other => Err(format!(
            "boundary condition `{name}` selects {other:?}: the elastic-beam cross-check needs a \
             box selector, which the reference script can reproduce"
        )),
    }
}

fn component_index(c: &Component) -> usize {
    *c as usize
}

/// The request to `skfem_beam.py`: the scene's beam, material, supports, plate and pins.
pub fn request(spec: &ElasticBeamSpec, scene: &Scene) -> Result<Value, String> {
    let body = scene
        .bodies
        .iter()
        .find(|b| b.name == spec.body)
        .ok_or_else(|| format!("the scene has no body `{}`", spec.body))?;
    let MeshSource::Box(mesh) = &body.mesh else {
        return Err(format!("body `{}` needs a box mesh", spec.body));
    };
    if mesh.origin != [0.0; 3] {
        return Err(format!(
            "body `{}`: the box must start at the origin (it starts at {:?})",
            spec.body, mesh.origin
        ));
    }
    let MaterialSpec::LinearElastic(c) = &body.material else {
        return Err(format!(
            "body `{}` must be linear elastic: the cross-check is an elastic solution",
            spec.body
        ));
    };
    let [_, depth, width] = mesh.size;
    let strip = |name: &str, y: f64| -> Result<[f64; 2], String> {
        let (min, max, _) = box_of(scene, name)?;
        let full_width = min[2] <= 0.0 && max[2] >= width;
        if min[1] != y || max[1] != y || !full_width {
            return Err(format!(
                "boundary condition `{name}` must select a full-width strip of the face y = {y} \
                 (it selects {min:?} to {max:?})"
            ));
        }
        Ok([min[0], max[0]])
    };
    let supports = spec
        .supports
        .iter()
        .map(|s| {
            let (_, _, motion) = box_of(scene, s)?;
            if !matches!(motion, MotionSpec::Fixed(c) if c == &[Component::Y]) {
                return Err(format!("support `{s}` must be `fixed: [y]`"));
            }
            Ok(json!({"name": s, "x": strip(s, 0.0)?}))
        })
        .collect::<Result<Vec<_>, String>>()?;
    let (_, _, motion) = box_of(scene, &spec.plate)?;
    let MotionSpec::Displacement { components, value } = motion else {
        return Err(format!(
            "plate `{}` must prescribe a displacement",
            spec.plate
        ));
    };
    if components != &[Component::Y] {
        return Err(format!("plate `{}` must move along y only", spec.plate));
    }
    // The static solver evaluates the function at load factor 1; the explicit run ends holding
    // the same value.
    let displacement = value.eval(1.0);
    let pins = spec
        .pins
        .iter()
        .map(|p| {
            let (min, max, motion) = box_of(scene, p)?;
            let MotionSpec::Fixed(components) = motion else {
                return Err(format!("pin `{p}` must be `fixed`"));
            };
            if min != max {
                return Err(format!("pin `{p}` must select one point (min = max)"));
            }
            Ok(json!({"point": min, "components": components.iter().map(component_index).collect::<Vec<_>>()}))
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(json!({
        "size": mesh.size,
        "young": c.youngs_modulus,
        "poisson": c.poisson_ratio,
        "supports": supports,
        "plate": {"name": spec.plate, "x": strip(&spec.plate, depth)?, "displacement": displacement},
        "pins": pins,
        "deflection_points": spec.deflection_points,
        "levels": spec.reference_levels,
    }))
}

/// The node of body `body` at `point`, or an error (deflections are read at nodes).
fn node_at(problem: &Problem, body: &str, point: &[f64; 3]) -> Result<usize, String> {
    let b = problem
        .model
        .bodies
        .iter()
        .find(|b| b.name == body)
        .ok_or_else(|| format!("no body `{body}`"))?;
    b.nodes
        .clone()
        .find(|&n| {
            let x = problem.model.reference[n];
            (0..3).all(|k| (x[k] - point[k]).abs() <= 1e-9)
        })
        .ok_or_else(|| {
            format!("no node of `{body}` at {point:?}: choose mesh divisions that put one there")
        })
}

/// Values of a solution from its plate force, support reactions and point deflections, all at
/// the prescribed plate displacement `delta`.
fn values_of(
    label: String,
    delta: f64,
    plate_force: f64,
    reactions: BTreeMap<String, f64>,
    deflections: BTreeMap<String, f64>,
    elements: usize,
    seconds: f64,
) -> BeamValues {
    BeamValues {
        label,
        deflection: deflections,
        reaction: reactions,
        stiffness: plate_force.abs() / delta.abs(),
        elements,
        seconds,
    }
}

fn constraint_index(problem: &Problem, name: &str) -> Result<usize, String> {
    problem
        .constraints
        .iter()
        .position(|c| c.name == name)
        .ok_or_else(|| format!("no constraint `{name}` in the built problem"))
}

/// The scene with the beam's box divisions replaced.
fn at_level(scene: &Scene, body: &str, cells: [usize; 3]) -> Scene {
    let mut s = scene.clone();
    for b in s.bodies.iter_mut().filter(|b| b.name == body) {
        if let MeshSource::Box(m) = &mut b.mesh {
            m.divisions = cells;
        }
    }
    s
}

/// Our implicit static solution on `cells`.
pub fn implicit(
    spec: &ElasticBeamSpec,
    scene: &Scene,
    cells: [usize; 3],
    delta: f64,
) -> Result<BeamValues, String> {
    let started = Instant::now();
    let mut s = at_level(scene, &spec.body, cells);
    let settings = StaticSettings::default();
    s.analysis = Analysis::Static(settings.clone());
    let problem = build_problem(&s).map_err(|e| e.to_string())?;
    let solution = solve_static(&problem, &settings).map_err(|e| e.to_string())?;
    let y = |name: &str| -> Result<f64, String> {
        Ok(solution.constraint_reaction(&problem, constraint_index(&problem, name)?)[1])
    };
    let reactions = spec
        .supports
        .iter()
        .map(|n| Ok((n.clone(), y(n)?)))
        .collect::<Result<_, String>>()?;
    let deflections = spec
        .deflection_points
        .iter()
        .map(|(k, p)| Ok((k.clone(), solution.u[node_at(&problem, &spec.body, p)?][1])))
        .collect::<Result<_, String>>()?;
    Ok(values_of(
        format!(
            "ours, implicit static, linear tets {}x{}x{}",
            cells[0], cells[1], cells[2]
        ),
        delta,
        y(&spec.plate)?,
        reactions,
        deflections,
        problem.model.element_count(),
        started.elapsed().as_secs_f64(),
    ))
}

/// Our explicit solution on `cells`: the scene's own analysis, read at its end.
pub fn explicit(
    spec: &ElasticBeamSpec,
    scene: &Scene,
    cells: [usize; 3],
    delta: f64,
    time_limit_s: f64,
) -> Result<(BeamValues, Vec<String>), String> {
    let started = Instant::now();
    let scene = &at_level(scene, &spec.body, cells);
    let mut problem = build_problem(scene).map_err(|e| e.to_string())?;
    let options = crate::execute::ExecuteOptions {
        out: None,
        stem: "explicit",
        fields: false,
        time_limit_s: Some(time_limit_s),
        stop: None,
    };
    let run = crate::execute::execute(&mut problem, &scene.analysis, &options, &mut |_| {})
        .map_err(|e| e.to_string())?;
    let history = run
        .history
        .as_ref()
        .ok_or("the explicit run kept no history")?;
    let last = |column: &str| -> Result<f64, String> {
        history
            .column(column)
            .and_then(|c| c.last().copied())
            .ok_or_else(|| format!("the history has no column `{column}`"))
    };
    let reactions = spec
        .supports
        .iter()
        .map(|n| Ok((n.clone(), last(&format!("{n}_reaction_y"))?)))
        .collect::<Result<_, String>>()?;
    let deflections = spec
        .deflection_points
        .iter()
        .map(|(k, p)| Ok((k.clone(), run.u[node_at(&problem, &spec.body, p)?][1])))
        .collect::<Result<_, String>>()?;
    // How far from rest the end is: kinetic energy over the work done.
    let notes = match (history.column("kinetic"), history.column("external_work")) {
        (Some(k), Some(w)) => vec![format!(
            "explicit run on {cells:?}: kinetic energy at the end {:.3e} J, {:.2e} of the external work",
            k.last().unwrap_or(&f64::NAN),
            k.last().unwrap_or(&f64::NAN) / w.last().unwrap_or(&f64::NAN).abs()
        )],
        _ => vec![],
    };
    Ok((
        values_of(
            format!(
                "ours, explicit quasi-static (ramp, damped hold), linear tets {}x{}x{}",
                cells[0], cells[1], cells[2]
            ),
            delta,
            last(&format!("{}_reaction_y", spec.plate))?,
            reactions,
            deflections,
            problem.model.element_count(),
            started.elapsed().as_secs_f64(),
        ),
        notes,
    ))
}

/// The reference values from scikit-fem's answer: its converged values, and one row per level.
pub fn reference_values(
    spec: &ElasticBeamSpec,
    answer: &Value,
    delta: f64,
) -> Result<(BeamValues, Vec<BeamValues>, String), String> {
    let number = |v: &Value, what: &str| {
        v.as_f64()
            .ok_or_else(|| format!("scikit-fem's answer has no number at {what}"))
    };
    let values =
        |v: &Value, label: String, elements: usize, seconds: f64| -> Result<BeamValues, String> {
            let deflections = spec
                .deflection_points
                .keys()
                .map(|k| {
                    Ok((
                        k.clone(),
                        number(&v["deflection"][k], &format!("deflection.{k}"))?,
                    ))
                })
                .collect::<Result<_, String>>()?;
            let reactions = spec
                .supports
                .iter()
                .map(|s| Ok((s.clone(), number(&v[s], s)?)))
                .collect::<Result<_, String>>()?;
            Ok(values_of(
                label,
                delta,
                number(&v["plate_force"], "plate_force")?,
                reactions,
                deflections,
                elements,
                seconds,
            ))
        };
    let converged = &answer["converged"];
    let method = converged["method"].as_str().unwrap_or("").to_string();
    let levels = answer["levels"]
        .as_array()
        .ok_or("scikit-fem's answer has no `levels`")?
        .iter()
        .map(|l| {
            let cells: Vec<u64> = l["cells"]
                .as_array()
                .map(|c| c.iter().filter_map(Value::as_u64).collect())
                .unwrap_or_default();
            let label = format!(
                "scikit-fem, quadratic tets {}",
                cells
                    .iter()
                    .map(u64::to_string)
                    .collect::<Vec<_>>()
                    .join("x")
            );
            values(
                l,
                label,
                l["elements"].as_u64().unwrap_or(0) as usize,
                l["seconds"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect::<Result<Vec<_>, String>>()?;
    let total: f64 = levels.iter().map(|l| l.seconds).sum();
    let elements = levels.last().map_or(0, |l| l.elements);
    Ok((
        values(
            converged,
            "scikit-fem, converged (extrapolated)".into(),
            elements,
            total,
        )?,
        levels,
        method,
    ))
}

/// The two finest of `rows` (solutions on `levels`) extrapolated to `h -> 0` at order 1
/// (Richardson): `v = v_2 + (v_2 - v_1) / (r - 1)` with `r = h_1 / h_2` from the cells along x.
fn extrapolate(what: &str, levels: &[[usize; 3]], rows: &[BeamValues]) -> Option<BeamValues> {
    let n = rows.len();
    if n < 2 {
        return None;
    }
    let (c1, c2) = (levels[n - 2], levels[n - 1]);
    let r = c2[0] as f64 / c1[0] as f64;
    let (a, b) = (&rows[n - 2], &rows[n - 1]);
    let x = |v1: f64, v2: f64| v2 + (v2 - v1) / (r - 1.0);
    let map = |m1: &BTreeMap<String, f64>, m2: &BTreeMap<String, f64>| {
        m2.iter()
            .map(|(k, v2)| (k.clone(), x(m1[k], *v2)))
            .collect()
    };
    Some(BeamValues {
        label: format!("ours, {what}, extrapolated at order 1 from the two finest levels"),
        deflection: map(&a.deflection, &b.deflection),
        reaction: map(&a.reaction, &b.reaction),
        stiffness: x(a.stiffness, b.stiffness),
        elements: b.elements,
        seconds: a.seconds + b.seconds,
    })
}

/// Largest relative difference of `ours` from `reference` over the deflections, and over the
/// reactions.
pub fn differences(ours: &BeamValues, reference: &BeamValues) -> (f64, f64, f64) {
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let max_over = |a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>| {
        b.iter()
            .map(|(k, r)| a.get(k).map_or(f64::INFINITY, |v| rel(*v, *r)))
            .fold(0.0, f64::max)
    };
    (
        max_over(&ours.deflection, &reference.deflection),
        max_over(&ours.reaction, &reference.reaction),
        rel(ours.stiffness, reference.stiffness),
    )
}

/// The table of every solution against the converged reference.
pub fn table(spec: &ElasticBeamSpec, reference: &BeamValues, rows: &[BeamValues]) -> RecordTable {
    let mut head = vec!["solution".to_string(), "elements".into(), "time (s)".into()];
    head.extend(
        spec.deflection_points
            .keys()
            .map(|k| format!("deflection {k} (mm)")),
    );
    head.extend(spec.supports.iter().map(|s| format!("{s} (kN)")));
    head.extend([
        "stiffness (MN/mm)".to_string(),
        "deflection diff.".into(),
        "reaction diff.".into(),
        "stiffness diff.".into(),
    ]);
    let pct = |x: f64| format!("{:+.2} %", 100.0 * x);
    let signed = |a: f64, b: f64| (a - b) / b.abs();
    let worst = |a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>| {
        b.iter()
            .map(|(k, r)| signed(a[k], *r))
            .fold(0.0_f64, |m, d| if d.abs() > m.abs() { d } else { m })
    };
    let body = std::iter::once(reference)
        .chain(rows)
        .map(|v| {
            let mut r = vec![
                v.label.clone(),
                v.elements.to_string(),
                format!("{:.1}", v.seconds),
            ];
            r.extend(v.deflection.values().map(|d| format!("{:.5}", d * 1e3)));
            r.extend(v.reaction.values().map(|f| format!("{:.3}", f * 1e-3)));
            r.push(format!("{:.4}", v.stiffness * 1e-9));
            r.push(pct(worst(&v.deflection, &reference.deflection)));
            r.push(pct(worst(&v.reaction, &reference.reaction)));
            r.push(pct(signed(v.stiffness, reference.stiffness)));
            r
        })
        .collect();
    RecordTable {
        title: "Deflection and support reactions at the prescribed plate displacement".into(),
        head,
        rows: body,
        note: "Differences are signed, relative to scikit-fem's converged value (the first row); \
               for several points or supports the largest in magnitude is shown. Reactions \
               converge like h (the singular edges of the plate and supports), so the coarse \
               levels of both codes are stiffer than the limit; the extrapolated rows remove the \
               leading error term."
            .into(),
    }
}

/// Everything the case measured: the named quantities for its metrics, and the record.
pub struct Outcome {
    pub quantities: BTreeMap<String, f64>,
    pub provenance: Provenance,
    pub setup: Vec<String>,
    pub tables: Vec<RecordTable>,
    pub notes: Vec<String>,
}

/// The quantities this cross-check measures (metric `measure: { crosscheck: <name> }`).
pub const QUANTITIES: [&str; 13] = [
    "explicit_extrapolated_reaction_difference",
    "explicit_extrapolated_deflection_difference",
    "implicit_deflection_difference",
    "implicit_reaction_difference",
    "implicit_stiffness_difference",
    "implicit_extrapolated_reaction_difference",
    "implicit_extrapolated_deflection_difference",
    "explicit_deflection_difference",
    "explicit_reaction_difference",
    "explicit_stiffness_difference",
    "explicit_against_implicit_same_mesh",
    "reference_estimated_error",
    "implicit_coarse_deflection_difference",
];

/// Runs the cross-check: the reference (fresh or cached), our implicit levels and our explicit
/// run.
pub fn run(spec: &ElasticBeamSpec, scene: &Scene, time_limit_s: f64) -> Result<Outcome, String> {
    let req = request(spec, scene)?;
    let delta = req["plate"]["displacement"].as_f64().unwrap_or(f64::NAN);
    let (answer, provenance) = obtain("skfem_beam.py", &req, &cache_path(&spec.cache))?;
    let (reference, reference_levels, method) = reference_values(spec, &answer, delta)?;
    let mut implicit_rows = Vec::new();
    for cells in &spec.implicit_levels {
        implicit_rows.push(implicit(spec, scene, *cells, delta)?);
    }
    let finest = implicit_rows.last().ok_or("implicit_levels is empty")?;
    let mut explicit_rows = Vec::new();
    let mut notes = Vec::new();
    for cells in &spec.explicit_levels {
        let (row, n) = explicit(spec, scene, *cells, delta, time_limit_s)?;
        explicit_rows.push(row);
        notes.extend(n);
    }
    let explicit_row = explicit_rows.last().ok_or("explicit_levels is empty")?;
    let mut q = BTreeMap::new();
    let (d, r, s) = differences(finest, &reference);
    q.insert("implicit_deflection_difference".into(), d);
    q.insert("implicit_reaction_difference".into(), r);
    q.insert("implicit_stiffness_difference".into(), s);
    let (d, r, s) = differences(explicit_row, &reference);
    q.insert("explicit_deflection_difference".into(), d);
    q.insert("explicit_reaction_difference".into(), r);
    q.insert("explicit_stiffness_difference".into(), s);
    // The explicit run against the implicit one on the same mesh: how static the quasi-static
    // run is, free of discretisation error.
    let same_mesh: Vec<f64> = spec
        .explicit_levels
        .iter()
        .zip(&explicit_rows)
        .filter_map(|(c, e)| {
            let i = spec.implicit_levels.iter().position(|x| x == c)?;
            let (d, r, s) = differences(e, &implicit_rows[i]);
            Some(d.max(r).max(s))
        })
        .collect();
    if same_mesh.is_empty() {
        notes.push(
            "no explicit level is among implicit_levels, so \
                    explicit_against_implicit_same_mesh is not measured"
                .into(),
        );
    } else {
        q.insert(
            "explicit_against_implicit_same_mesh".into(),
            same_mesh.iter().cloned().fold(0.0, f64::max),
        );
    }
    let extrapolated = extrapolate("implicit", &spec.implicit_levels, &implicit_rows);
    if let Some(e) = &extrapolated {
        let (d, r, _) = differences(e, &reference);
        q.insert("implicit_extrapolated_deflection_difference".into(), d);
        q.insert("implicit_extrapolated_reaction_difference".into(), r);
    }
    let explicit_extrapolated = extrapolate("explicit", &spec.explicit_levels, &explicit_rows);
    if let Some(e) = &explicit_extrapolated {
        let (d, r, _) = differences(e, &reference);
        q.insert("explicit_extrapolated_deflection_difference".into(), d);
        q.insert("explicit_extrapolated_reaction_difference".into(), r);
    }
    q.insert(
        "implicit_coarse_deflection_difference".into(),
        differences(&implicit_rows[0], &reference).0,
    );
    let estimated = answer["converged"]["estimated_relative_error"]
        .as_object()
        .map(|m| m.values().filter_map(Value::as_f64).fold(0.0, f64::max))
        .unwrap_or(f64::NAN);
    q.insert("reference_estimated_error".into(), estimated);
    let mut rows = reference_levels;
    rows.extend(implicit_rows.iter().cloned());
    rows.extend(extrapolated);
    rows.extend(explicit_rows);
    rows.extend(explicit_extrapolated);
    let setup = vec![
        provenance.line(),
        format!("scikit-fem: {method}"),
        format!(
            "the beam of body `{}`, E = {:.1} GPa, nu = {}, plate displacement {} mm",
            spec.body,
            req["young"].as_f64().unwrap_or(f64::NAN) * 1e-9,
            req["poisson"],
            delta * 1e3,
        ),
    ];
    Ok(Outcome {
        quantities: q,
        provenance,
        setup,
        tables: vec![table(spec, &reference, &rows)],
        notes,
    })
}
