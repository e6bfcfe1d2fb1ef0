//! The benchmark catalogue: one YAML case per file under `cases/`, strictly parsed.

use std::path::{Path, PathBuf};

use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};

use crate::measure::Measure;
use crate::reference::Reference;

/// How often a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tier {
    /// Seconds: CI and the snapshot tests run these.
    Quick,
    /// The full catalogue, every night.
    Nightly,
    /// Stability and robustness sweeps.
    Stress,
    /// Validation runs too long for the nightly budget (the static beam on an unstructured
    /// mesh, about 15 minutes): run by hand or weekly, `impact-vv run --tier long`.
    Long,
}

impl Tier {
    pub fn name(self) -> &'static str {
        match self {
            Tier::Quick => "quick",
            Tier::Nightly => "nightly",
            Tier::Stress => "stress",
            Tier::Long => "long",
        }
    }

    /// Tiers included when running `self`: nightly includes quick; stress and long are their
    /// own.
    pub fn includes(self, case: Tier) -> bool {
        match self {
            Tier::Quick => case == Tier::Quick,
            Tier::Nightly => matches!(case, Tier::Quick | Tier::Nightly),
            Tier::Stress => case == Tier::Stress,
            Tier::Long => case == Tier::Long,
        }
    }
}

/// A benchmark case: a scene, what to measure, and the reference each measurement must meet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    pub id: String,
    /// One line: what the case checks.
    pub description: String,
    pub tier: Tier,
    #[serde(default)]
    pub tags: Vec<String>,
    /// The scene the case runs. Exactly one of `scene`, `contact_problems` and
    /// `material_point` is given.
    #[serde(default)]
    pub scene: Option<Scene>,
    /// Instead of a scene: a comparison of the contact solvers on stored contact problems
    /// (`crate::contact_compare`); its metrics measure that comparison.
    #[serde(default)]
    pub contact_problems: Option<crate::contact_compare::ContactProblemsSpec>,
    /// Instead of a scene: a virtual experiment on one material point of the microplane
    /// concrete model (`crate::material_point`); its metrics measure that experiment.
    #[serde(default)]
    pub material_point: Option<crate::material_point::MaterialPointSpec>,
    /// A comparison with independent code (`crate::crosscheck`): scikit-fem on the case's
    /// scene, or ipctk on recorded CCD queries; its metrics measure that comparison.
    #[serde(default)]
    pub crosscheck: Option<crate::crosscheck::CrosscheckSpec>,
    #[serde(default)]
    pub sweep: Option<Sweep>,
    /// Solver configurations to compare on the same scene; each runs and is judged on its own.
    /// Empty: the scene's own analysis, reported as variant `default`.
    #[serde(default)]
    pub variants: Vec<Variant>,
    pub metrics: Vec<MetricSpec>,
    #[serde(default)]
    pub plots: Vec<PlotSpec>,
    /// Wall-time limit of one solver run of this case (s).
    #[serde(default)]
    pub time_limit_s: Option<f64>,
    /// Why this case is known to fail today (a model limitation with an open issue). The case
    /// still runs, is judged and is reported as failed; only the exit status of a run ignores its
    /// `Fail` (never an `Error`), so that a nightly job alerts on new failures.
    #[serde(default)]
    pub known_failure: Option<String>,
}

/// A refinement sweep: the case runs once per level; metrics are judged at the last level and
/// their errors give the observed convergence order and a work-precision diagram.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Sweep {
    /// Box divisions of the first body, coarse to fine; the parameter is the cell size along x.
    Mesh(Vec<[usize; 3]>),
    /// Time step as a fraction of the stable estimate (runs above 1 are allowed on purpose).
    TimeStepFactor(Vec<f64>),
    /// Gmsh files, coarse to fine, that replace the mesh of every body read from a Gmsh file;
    /// the parameter is the element size each level states.
    MeshFiles(Vec<MeshLevel>),
}

