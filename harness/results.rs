//! What a run of the harness records: the per-case verdicts (`results.json`), the plots to draw,
//! and one line per case in `reports/history.jsonl` for trends. Scripts read `results.json`:
//! extend these types, never rename a field.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

mod record;
pub use record::RecordError;

/// The one rule for a case's output folder in a run folder: `<run>/cases/<id, / as __>/`.
/// Kinds write there; the report reads from there.
pub fn case_dir(run_dir: &std::path::Path, id: &str) -> std::path::PathBuf {
    run_dir.join("cases").join(id.replace('/', "__"))
}

/// `name` with every character but ASCII letters, digits and `-` replaced by `_`: a variant's
/// name such as `gauss-seidel/thesis` as part of a file name in a case's folder.
pub fn file_safe(name: &str) -> String {
    name.replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "_")
}

/// JSON has no NaN or infinity: serde_json writes them as `null`. These read `null` back as
/// NaN so that a run with a non-finite value can still be reloaded by `impact-vv report`.
pub(crate) mod lenient {
    use serde::{Deserialize, Deserializer};

    pub fn f64<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
    }

    pub fn vec<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Ok(Vec::<Option<f64>>::deserialize(d)?
            .into_iter()
            .map(|x| x.unwrap_or(f64::NAN))
            .collect())
    }
}

/// Verdict of a case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Every metric met its reference.
    Pass,
    /// At least one metric missed its reference.
    Fail,
    /// Not run, with the reason in `CaseResult::message`.
    Skipped,
    /// The case could not be evaluated (bad input, solver error); the message says why.
    Error,
    /// A signal stopped the run before the case finished (or started): no verdict.
    Interrupted,
}

/// How a metric's error is measured and bounded, as `results.json` spells it: the one place the
/// judge, the runner's plots and the report read it from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToleranceKind {
    /// `|value - reference| <= tolerance`.
    Absolute,
    /// `|value - reference| / |reference| <= tolerance`.
    Relative,
    /// `value <= tolerance` (the error is the value).
    AtMost,
    /// `value >= tolerance` (the error is the value).
    AtLeast,
    /// `value / reference >= tolerance`.
    AtLeastRatio,
    /// `|value - reference| / max |column| <= tolerance`, the column's peak unknown here.
    RelativeToPeak,
    /// A kind this version does not know (a `results.json` written by another one).
    #[default]
    #[serde(other)]
    Unknown,
}

impl ToleranceKind {
    /// The name in `results.json`.
    pub fn name(self) -> &'static str {
        match self {
            ToleranceKind::Absolute => "absolute",
            ToleranceKind::Relative => "relative",
            ToleranceKind::AtMost => "at_most",
            ToleranceKind::AtLeast => "at_least",
            ToleranceKind::AtLeastRatio => "at_least_ratio",
            ToleranceKind::RelativeToPeak => "relative_to_peak",
            ToleranceKind::Unknown => "unknown",
        }
    }

    /// The acceptance band around `reference` in the metric's own units, where the kind says how
    /// wide it is (absolute and relative tolerances).
    pub fn band(self, reference: f64, tolerance: f64) -> Option<[f64; 2]> {
        let half_width = match self {
            ToleranceKind::Absolute => tolerance,
            ToleranceKind::Relative => tolerance * reference.abs(),
            _ => return None,
        };
        Some([reference - half_width, reference + half_width])
    }

    /// Whether passing means staying above the bound (a floor) rather than below it.
    pub fn is_floor(self) -> bool {
        matches!(self, ToleranceKind::AtLeast | ToleranceKind::AtLeastRatio)
    }
}

