//! The default kind of case: a scene (`scene:` in the case file), run by the solver once or
//! once per level of a sweep, and measured from its histories and fields ([`measure`]).
//! Several variants (integrators, contact solvers) may run the same scene.

mod level_run;
pub mod measure;

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use impact_solver::problem::Problem;
use impact_solver::scene::{build_problem, Analysis, MeshSource, Scene};
use impact_solver::SolverError;

use crate::case_kind::{
    parse_measures, unfinished_result, Block, CaseKind, KindParseError, LoadedCase, RunOptions,
};
use crate::case_log::CaseLog;
use crate::catalogue::{CaseSpec, Sweep, Variant};
use crate::judge::{error_for_sweep, judge_readings, observed_order};
use crate::results::{
    case_dir, CaseResult, LevelStatus, MetricResult, PlotData, ReferenceLine, Series, Status,
    SweepLevel, SweepResult,
};
use impact_solver::analysis::Execution;
use impact_solver::distributed::Communicator;
use impact_solver::output::HistoryTable;
use level_run::{stem_of, LevelRun, LevelRunner};
use measure::{Measure, MeasureError};

/// Why a case's scene is refused before it runs.
#[derive(Debug, thiserror::Error)]
pub enum SceneCaseError {
    /// A scene case without a scene.
    #[error(
        "the case has no `scene`: add one, or the block of another kind of case \
         (docs/catalogue.md, 'The case format')"
    )]
    NoScene,
    /// A mesh sweep over a body not meshed as a box.
    #[error("a mesh sweep needs a box mesh on the first body")]
    MeshSweepNeedsBox,
    /// A mesh-file sweep without a Gmsh body.
    #[error("a mesh_files sweep needs a body meshed from a Gmsh file")]
    MeshFilesNeedGmsh,
    /// A time-step sweep of a static analysis.
    #[error("a time-step sweep needs an explicit analysis")]
    TimeStepSweepNeedsExplicit,
    /// The scene cannot be built to find its stable step.
    #[error(transparent)]
    Build(#[from] SolverError),
}

/// A case that runs its scene.
#[derive(Debug)]
pub struct SceneCase {
    measures: Vec<Measure>,
}

/// Reads a scene case (the registry's default kind: it has no block of its own): it needs a
/// scene, and its metrics measure scene runs.
pub fn parse(
    _block: Option<&Block>,
    spec: &CaseSpec,
    _base: &Path,
) -> Result<Arc<dyn CaseKind>, KindParseError> {
    if spec.scene.is_none() {
        return Err(SceneCaseError::NoScene.into());
    }
    let measures = parse_measures(spec, "scene")?;
    Ok(Arc::new(SceneCase { measures }))
}

impl CaseKind for SceneCase {
    fn name(&self) -> &'static str {
        "scene"
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn run(
        &self,
        case: &LoadedCase,
        variant: Option<&Variant>,
        options: &RunOptions,
    ) -> CaseResult {
        run_case(self, case, variant, options, None)
    }
}

impl SceneCase {
    /// Runs `case` under `variant` as one rank of `world` (this process is one of the
    /// `mpirun` ranks that [`crate::mpirun`] started for a variant with `ranks: N`): every
    /// level's scene runs distributed over `world`, and every rank judges the same history
    /// (rank 0's result is the case's).
    pub fn run_as_rank(
        &self,
        case: &LoadedCase,
        variant: Option<&Variant>,
        options: &RunOptions,
        world: &dyn Communicator,
    ) -> CaseResult {
        run_case(self, case, variant, options, Some(world))
    }
}