/// One level of a `mesh_files` sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshLevel {
    /// Relative to the case file.
    pub file: PathBuf,
    /// The element size that characterises the level (m), for example the size where the
    /// solution is resolved (the contact zone).
    pub size: f64,
}

/// A named solver configuration: what replaces the scene's for this variant, the analysis
/// (integrator and its settings), the contact solver of every pair, or both.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    pub name: String,
    #[serde(default)]
    pub analysis: Option<impact_solver::scene::Analysis>,
    /// `gauss_seidel` or `{ conic: { mode: coulomb } }`: the same contact problems, another
    /// algorithm (issue 5).
    #[serde(default)]
    pub contact_solver: Option<impact_solver::scene::ContactSolverSpec>,
}

impl Variant {
    /// The case's scene as this variant runs it.
    pub fn apply(&self, scene: &mut Scene) {
        if let Some(analysis) = &self.analysis {
            scene.analysis = analysis.clone();
        }
        if let Some(solver) = &self.contact_solver {
            for pair in &mut scene.contact {
                pair.solver = solver.clone();
            }
        }
    }
}

/// How far a value may lie from its reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Tolerance {
    /// `|value - reference| <= tolerance`.
    Absolute(f64),
    /// `|value - reference| <= tolerance |reference|`.
    Relative(f64),
    /// `value <= tolerance` (an error measure that must stay small; reference 0).
    AtMost(f64),
    /// `value >= tolerance` (a quantity that must reach a floor; reference the bound).
    AtLeast(f64),
    /// `|value - reference| <= fraction * max |column|` over the run's history: relative to a
    /// scale such as the peak force or the largest energy, for quantities that pass through zero.
    RelativeToPeak { fraction: f64, column: String },
    /// `value >= tolerance * reference` (a quantity that must exceed a multiple of a reference,
    /// e.g. a peak impact force far above the static peak load): the error is
    /// `value / reference`.
    AtLeastRatio(f64),
}

/// One measurement of a case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetricSpec {
    pub name: String,
    #[serde(default)]
    pub unit: String,
    pub measure: Measure,
    /// Required: a metric without a reference fails the case (never skipped).
    #[serde(default)]
    pub reference: Option<Reference>,
    pub tolerance: Tolerance,
}

/// A plot of history columns against time, or against another column (`x_column`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSpec {
    pub title: String,
    /// History columns to draw against time (or against `x_column`).
    pub columns: Vec<String>,
    /// History column on the x axis, e.g. a displacement probe for a load-displacement curve
    /// (thesis Fig. 10.5); default `time`.
    #[serde(default)]
    pub x_column: Option<String>,
    #[serde(default)]
    pub y_label: String,
    /// Draw the reference (and band) of this metric as a horizontal line.
    #[serde(default)]
    pub reference_metric: Option<String>,
    /// Instead of `columns`: the traction-opening curve of a crack band in the run beside the
    /// material point's `sigma(w)` (`crate::band::plot_series`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack_band: Option<crate::band::BandSpec>,
    /// History column subtracted from `x_column`, e.g. the crack mouth opening as the difference
    /// of two probes' displacements (`x_column: mouth_right_x`, `x_minus: mouth_left_x`).
    #[serde(default)]
    pub x_minus: Option<String>,
    /// Factor on the drawn `columns`, e.g. -1 to draw a downward reaction as a positive load.
    #[serde(default)]
    pub y_scale: Option<f64>,
    /// Measured curves drawn beside the computed ones, from published data files.
    #[serde(default)]
    pub reference_curves: Vec<ReferenceCurve>,
}

/// A measured curve from a CSV file (a header line of column names, `#` comment lines), its
/// columns scaled to the plot's units: `x = x_scale * file[x]`, `y = y_scale * file[y]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceCurve {
    /// The file, relative to the case file.
    pub file: PathBuf,
    pub x: String,
    pub y: String,
    #[serde(default = "one")]
    pub x_scale: f64,
    #[serde(default = "one")]
    pub y_scale: f64,
    /// The legend entry.
    pub label: String,
}