/// One measured quantity against its reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricResult {
    /// Name of the metric, as the case file gives it.
    pub name: String,
    /// The measured value, in `unit`.
    #[serde(deserialize_with = "lenient::f64")]
    pub value: f64,
    /// The reference value, in `unit` (0 for error measures).
    #[serde(deserialize_with = "lenient::f64")]
    pub reference: f64,
    /// `|value - reference|`, divided by the reference scale for relative tolerances.
    #[serde(deserialize_with = "lenient::f64")]
    pub error: f64,
    /// The bound on `error` (or the floor, see `tolerance_kind`).
    #[serde(deserialize_with = "lenient::f64")]
    pub tolerance: f64,
    /// Unit of `value` and `reference` as printed.
    pub unit: String,
    /// Whether the metric met its reference.
    pub pass: bool,
    /// How `error` and `tolerance` are to be read.
    #[serde(default)]
    pub tolerance_kind: ToleranceKind,
    /// Where the reference comes from (formula and source, or data file).
    #[serde(default)]
    pub reference_source: String,
    /// The measure's own verdict on its reading, for measures that give one (a crack-tip speed
    /// judged with its resolution: `pass`, `fail`, `inconclusive` or `no tip`, and why); such a
    /// metric passes only if its reading does.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reading: Option<String>,
}

/// A curve of a plot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// Abscissae, in the plot's x unit.
    #[serde(deserialize_with = "lenient::vec")]
    pub x: Vec<f64>,
    /// Ordinates, one per abscissa, in the plot's y unit.
    #[serde(deserialize_with = "lenient::vec")]
    pub y: Vec<f64>,
}

/// A horizontal reference line with an optional acceptance band `[lo, hi]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceLine {
    /// Legend entry.
    pub label: String,
    /// Height of the line, in the plot's y unit.
    #[serde(deserialize_with = "lenient::f64")]
    pub y: f64,
    /// The acceptance band `[lo, hi]` drawn around it, if any.
    pub band: Option<[f64; 2]>,
}

/// A plot of a case: curves plus reference lines and bands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlotData {
    /// Title of the plot.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Horizontal reference lines with their bands.
    #[serde(default)]
    pub reference_lines: Vec<ReferenceLine>,
    /// Draw both axes logarithmically (convergence and work-precision diagrams).
    #[serde(default)]
    pub log_log: bool,
}

/// One level of a refinement sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepLevel {
    /// The swept parameter's value (element size in m, or time-step factor).
    #[serde(deserialize_with = "lenient::f64")]
    pub parameter: f64,
    /// Wall time of the level's run (s of real time).
    #[serde(deserialize_with = "lenient::f64")]
    pub wall_s: f64,
    /// Error of each metric against its reference at this level.
    pub errors: BTreeMap<String, f64>,
    /// Value of each metric at this level, in the metric's unit.
    pub values: BTreeMap<String, f64>,
    /// How the level's run ended.
    #[serde(default)]
    pub status: LevelStatus,
}

/// How the solver run of a sweep level ended. Written as the text `completed`, `unstable` or
/// `error: <why>` (the form of results files before it was typed).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(from = "String", into = "String")]
pub enum LevelStatus {
    /// The run reached its end.
    #[default]
    Completed,
    /// Stopped by the instability check (a time step above the stable limit, on purpose).
    Unstable,
    /// Any other error, with its message.
    Failed(String),
}

impl From<String> for LevelStatus {
    fn from(text: String) -> Self {
        match text.as_str() {
            "completed" | "" => LevelStatus::Completed,
            "unstable" => LevelStatus::Unstable,
            _ => LevelStatus::Failed(
                text.strip_prefix("error: ")
                    .map_or(text.clone(), str::to_string),
            ),
        }
    }
}

impl From<LevelStatus> for String {
    fn from(status: LevelStatus) -> Self {
        status.to_string()
    }
}

impl std::fmt::Display for LevelStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LevelStatus::Completed => f.write_str("completed"),
            LevelStatus::Unstable => f.write_str("unstable"),
            LevelStatus::Failed(why) => write!(f, "error: {why}"),
        }
    }
}

/// A refinement sweep: levels and the observed convergence order of each metric's error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    /// What is swept, with its unit (element size, time-step factor).
    pub parameter: String,
    /// The levels, coarse to fine.
    pub levels: Vec<SweepLevel>,
    /// Least-squares slope of log(error) against log(parameter) over the levels.
    pub observed_order: BTreeMap<String, f64>,
}

