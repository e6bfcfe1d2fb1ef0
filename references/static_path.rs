//! The peak of a case's own scene solved by the implicit static solver along the same loading:
//! Newton's method on each load step from the committed material history, no inertia, stopping
//! at the limit point of the loading (`solver/src/statics/path.rs`).
//!
//! An explicit run that is quasi-static should find the same peak: this checks it along another
//! integrator (equilibrium at every step instead of a slow dynamic loading), on the same mesh and
//! material.

use crate::error::ReferenceError;
use impact_solver::scene::{build_problem, Analysis, Scene};
use impact_solver::statics::{solve_static, StaticSettings};
use serde::{Deserialize, Serialize};

/// The static settings of the path (`end_time`: the time of the scene's loading functions that
/// the path ends at) and the history column whose largest magnitude is the reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticPathSpec {
    /// Load steps, tolerance and `end_time` of the static path.
    pub settings: StaticSettings,
    /// Name of the history column (a probe or reaction component) whose largest magnitude
    /// along the path is the reference.
    pub peak_of: String,
}

/// Largest magnitude of the `peak_of` column along the static path of the case's scene, and a
/// line saying how it was computed.
pub fn static_path_peak(
    scene: &Scene,
    spec: &StaticPathSpec,
) -> Result<(f64, String), ReferenceError> {
    let mut statics = scene.clone();
    statics.analysis = Analysis::Static(spec.settings.clone());
    let problem = build_problem(&statics)?;
    let solution = solve_static(&problem, &spec.settings)?;
    let history = solution.history.as_ref().ok_or(ReferenceError::NoHistory)?;
    let column = history
        .column(&spec.peak_of)
        .ok_or_else(|| ReferenceError::NoColumn {
            column: spec.peak_of.clone(),
            columns: history.columns().to_vec(),
        })?;
    let (index, peak) = column
        .iter()
        .enumerate()
        .fold((0, 0.0_f64), |(i, p), (j, v)| {
            if v.abs() > p {
                (j, v.abs())
            } else {
                (i, p)
            }
        });
    let time = history.column("time").map_or(f64::NAN, |t| t[index]);
    Ok((
        peak,
        format!(
            "implicit static path of the same scene ({} elements; Newton from the committed \
             history, forward-difference tangent, {} load steps to t = {} s, tolerance {:.0e}): \
             largest |{}| at t = {time:.4} s, {} of {} load steps converged{}",
            problem.model.element_count(),
            spec.settings.load_steps,
            spec.settings.end_time,
            spec.settings.tolerance,
            spec.peak_of,
            solution.iterations.len(),
            spec.settings.load_steps,
            solution
                .stopped
                .as_ref()
                .map_or(String::new(), |s| format!("; stopped at its {s}"))
        ),
    ))
}