fn one() -> f64 {
    1.0
}

impl ReferenceCurve {
    /// Reads the curve's two columns, scaled.
    pub fn read(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        let text = std::fs::read_to_string(&self.file)
            .map_err(|e| format!("cannot read {}: {e}", self.file.display()))?;
        let mut lines = text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'));
        let header: Vec<&str> = lines
            .next()
            .ok_or_else(|| format!("{}: no header line", self.file.display()))?
            .split(',')
            .map(str::trim)
            .collect();
        let column = |name: &str| {
            header
                .iter()
                .position(|h| *h == name)
                .ok_or_else(|| format!("{}: no column `{name}` in {header:?}", self.file.display()))
        };
        let (ix, iy) = (column(&self.x)?, column(&self.y)?);
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for (k, line) in lines.enumerate() {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let value = |i: usize| -> Result<f64, String> {
                fields
                    .get(i)
                    .and_then(|f| f.parse().ok())
                    .ok_or_else(|| format!("{}: bad data row {}", self.file.display(), k + 1))
            };
            xs.push(self.x_scale * value(ix)?);
            ys.push(self.y_scale * value(iy)?);
        }
        Ok((xs, ys))
    }
}

/// A case with the file it came from.
#[derive(Debug, Clone)]
pub struct LoadedCase {
    pub path: PathBuf,
    pub spec: CaseSpec,
}

/// An error in the catalogue: names the file, the line when known, and the problem.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct CatalogueError {
    pub path: String,
    pub message: String,
}