/// The result of one case under one solver variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    /// Id of the case.
    pub id: String,
    /// Name of the solver variant (`default` for the scene's own analysis).
    pub variant: String,
    /// The case's verdict.
    pub status: Status,
    /// Wall time of the case (s of real time).
    #[serde(deserialize_with = "lenient::f64")]
    pub wall_s: f64,
    /// Each metric, judged.
    pub metrics: Vec<MetricResult>,
    /// One line: what the case checks.
    #[serde(default)]
    pub description: String,
    /// The case's tier by name.
    #[serde(default)]
    pub tier: String,
    /// The case's tags.
    #[serde(default)]
    pub tags: Vec<String>,
    /// Why a case failed, was skipped or errored; the solver's plan otherwise.
    #[serde(default)]
    pub message: Option<String>,
    /// The case's plots, with their data.
    #[serde(default)]
    pub plots: Vec<PlotData>,
    /// The refinement sweep, if the case has one.
    #[serde(default)]
    pub sweep: Option<SweepResult>,
    /// How the contact solver fared over the judged run, for scenes with contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSolverStats>,
    /// Wall time of each phase of the explicit step (s), by phase name, for scene runs.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub phase_seconds: BTreeMap<String, f64>,
    /// Share of the element updates of bodies with a fast path (the microplane elastic path,
    /// issue 20) that took it over the judged explicit run; absent without such bodies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_update_share: Option<f64>,
    /// Peak resident memory (`VmHWM`, MiB) of each rank's process, for a variant run under
    /// `mpirun`; absent for a case run inside the harness, whose process the cases share.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_memory_mib: Option<Vec<f64>>,
    /// What the case's kind recorded for its part of the report, under the kind's key
    /// (`contact_comparison`, `material`, `crosscheck`, ...): written and read by the kind
    /// ([`CaseResult::record`], [`CaseResult::set_record`]), carried as JSON by everything else.
    #[serde(flatten, default)]
    pub records: BTreeMap<String, serde_json::Value>,
    /// The case's `known_failure` (the debt it records, from its YAML): a failure so described
    /// does not fail the run (see [`RunResults::exit_code`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub known_failure: Option<String>,
    /// The case's log file (the lines its runs printed on the way: each remeshing's summary,
    /// ...), relative to the run folder with `/` separators (`cases/<case>/log.txt`); absent
    /// when the case logged nothing (`crate::case_log`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log_file: Option<String>,
}

impl CaseResult {
    /// Whether this result fails the run: a failure or an error, unless it is a failure the
    /// case records as known. Passed, skipped and interrupted cases do not (an interrupted run
    /// has a status of its own).
    pub fn fails_the_run(&self) -> bool {
        match self.status {
            Status::Fail => self.known_failure.is_none(),
            Status::Error => true,
            Status::Pass | Status::Skipped | Status::Interrupted => false,
        }
    }
}

/// Contact-solver statistics of one scene run (summed over pairs and passes).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactSolverStats {
    /// The solver's name in `impact_solver::contact::registry`: `gauss-seidel/thesis`,
    /// `conic/coulomb`, ...
    pub solver: String,
    /// Time steps in which at least one contact problem was solved.
    pub steps_with_contact: usize,
    /// Contact problems solved (steps x pairs x passes with contacts).
    pub solves: usize,
    /// Solves that did not converge (cap reached, time limit, or solver failure).
    pub not_converged: usize,
    /// Penetrations detection could not resolve, summed over the run.
    pub unresolved: usize,
    /// Iterations (sweeps or interior-point iterations) summed over the run.
    pub iterations: usize,
    /// Wall time in the contact phase (detection and solution) over the run (s).
    #[serde(deserialize_with = "lenient::f64")]
    pub contact_seconds: f64,
}