/// Runs one case under one variant with its log ([`crate::case_log`]): what its runs print on
/// the way goes to the case's log file, whose path the result records.
fn run_case(
    kind: &SceneCase,
    case: &LoadedCase,
    variant: Option<&Variant>,
    options: &RunOptions,
    world: Option<&dyn Communicator>,
) -> CaseResult {
    let variant_name = variant.map_or("default", |v| v.name.as_str());
    // Rank 0 of an `mpirun` variant keeps the log; the other ranks would write the same lines.
    let log = if world.is_some_and(|w| w.rank() > 0) {
        CaseLog::silent(&case.spec.id, variant_name)
    } else {
        CaseLog::new(options, &case.spec.id, variant_name)
    };
    let mut result = run_logged(kind, case, variant, options, world, &log);
    // A variant run under `mpirun` brings its ranks' log path in its result.
    if let Some(path) = log.relative_path() {
        result.log_file = Some(path);
    }
    result
}

/// Runs one case under one variant (or the scene's own analysis): every level of its sweep (or
/// the scene once), then judges its metrics. A variant with `ranks: N` runs as `N` ranks: over
/// `world` when this process is one of them, under `mpirun` in a build with the `mpi` feature
/// ([`crate::mpirun`]), and otherwise as `N` threads of this process (`ThreadGroup`).
fn run_logged(
    kind: &SceneCase,
    case: &LoadedCase,
    variant: Option<&Variant>,
    options: &RunOptions,
    world: Option<&dyn Communicator>,
    log: &CaseLog,
) -> CaseResult {
    let spec = &case.spec;
    #[cfg(feature = "mpi")]
    if let (None, Some(v)) = (world, variant) {
        if let Some(n) = v.ranks.filter(|&n| n > 1) {
            return crate::mpirun::run_variant(case, v, n, options);
        }
    }
    let mut result = unfinished_result(spec, variant.map_or("default", |v| v.name.as_str()));
    let Some(scene) = &spec.scene else {
        result.message = Some("the case has no scene".into());
        return result;
    };
    let started = Instant::now();
    let mut scene = scene.clone();
    if let Some(v) = variant {
        v.apply(&mut scene);
    }
    let levels = match level_scenes(&scene, spec.sweep.as_ref()) {
        Ok(l) => l,
        Err(message) => {
            result.message = Some(message.to_string());
            return result;
        }
    };
    let case_dir = options.output_dir.as_ref().map(|d| case_dir(d, &spec.id));
    let sink = log.sink();
    let runner = LevelRunner {
        spec,
        variant,
        options,
        world,
        case_dir: case_dir.as_deref(),
        sink: &sink,
        levels: levels.len(),
    };
    let runs: Vec<LevelRun> = levels
        .iter()
        .enumerate()
        .map(|(i, (parameter, scene))| runner.run(i, *parameter, scene))
        .collect();
    result.wall_s = started.elapsed().as_secs_f64();

    let Some(judged) = level_to_judge(&mut result, &runner, &runs, log) else {
        return result;
    };
    let (problem, run) = runs[judged]
        .outcome
        .as_ref()
        .expect("judged level completed");
    record_run_statistics(&mut result, problem, run);
    let (status, message) = judge(kind, spec, &scene, &runs, judged, &mut result);
    result.plots = plots(spec, run.history.as_ref(), &result.metrics, log);
    if let Some(dir) = &case_dir {
        crate::report::penetration::record(
            &mut result,
            dir,
            &stem_of(variant, judged, levels.len()),
        );
    }
    let beam_plots = crate::report::beam::record(
        &result,
        &levels[judged].1,
        problem,
        run,
        case_dir.as_deref(),
        &result.plots,
    );
    result.plots.extend(beam_plots);
    result.status = status;
    result.message = Some(message);
    result
}

