//! The benchmark catalogue's schema: the part of a case file every kind of case shares (id,
//! tier, metrics with their references and tolerances, plots, sweeps, variants). Reading the
//! files is `crate::case_file`; the kinds' own blocks are `crate::case_kind`.

use std::path::PathBuf;

use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};

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
    /// The tier's name in case files and on the command line (`quick`, `nightly`, `stress`,
    /// `long`).
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
    /// Unique id of the case, `<group>/<name>` (e.g. `fracture/band-in-prism-h25`).
    pub id: String,
    /// One line: what the case checks.
    pub description: String,
    /// The tier the case runs in.
    pub tier: Tier,
    /// Free labels for selecting cases (`impact-vv run tag:<label>`).
    #[serde(default)]
    pub tags: Vec<String>,
    /// The scene: what a scene case runs, and what kinds that compare with it (a cross-check)
    /// read. Its kind (`crate::case_kind`) says whether it needs one.
    #[serde(default)]
    pub scene: Option<Scene>,
    /// A refinement sweep: the case runs once per level; none without one.
    #[serde(default)]
    pub sweep: Option<Sweep>,
    /// Solver configurations to compare on the same scene; each runs and is judged on its own.
    /// Empty: the scene's own analysis, reported as variant `default`.
    #[serde(default)]
    pub variants: Vec<Variant>,
    /// The measurements, each judged against its reference.
    pub metrics: Vec<MetricSpec>,
    /// Plots of the report page of the case.
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
    /// Name of the variant in results and reports.
    pub name: String,
    /// The analysis (integrator and settings) replacing the scene's; the scene's when absent.
    #[serde(default)]
    pub analysis: Option<impact_solver::scene::Analysis>,
    /// A solver name from `impact_solver::contact::registry` (`gauss-seidel/thesis`,
    /// `conic/coulomb`, ...), alone or as `{ name, tolerance, max_iterations }`: the same contact
    /// problems, another algorithm (issue 5).
    #[serde(default)]
    pub contact_solver: Option<impact_solver::scene::ContactSolverSpec>,
    /// Runs the case as this many ranks of a distributed run (issue 22, `impact_solver::distributed`),
    /// so the report sets the distributed run beside the one-process one: in a build with the
    /// `mpi` feature the harness starts them with `mpirun` (`crate::mpirun`); in the default
    /// build they are threads of the harness joined by `ThreadGroup`, with the same
    /// decomposition and force exchange but not MPI's transport or wall time. One rank when
    /// absent.
    #[serde(default)]
    pub ranks: Option<usize>,
    /// The seed of every random strength field of the scene's bodies
    /// (`material.microplane.strength_field`): the same case on another draw of the concrete's
    /// scatter, so that the report sets the seeds side by side.
    #[serde(default)]
    pub strength_seed: Option<u64>,
}

impl Variant {
    /// The case's scene as this variant runs it.
    pub fn apply(&self, scene: &mut Scene) {
        if let Some(analysis) = &self.analysis {
            scene.analysis = analysis.clone();
        }
        if let Some(seed) = self.strength_seed {
            for body in &mut scene.bodies {
                if let impact_solver::scene::MaterialSpec::Microplane(spec) = &mut body.material {
                    if let Some(field) = &mut spec.strength_field {
                        field.seed = seed;
                    }
                }
            }
        }
        if let Some(solver) = &self.contact_solver {
            for pair in &mut scene.contact {
                pair.solver = *solver;
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
    RelativeToPeak {
        /// Fraction of the scale (dimensionless).
        fraction: f64,
        /// History column whose largest magnitude is the scale.
        column: String,
    },
    /// `value >= tolerance * reference` (a quantity that must exceed a multiple of a reference,
    /// e.g. a peak impact force far above the static peak load): the error is
    /// `value / reference`.
    AtLeastRatio(f64),
}

/// One measurement of a case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetricSpec {
    /// Name of the metric, unique within the case.
    pub name: String,
    /// Unit of the value as printed in reports (e.g. `N`, `mm`, `-`); informative.
    #[serde(default)]
    pub unit: String,
    /// What to measure, in the terms of the case's kind, which reads it
    /// (`crate::case_kind::parse_measures`).
    pub measure: serde_norway::Value,
    /// Required: a metric without a reference fails the case (never skipped).
    #[serde(default)]
    pub reference: Option<Reference>,
    /// How far the value may lie from the reference.
    pub tolerance: Tolerance,
}

/// A plot of history columns against time, or against another column (`x_column`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSpec {
    /// Title of the plot.
    pub title: String,
    /// History columns to draw against time (or against `x_column`).
    pub columns: Vec<String>,
    /// History column on the x axis, e.g. a displacement probe for a load-displacement curve
    /// (thesis Fig. 10.5); default `time`.
    #[serde(default)]
    pub x_column: Option<String>,
    /// Label of the y axis, with its unit.
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
    /// Name of the file's column drawn on the x axis.
    pub x: String,
    /// Name of the file's column drawn on the y axis.
    pub y: String,
    /// Factor from the file's x unit to the plot's (default 1).
    #[serde(default = "one")]
    pub x_scale: f64,
    /// Factor from the file's y unit to the plot's (default 1).
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
    pub fn read(&self) -> Result<(Vec<f64>, Vec<f64>), crate::curve::CurveError> {
        let mut c = crate::curve::read_columns(&self.file, &[&self.x, &self.y])?.into_iter();
        let (xs, ys) = (c.next().unwrap_or_default(), c.next().unwrap_or_default());
        Ok((
            xs.into_iter().map(|x| self.x_scale * x).collect(),
            ys.into_iter().map(|y| self.y_scale * y).collect(),
        ))
    }
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
        let missing = curve("load").read().unwrap_err().to_string();
        assert!(missing.contains("no column `load`"), "{missing}");
        std::fs::write(&file, "cmod_mm, load_max\n0.0, x\n").unwrap();
        let bad = curve("load_max").read().unwrap_err().to_string();
        assert!(
            bad.contains("bad data row 1") && bad.contains("curve.csv"),
            "{bad}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