/// Everything one `impact-vv run` produced: written as `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResults {
    /// Id of the run, from its start time; names its folder under `reports/`.
    pub run_id: String,
    /// Short commit hash, `+dirty` when the tree had uncommitted changes.
    pub commit: String,
    /// The tier that ran, by name.
    pub tier: String,
    /// One result per case and variant, in run order.
    pub cases: Vec<CaseResult>,
    /// Start time of the run (UTC).
    #[serde(default)]
    pub date: String,
    /// Host name and core count.
    #[serde(default)]
    pub machine: String,
    /// Worker threads of the solver.
    #[serde(default)]
    pub threads: usize,
    /// Versions of the harness, the solver and the compiler.
    #[serde(default)]
    pub versions: BTreeMap<String, String>,
    /// Wall time of the whole run (s of real time).
    #[serde(default)]
    #[serde(deserialize_with = "lenient::f64")]
    pub wall_s: f64,
}

/// One line of `reports/history.jsonl`: one case of one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HistoryRecord {
    /// Id of the run ([`RunResults::run_id`]).
    pub run_id: String,
    /// The run's commit.
    pub commit: String,
    /// Start time of the run (UTC).
    pub date: String,
    /// Host name and core count.
    pub machine: String,
    /// Worker threads of the solver.
    pub threads: usize,
    /// Versions of the harness, the solver and the compiler.
    pub versions: BTreeMap<String, String>,
    /// Id of the case.
    pub case: String,
    /// Name of the solver variant.
    pub variant: String,
    /// The case's verdict.
    pub status: Status,
    /// Wall time of the case (s of real time).
    #[serde(deserialize_with = "lenient::f64")]
    pub wall_s: f64,
    /// Value of each metric, in its unit.
    pub metrics: BTreeMap<String, f64>,
    /// Wall time of each phase of the explicit step (s), for scene runs: the trend of where the
    /// time goes.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub phase_seconds: BTreeMap<String, f64>,
}

impl RunResults {
    /// The history lines of this run, one per case.
    /// One record per case that finished (interrupted cases have no verdict to trend).
    pub fn history_records(&self) -> Vec<HistoryRecord> {
        self.cases
            .iter()
            .filter(|c| c.status != Status::Interrupted)
            .map(|c| HistoryRecord {
                run_id: self.run_id.clone(),
                commit: self.commit.clone(),
                date: self.date.clone(),
                machine: self.machine.clone(),
                threads: self.threads,
                versions: self.versions.clone(),
                case: c.id.clone(),
                variant: c.variant.clone(),
                status: c.status,
                wall_s: c.wall_s,
                metrics: c
                    .metrics
                    .iter()
                    .map(|m| (m.name.clone(), m.value))
                    .collect(),
                phase_seconds: c.phase_seconds.clone(),
            })
            .collect()
    }

    /// Exit status of the run, the one policy of `run` and `report`: 1 when a case fails the run
    /// ([`CaseResult::fails_the_run`]), 0 otherwise.
    pub fn exit_code(&self) -> u8 {
        u8::from(self.cases.iter().any(CaseResult::fails_the_run))
    }
}

/// A table a kind records for its part of the report (material-point experiments,
/// cross-checks): title, head, rows of text, and how to read it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordTable {
    /// Title of the table.
    pub title: String,
    /// Column headings.
    pub head: Vec<String>,
    /// Rows of text cells, one per heading.
    pub rows: Vec<Vec<String>>,
    /// What the table shows and how to read it.
    #[serde(default)]
    pub note: String,
}

/// A plot a kind records for its part of the report: a [`PlotData`] with a logarithmic x axis, target windows and dashed
/// reference curves where it needs them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialPlot {
    /// The curves, labels and reference lines.
    pub plot: PlotData,
    /// Logarithmic x axis.
    #[serde(default)]
    pub log_x: bool,
    /// Logarithmic y axis.
    #[serde(default)]
    pub log_y: bool,
    /// Target windows drawn as boxes.
    #[serde(default)]
    pub boxes: Vec<TargetBox>,
    /// Names of the series that are references (drawn dashed).
    #[serde(default)]
    pub dashed: Vec<String>,
}