/// The level whose run the per-run metrics are judged on: the last that completed (the finest
/// mesh). `None` when the case ends without a judgement, `result` saying why: a run was
/// interrupted; every level failed (with the plots of what the last level wrote before it
/// failed); or a level of a mesh sweep failed, which leaves no convergence to judge.
fn level_to_judge(
    result: &mut CaseResult,
    runner: &LevelRunner,
    runs: &[LevelRun],
    log: &CaseLog,
) -> Option<usize> {
    let spec = runner.spec;
    if let Some(e) = runs.iter().find_map(|r| match &r.outcome {
        Err(e @ SolverError::Interrupted { .. }) => Some(e),
        _ => None,
    }) {
        result.status = Status::Interrupted;
        result.message = Some(e.to_string());
        return None;
    }
    let judged = runs.iter().rposition(|r| r.outcome.is_ok());
    let Some(judged) = judged else {
        let e = runs
            .last()
            .and_then(|r| r.outcome.as_ref().err())
            .map(|e| e.to_string())
            .unwrap_or_default();
        result.message = Some(format!("the solver run failed: {e}"));
        // What the last level wrote before it failed: its history as the case's plots (the
        // history file is written as the run goes) and the records of a run that remeshes.
        if let Some(dir) = runner.case_dir {
            let levels = runner.levels;
            let stem = stem_of(runner.variant, levels.saturating_sub(1), levels);
            let history = HistoryTable::read_csv(&dir.join(format!("{stem}_history.csv"))).ok();
            result.plots = plots(spec, history.as_ref(), &[], log);
            crate::report::penetration::record(result, dir, &stem);
        }
        return None;
    };
    if matches!(spec.sweep, Some(Sweep::Mesh(_) | Sweep::MeshFiles(_))) {
        if let Some((i, e)) = runs
            .iter()
            .enumerate()
            .find_map(|(i, r)| r.outcome.as_ref().err().map(|e| (i, e)))
        {
            result.message = Some(format!("sweep level {i} failed: {e}"));
            return None;
        }
    }
    Some(judged)
}

/// The judged run's statistics in the result: the contact solver's record, the wall time per
/// phase of an explicit run, and the share of fast material updates.
fn record_run_statistics(result: &mut CaseResult, problem: &Problem, run: &Execution) {
    result.contact = contact_stats(problem, run);
    if let Some(summary) = &run.summary {
        result.phase_seconds = summary
            .phase_seconds
            .named()
            .iter()
            .map(|(name, t)| (name.to_string(), *t))
            .collect();
        result.fast_update_share = run
            .material_history
            .as_ref()
            .and_then(|h| problem.model.fast_update_share(h, summary.steps));
    }
}

/// Judges the case's metrics into `result`: each per-run metric on the run of level `judged`
/// (and at every completed level, for the sweep's table and observed orders), each sweep metric
/// over the levels; with a sweep, its levels and observed orders. Returns the verdict.
fn judge(
    kind: &SceneCase,
    spec: &CaseSpec,
    scene: &Scene,
    runs: &[LevelRun],
    judged: usize,
    result: &mut CaseResult,
) -> (Status, String) {
    let (problem, run) = runs[judged]
        .outcome
        .as_ref()
        .expect("judged level completed");
    let mut sweep_levels: Vec<SweepLevel> = runs
        .iter()
        .map(|r| SweepLevel {
            parameter: r.parameter,
            wall_s: r.wall_s,
            errors: BTreeMap::new(),
            values: BTreeMap::new(),
            status: match &r.outcome {
                Ok(_) => LevelStatus::Completed,
                Err(SolverError::Unstable(_)) => LevelStatus::Unstable,
                Err(e) => LevelStatus::Failed(e.to_string()),
            },
        })
        .collect();
    let peak = |column: &str| {
        run.history
            .as_ref()?
            .column(column)
            .map(|y| y.iter().fold(0.0f64, |a, x| a.max(x.abs())))
    };
    let judgement = judge_readings(
        &spec.metrics,
        Some(scene),
        &mut |i, m, ref_value| {
            let measure = &kind.measures[i];
            if measure.is_sweep_measure() {
                return sweep_measure(measure, spec, runs, &sweep_levels).map(Into::into);
            }
            for (level, r) in sweep_levels.iter_mut().zip(runs) {
                if let Ok((p, e)) = &r.outcome {
                    if let Ok(v) = measure.evaluate(p, e) {
                        level.values.insert(m.name.clone(), v);
                        level
                            .errors
                            .insert(m.name.clone(), error_for_sweep(m, v, ref_value));
                    }
                }
            }
            measure.evaluate_read(problem, run)
        },
        &peak,
    );
    let verdict = judgement.verdict(std::slice::from_ref(&run.plan));
    result.metrics = judgement.metrics;
    if spec.sweep.is_some() {
        result.sweep = Some(sweep_result(kind, spec, sweep_levels));
    }
    verdict
}

