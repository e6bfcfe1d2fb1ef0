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

mod compare;
mod ours;
mod skfem;

use compare::extrapolate;
pub use compare::{differences, table};
pub use ours::{explicit, implicit};
pub use skfem::{reference_values, request};

use std::collections::BTreeMap;

use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::cache::{cache_path, obtain, Provenance};
use super::error::CrosscheckError;
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
    /// Number of elements of the solution's mesh.
    pub elements: usize,
    /// Wall time of the solution (s of real time).
    pub seconds: f64,
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

/// Everything the case measured: the named quantities for its metrics, and the record.
pub struct Outcome {
    /// Each quantity the metrics may measure, by name.
    pub quantities: BTreeMap<String, f64>,
    /// Where the independent answer came from.
    pub provenance: Provenance,
    /// Lines describing the setup of both sides.
    pub setup: Vec<String>,
    /// Tables of the report.
    pub tables: Vec<RecordTable>,
    /// What a reader should know.
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
pub fn run(
    spec: &ElasticBeamSpec,
    scene: &Scene,
    time_limit_s: f64,
) -> Result<Outcome, CrosscheckError> {
    let req = request(spec, scene)?;
    let delta = req["plate"]["displacement"].as_f64().unwrap_or(f64::NAN);
    let (answer, provenance) = obtain("skfem_beam.py", &req, &cache_path(&spec.cache))?;
    let (reference, reference_levels, method) = reference_values(spec, &answer, delta)?;
    let mut implicit_rows = Vec::new();
    for cells in &spec.implicit_levels {
        implicit_rows.push(implicit(spec, scene, *cells, delta)?);
    }
    let finest = implicit_rows.last().ok_or(CrosscheckError::NoLevels {
        levels: "implicit_levels",
    })?;
    let mut explicit_rows = Vec::new();
    let mut notes = Vec::new();
    for cells in &spec.explicit_levels {
        let (row, n) = explicit(spec, scene, *cells, delta, time_limit_s)?;
        explicit_rows.push(row);
        notes.extend(n);
    }
    let explicit_row = explicit_rows.last().ok_or(CrosscheckError::NoLevels {
        levels: "explicit_levels",
    })?;
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