/// A target window `[x_lo, x_hi] x [y_lo, y_hi]` in the plot's units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TargetBox {
    /// Legend entry.
    pub label: String,
    /// `[x_lo, x_hi]`, in the plot's x unit.
    #[serde(deserialize_with = "lenient::vec")]
    pub x: Vec<f64>,
    /// `[y_lo, y_hi]`, in the plot's y unit.
    #[serde(deserialize_with = "lenient::vec")]
    pub y: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::{CaseResult, RunResults, ToleranceKind};

    fn case(status: &str, known_failure: Option<&str>) -> CaseResult {
        let mut json = serde_json::json!({
            "id": "x", "variant": "default", "status": status, "wall_s": 0.0, "metrics": []
        });
        if let Some(k) = known_failure {
            json["known_failure"] = k.into();
        }
        serde_json::from_value(json).unwrap()
    }

    fn exit_code(cases: Vec<CaseResult>) -> u8 {
        let run: RunResults = serde_json::from_value(serde_json::json!({
            "run_id": "r", "commit": "c", "tier": "quick", "cases": []
        }))
        .unwrap();
        RunResults { cases, ..run }.exit_code()
    }

    /// One exit policy: a failure the case records as known does not fail the run; an unknown
    /// failure or an error does, known or not; skipped and interrupted cases do not.
    #[test]
    fn known_failures_alone_do_not_fail_the_run() {
        assert_eq!(
            exit_code(vec![case("pass", None), case("fail", Some("debt"))]),
            0
        );
        assert_eq!(
            exit_code(vec![case("fail", Some("debt")), case("fail", None)]),
            1
        );
        assert_eq!(exit_code(vec![case("error", Some("debt"))]), 1);
        assert_eq!(
            exit_code(vec![case("skipped", None), case("interrupted", None)]),
            0
        );
    }

    const KINDS: [ToleranceKind; 6] = [
        ToleranceKind::Absolute,
        ToleranceKind::Relative,
        ToleranceKind::AtMost,
        ToleranceKind::AtLeast,
        ToleranceKind::AtLeastRatio,
        ToleranceKind::RelativeToPeak,
    ];

    /// A sweep level's status reads and writes as the text results files have always had.
    #[test]
    fn level_statuses_keep_their_text_form() {
        use super::LevelStatus;
        for (status, text) in [
            (LevelStatus::Completed, "\"completed\""),
            (LevelStatus::Unstable, "\"unstable\""),
            (LevelStatus::Failed("no mesh".into()), "\"error: no mesh\""),
        ] {
            assert_eq!(serde_json::to_string(&status).unwrap(), text);
            assert_eq!(serde_json::from_str::<LevelStatus>(text).unwrap(), status);
        }
    }

    /// Each kind is written and read back under its `name()`, and a name this version does not
    /// know reads as `Unknown` instead of failing the whole `results.json`.
    #[test]
    fn tolerance_kinds_round_trip_under_their_names() {
        for kind in KINDS {
            let json = serde_json::to_string(&kind).unwrap();
            assert_eq!(json, format!("\"{}\"", kind.name()));
            assert_eq!(serde_json::from_str::<ToleranceKind>(&json).unwrap(), kind);
        }
        let future: ToleranceKind = serde_json::from_str("\"relative_to_scale\"").unwrap();
        assert_eq!(future, ToleranceKind::Unknown);
    }

    /// Bands exist for absolute and relative tolerances only; floors are the two `at_least`s.
    #[test]
    fn bands_and_floors() {
        assert_eq!(ToleranceKind::Absolute.band(10.0, 2.0), Some([8.0, 12.0]));
        assert_eq!(
            ToleranceKind::Relative.band(-10.0, 0.1),
            Some([-11.0, -9.0])
        );
        for kind in KINDS.into_iter().skip(2) {
            assert_eq!(kind.band(10.0, 2.0), None, "{kind:?}");
        }
        let floors: Vec<_> = KINDS.into_iter().filter(|k| k.is_floor()).collect();
        assert_eq!(
            floors,
            [ToleranceKind::AtLeast, ToleranceKind::AtLeastRatio]
        );
    }
}