/// Parses one case file. Mesh paths in its scene are resolved against the file's folder.
pub fn load_case(path: &Path) -> Result<LoadedCase, CatalogueError> {
    let fail = |message: String| CatalogueError {
        path: path.display().to_string(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let de = serde_norway::Deserializer::from_str(&text);
    let mut spec: CaseSpec = serde_norway::with::singleton_map_recursive::deserialize(de)
        .map_err(|e| fail(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let resolve = |p: &mut PathBuf| {
        if p.is_relative() {
            *p = base.join(&*p);
        }
    };
    for body in spec.scene.iter_mut().flat_map(|s| s.bodies.iter_mut()) {
        if let impact_solver::scene::MeshSource::Gmsh(p) = &mut body.mesh {
            resolve(p);
        }
        if let impact_solver::scene::MaterialSpec::Microplane(
            impact_solver::scene::MicroplaneSpec { file: Some(p), .. },
        ) = &mut body.material
        {
            resolve(p);
        }
        for p in body
            .regions
            .iter_mut()
            .filter_map(|r| r.material.file_mut())
        {
            resolve(p);
        }
    }
    if let Some(problems) = &mut spec.contact_problems {
        resolve(&mut problems.folder);
    }
    if let Some(mp) = &mut spec.material_point {
        resolve(&mut mp.material);
    }
    for curve in spec
        .plots
        .iter_mut()
        .flat_map(|p| p.reference_curves.iter_mut())
    {
        resolve(&mut curve.file);
        curve.read().map_err(&fail)?;
    }
    crate::material_point::validate(&spec).map_err(fail)?;
    crate::crosscheck::validate(&spec).map_err(fail)?;
    if spec.material_point.is_none() && spec.crosscheck.is_none() {
        crate::contact_compare::case::validate(&spec).map_err(fail)?;
    }
    if let Some(Sweep::MeshFiles(levels)) = &mut spec.sweep {
        levels.iter_mut().for_each(|l| resolve(&mut l.file));
    }
    if spec.metrics.is_empty() {
        return Err(fail(
            "the case has no metrics: every case measures something against a reference".into(),
        ));
    }
    for v in &spec.variants {
        if spec.variants.iter().filter(|w| w.name == v.name).count() > 1 {
            return Err(fail(format!("variant `{}` appears twice", v.name)));
        }
    }
    for m in &spec.metrics {
        if spec.metrics.iter().filter(|n| n.name == m.name).count() > 1 {
            return Err(fail(format!("metric `{}` appears twice", m.name)));
        }
    }
    Ok(LoadedCase {
        path: path.to_path_buf(),
        spec,
    })
}

/// Every `*.yaml` case under `dir` (recursively, sorted by path), skipping `dir/examples` and
/// `dir/materials` (scenes and material data, not cases). All errors are collected.
pub fn load_catalogue(dir: &Path) -> Result<Vec<LoadedCase>, Vec<CatalogueError>> {
    let mut files = Vec::new();
    collect_yaml(dir, dir, &mut files);
    files.sort();
    let mut cases = Vec::new();
    let mut errors = Vec::new();
    for f in files {
        match load_case(&f) {
            Ok(c) => cases.push(c),
            Err(e) => errors.push(e),
        }
    }
    for (i, c) in cases.iter().enumerate() {
        if let Some(other) = cases[..i].iter().find(|o| o.spec.id == c.spec.id) {
            errors.push(CatalogueError {
                path: c.path.display().to_string(),
                message: format!(
                    "case id `{}` is also used by {}",
                    c.spec.id,
                    other.path.display()
                ),
            });
        }
    }
    if errors.is_empty() {
        Ok(cases)
    } else {
        Err(errors)
    }
}

fn collect_yaml(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            let skip = path.parent() == Some(root)
                && matches!(
                    path.file_name().and_then(|n| n.to_str()),
                    Some("examples" | "materials" | "meshes")
                );
            if !skip {
                collect_yaml(root, &path, out);
            }
        } else if path.extension().is_some_and(|e| e == "yaml" || e == "yml") {
            out.push(path);
        }
    }
}

/// Whether a case is selected by a pattern: its id, a glob with `*`, a tag `tag:<name>`, or the
/// path of its file.
pub fn matches(case: &LoadedCase, pattern: &str) -> bool {
    if let Some(tag) = pattern.strip_prefix("tag:") {
        return case.spec.tags.iter().any(|t| t == tag);
    }
    if Path::new(pattern) == case.path || case.path.ends_with(pattern) {
        return true;
    }
    glob_match(pattern, &case.spec.id)
}

/// `*` matches any run of characters; everything else literally.
fn glob_match(pattern: &str, text: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    if parts.len() == 1 {
        return pattern == text;
    }
    let mut rest = text;
    for (i, part) in parts.iter().enumerate() {
        if i == 0 {
            let Some(r) = rest.strip_prefix(part) else {
                return false;
            };
            rest = r;
        } else if i == parts.len() - 1 {
            return rest.ends_with(part);
        } else {
            let Some(pos) = rest.find(part) else {
                return false;
            };
            rest = &rest[pos + part.len()..];
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::ReferenceCurve;

    /// A measured curve reads its two named columns scaled, skipping `#` comments and blank
    /// lines; a missing column or a bad number is an error naming the file.
    #[test]
    fn a_reference_curve_reads_its_columns_scaled() {
        let dir = std::env::temp_dir().join(format!("impact-refcurve-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("curve.csv");
        std::fs::write(
            &file,
            "# source: a test\ncmod_mm, load_min, load_max\n\n0.0, 1.0, 2.0\n0.5, 3.0, 4.0\n",
        )
        .unwrap();
        let curve = |y: &str| ReferenceCurve {
            file: file.clone(),
            x: "cmod_mm".into(),
            y: y.into(),
            x_scale: 1e-3,
            y_scale: 2.0,
            label: "measured".into(),
        };
        let (x, y) = curve("load_max").read().unwrap();
        assert_eq!(x, vec![0.0, 0.5e-3]);
        assert_eq!(y, vec![4.0, 8.0]);
        let missing = curve("load").read().unwrap_err();
        assert!(missing.contains("no column `load`"), "{missing}");
        std::fs::write(&file, "cmod_mm, load_max\n0.0, x\n").unwrap();
        let bad = curve("load_max").read().unwrap_err();
        assert!(
            bad.contains("bad data row 1") && bad.contains("curve.csv"),
            "{bad}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