/// The sweep's record: its levels, and the observed order of each per-run metric's error over
/// them.
fn sweep_result(kind: &SceneCase, spec: &CaseSpec, levels: Vec<SweepLevel>) -> SweepResult {
    let observed = spec
        .metrics
        .iter()
        .zip(&kind.measures)
        .filter(|(_, measure)| !measure.is_sweep_measure())
        .filter_map(|(m, _)| {
            let pts: Vec<(f64, f64)> = levels
                .iter()
                .filter_map(|l| l.errors.get(&m.name).map(|e| (l.parameter, *e)))
                .collect();
            observed_order(&pts).map(|o| (m.name.clone(), o))
        })
        .collect();
    SweepResult {
        parameter: match spec.sweep {
            Some(Sweep::Mesh(_) | Sweep::MeshFiles(_)) => "element size (m)".into(),
            _ => "time step / stable estimate".into(),
        },
        levels,
        observed_order: observed,
    }
}

/// The scene of every level: the case's scene with the sweep's parameter applied.
fn level_scenes(scene: &Scene, sweep: Option<&Sweep>) -> Result<Vec<(f64, Scene)>, SceneCaseError> {
    match sweep {
        None => Ok(vec![(1.0, scene.clone())]),
        Some(Sweep::Mesh(divisions)) => divisions
            .iter()
            .map(|d| {
                let mut s = scene.clone();
                let MeshSource::Box(b) = &mut s.bodies[0].mesh else {
                    return Err(SceneCaseError::MeshSweepNeedsBox);
                };
                b.divisions = *d;
                Ok((b.size[0] / d[0] as f64, s))
            })
            .collect(),
        Some(Sweep::MeshFiles(levels)) => levels
            .iter()
            .map(|level| {
                let mut s = scene.clone();
                let mut replaced = 0;
                for body in &mut s.bodies {
                    if let MeshSource::Gmsh(p) = &mut body.mesh {
                        p.clone_from(&level.file);
                        replaced += 1;
                    }
                }
                if replaced == 0 {
                    return Err(SceneCaseError::MeshFilesNeedGmsh);
                }
                Ok((level.size, s))
            })
            .collect(),
        Some(Sweep::TimeStepFactor(factors)) => {
            let problem = build_problem(scene)?;
            let (dt_cr, _) = problem.model.critical_time_step();
            factors
                .iter()
                .map(|f| {
                    let mut s = scene.clone();
                    let Analysis::Explicit(settings) = &mut s.analysis else {
                        return Err(SceneCaseError::TimeStepSweepNeedsExplicit);
                    };
                    settings.settings.time_step = Some(f * dt_cr);
                    settings.settings.allow_unstable_time_step = *f > 1.0;
                    Ok((*f, s))
                })
                .collect()
        }
    }
}

fn sweep_measure(
    measure: &Measure,
    spec: &crate::catalogue::CaseSpec,
    runs: &[LevelRun],
    levels: &[SweepLevel],
) -> Result<f64, MeasureError> {
    let Some(sweep) = &spec.sweep else {
        return Err(MeasureError::NeedsSweep);
    };
    let unstable = |r: &LevelRun| matches!(r.outcome, Err(SolverError::Unstable(_)));
    match measure {
        Measure::ObservedOrder { metric } => {
            let pts: Vec<(f64, f64)> = levels
                .iter()
                .filter_map(|l| l.errors.get(metric).map(|e| (l.parameter, *e)))
                .collect();
            observed_order(&pts).ok_or_else(|| MeasureError::FewLevels {
                metric: metric.clone(),
            })
        }
        Measure::StableUpToEstimate => Ok(runs
            .iter()
            .filter(|r| r.parameter <= 1.0)
            .all(|r| r.outcome.is_ok()) as u8 as f64),
        Measure::MeasuredStabilityLimit => {
            let Sweep::TimeStepFactor(factors) = sweep else {
                return Err(MeasureError::NeedsTimeStepSweep);
            };
            Ok(runs.iter().find(|r| unstable(r)).map_or_else(
                || factors.iter().cloned().fold(0.0, f64::max) + 0.1,
                |r| r.parameter,
            ))
        }
        Measure::UnstableRunsReported => {
            Ok(runs.iter().all(|r| r.outcome.is_ok() || unstable(r)) as u8 as f64)
        }
        _ => unreachable!("not a sweep measure"),
    }
}

/// The case's plots of history columns, with reference lines and bands from their metrics; a
/// plot that cannot be drawn says why in the case's log.
fn plots(
    spec: &crate::catalogue::CaseSpec,
    history: Option<&HistoryTable>,
    metrics: &[MetricResult],
    log: &CaseLog,
) -> Vec<PlotData> {
    let Some(history) = history else {
        return Vec::new();
    };
    spec.plots
        .iter()
        .map(|p| PlotData {
            title: p.title.clone(),
            x_label: match p.x_column.as_deref() {
                _ if p.crack_band.is_some() => "crack opening w (mm)".into(),
                None | Some("time") => "time (s)".into(),
                Some(c) => match &p.x_minus {
                    Some(m) => format!("{c} - {m}"),
                    None => c.to_string(),
                },
            },
            y_label: p.y_label.clone(),
            series: match (&p.crack_band, &spec.scene) {
                (Some(band), Some(scene)) => crate::band::plot_series(band, scene, &|c| {
                    history
                        .column(c)
                        .ok_or_else(|| crate::curve::CurveError::NoColumn {
                            name: c.into(),
                            columns: history.columns().to_vec(),
                        })
                })
                .unwrap_or_else(|e| {
                    log.line(&format!("plot `{}`: {e}", p.title));
                    Vec::new()
                }),
                _ => Vec::new(),
            }
            .into_iter()
            .chain(p.columns.iter().filter_map(|c| {
                let mut x = history.column(p.x_column.as_deref().unwrap_or("time"))?;
                if let Some(minus) = &p.x_minus {
                    let m = history.column(minus)?;
                    x.iter_mut().zip(m).for_each(|(a, b)| *a -= b);
                }
                let scale = p.y_scale.unwrap_or(1.0);
                history.column(c).map(|y| Series {
                    name: c.clone(),
                    x,
                    y: y.into_iter().map(|v| scale * v).collect(),
                })
            }))
            .chain(p.reference_curves.iter().filter_map(|r| {
                r.read().ok().map(|(x, y)| Series {
                    name: r.label.clone(),
                    x,
                    y,
                })
            }))
            .collect(),
            reference_lines: p
                .reference_metric
                .iter()
                .filter_map(|name| metrics.iter().find(|m| &m.name == name))
                .map(|m| ReferenceLine {
                    label: format!("{} reference", m.name),
                    y: m.reference,
                    band: band(m),
                })
                .collect(),
            log_log: false,
        })
        .collect()
}

fn band(m: &MetricResult) -> Option<[f64; 2]> {
    m.tolerance_kind.band(m.reference, m.tolerance)
}

/// The contact solver's record over a run of a scene with contact.
fn contact_stats(
    problem: &impact_solver::problem::Problem,
    run: &Execution,
) -> Option<crate::results::ContactSolverStats> {
    let pair = problem.contact.first()?;
    let summary = run.summary.as_ref()?;
    let t = summary.contact_totals;
    Some(crate::results::ContactSolverStats {
        solver: pair.solver.kind.name().to_string(),
        steps_with_contact: t.steps_with_contact,
        solves: t.solves,
        not_converged: t.not_converged,
        unresolved: t.unresolved,
        iterations: t.iterations,
        contact_seconds: summary.contact_seconds,
    })
}
