//! The static loading path of a model with bodies whose material has a history (microplane
//! concrete): load steps under the prescribed displacements, Newton's method on each step from the
//! history committed at the last one, step cutting, and a stop at the path's limit point.
//!
//! Within a load step from `u_c` (history `H_c`, both committed) to load factor `lambda`, a trial
//! displacement `u` gives every microplane element its stress from `H_c` and the strain at `u`:
//! one update of the model from its committed history, never a chain of trial updates, so the
//! out-of-balance force `r(u) = f_int(u) - f_ext` (3.64) is a function of `u` alone and Newton's
//! method applies to it. The step's history is committed once `|r|` on the free components is
//! below `tolerance` times the force scale of the path: the largest of the reaction and external
//! force norms, now or at any step committed before. The largest so far, not only the present
//! one: once a band has softened through, the reaction falls towards zero (0.03 N at the end of
//! a prism that carried 26 kN) and a tolerance relative to it asks for a residual below the
//! round-off of the forces, which no iteration reaches.
//!
//! The tangent (3.66): the model has no closed-form consistent tangent, so a microplane element's
//! stiffness is its forward difference from the same committed history,
//! `K_e[:, j] = (f_e(u_e + delta e_j) - f_e(u_e)) / delta` with `delta = 1e-10 h_e`. The step is
//! set by the kinks of the model, not by the curvature of its laws: a plane is on its virgin law
//! or on its unloading line, and on a short load step many planes are within a strain of 1e-8
//! of their turning point. A difference step that crosses such a kink gives a column that is the
//! derivative of neither branch, and Newton's iteration stalls on it (with `delta = 1e-7 h_e` an
//! opening-controlled prism path stopped at load factors 0.18 and 0.022 with 1 000 and 10 000
//! load steps, each time at a relative residual of 1e-6 to 5e-6, where the second difference of
//! the forces showed kinks 1e-9 to 1e-8 away). The laws are smooth between kinks and evaluated in
//! `f64` from the committed `f32` history, so the forces are known to about 1e-11 N and the
//! difference over 5e-12 m (a 5 cm element) is accurate to about 1e-8 of the elastic stiffness.
//! Elastic elements keep their consistent tangent (3.68a).
//! The strain rate of a static path is zero: the rate law gives `F(0) = 1`, the static law.
//!
//! Newton starts each step from the last converged increment extrapolated (a secant predictor),
//! not from the committed state (the comment in [`solve_path`] says why). Under an
//! [`super::OpeningControl`] the loading condition's displacement is one more unknown and the
//! opening between two probes is prescribed (`opening_control.rs`).
//!
//! The path follows its primary branch and does not switch branches. Where a crack may form in
//! any of several equivalent places (two cell columns at the mid-span of an unnotched beam), the
//! primary branch spreads the damage over them past the point where one should take it: an
//! imperfection (a notch, a slightly weaker element) decides, as the dynamics do in an explicit
//! run (`cases/beam/static-3pt-slice-h50-implicit-imperfect.yaml`).
//!
//! A step that does not converge in `max_iterations` (or that inverts an element) is halved, up
//! to `max_cuts` times; after a converged step the next one grows back by a factor of two, up to
//! the nominal `1 / load_steps`. Past the last cut the path has reached a limit point of this
//! control (under load-point control, the peak of a beam that snaps back after it): it stops there
//! and returns what it computed, with the reason in [`StaticSolution::stopped`]. Under opening
//! control the path has no limit point, but the branch that Newton's iteration follows from the
//! committed state can fold where the elements of a band deform unequally: past the last cut
//! such a step is solved again by pseudo-transient continuation (`relaxation.rs`), and the path
//! stops only if that fails too. It stops the
//! same way where a converged step moves a node farther than its body's size ([`lost_support`]).

use nalgebra::Vector3;
use rayon::prelude::*;

use super::inverted::Inverted;
use super::opening_control::Control;
use super::relaxation::{Relaxation, RELAXATION_ITERATIONS};
use super::rigid_body::{check_loaded, FreePiece};
use super::tangent::{forward_difference_tangents, solve_tangent, TangentTerms};
use super::{prescribe, StaticSettings, StaticSolution};
use crate::error::{Result, SolverError};
use crate::material::ElementState;
use crate::model::MaterialHistory;
use crate::output::HistoryTable;
use crate::problem::Problem;

/// Follows the loading path of `problem` from rest to load factor 1 (see the module
/// documentation), reporting the load factor reached.
pub(super) fn solve_path(
    problem: &Problem,
    settings: &StaticSettings,
    equation: &[[usize; 3]],
    free: usize,
    free_pieces: &[FreePiece],
    progress: &mut dyn FnMut(f64),
    stop: Option<&std::sync::atomic::AtomicBool>,
) -> Result<StaticSolution> {
    let model = &problem.model;
    let n = model.node_count();
    let constraint_of = problem.constraint_map();
    let control = settings
        .opening_control
        .as_ref()
        .map(|c| Control::new(c, problem, equation))
        .transpose()?;
    let mut table = HistoryTable::new(history_columns(problem, control.is_some()));
    let mut committed = Committed {
        u: vec![Vector3::zeros(); n],
        reaction: vec![Vector3::zeros(); n],
        history: model.initial_history(),
    };
    table.push(history_row(
        problem,
        &constraint_of,
        &committed,
        control.as_ref(),
        0.0,
        0,
        0,
        0.0,
    ));
    let nominal = 1.0 / settings.load_steps.max(1) as f64;
    let (mut lambda, mut cuts, mut step) = (0.0_f64, 0_u32, 0_usize);
    // The last converged increment, for the predictor: its displacement change and its size.
    let mut last_increment: Option<(Vec<Vector3<f64>>, f64)> = None;
    let (mut iterations, mut residuals) = (Vec::new(), Vec::new());
    let mut stopped = None;
    let mut interrupted_at = None;
    // The force scale of the convergence test: the largest reaction or external force norm of
    // the committed steps (see the module documentation).
    let mut path_scale = 0.0_f64;
    let sizes = body_sizes(problem);
    while lambda < 1.0 - 1e-12 {
        let size = (nominal / f64::from(1_u32 << cuts)).min(1.0 - lambda);
        let target = if 1.0 - (lambda + size) < 1e-12 {
            1.0
        } else {
            lambda + size
        };
        // Linear extrapolation of the last increment (a secant predictor): Newton then starts,
        // and takes its first tangent, where every loading plane is past its committed state by
        // a finite step. At the committed state itself a forward difference straddles the
        // loading-unloading switch of each plane (loading for columns that stretch it,
        // unloading for those that shorten it), and that mixture is no linearisation along any
        // path: on the slice beam under opening control it made the opening's response to the
        // plate 20 times too small at 60 % of the peak.
        let predicted = secant_prediction(&committed.u, last_increment.as_ref(), size);
        let trial = Step {
            problem,
            settings,
            equation,
            free,
            constraint_of: &constraint_of,
            control: control.as_ref(),
            committed: &committed,
            free_pieces,
            lambda: target,
            predicted: predicted.as_deref(),
            path_scale,
        };
        let outcome = solved_or_relaxed(&trial, cuts >= settings.max_cuts && control.is_some())?;
        match outcome {
            Outcome::Converged {
                state,
                iterations: it,
                residual,
                scale,
            } => {
                path_scale = path_scale.max(scale);
                if let Some(why) = lost_support(problem, &sizes, &state.u) {
                    stopped = Some(format!(
                        "lost support at load factor {target:.6}: {why}; the path ends at {lambda:.6}"
                    ));
                    break;
                }
                let du = state
                    .u
                    .iter()
                    .zip(&committed.u)
                    .map(|(a, b)| a - b)
                    .collect();
                last_increment = Some((du, target - lambda));
                committed = state;
                lambda = target;
                step += 1;
                iterations.push(it);
                residuals.push(residual);
                let time = lambda * settings.end_time;
                table.push(history_row(
                    problem,
                    &constraint_of,
                    &committed,
                    control.as_ref(),
                    time,
                    step,
                    it,
                    residual,
                ));
                progress(lambda);
                if stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed)) {
                    interrupted_at = Some((step, time));
                    break;
                }
                cuts = cuts.saturating_sub(1);
            }
            Outcome::Failed { reason } if cuts >= settings.max_cuts => {
                stopped = Some(path_end(
                    control.is_some(),
                    lambda,
                    target,
                    size / nominal,
                    cuts,
                    &reason,
                ));
                break;
            }
            Outcome::Failed { .. } => cuts += 1,
        }
    }
    Ok(StaticSolution {
        u: committed.u,
        reaction: committed.reaction,
        iterations,
        residuals,
        linear_iterations: Vec::new(),
        history: Some(table),
        material_history: Some(committed.history),
        stopped,
        interrupted_at,
    })
}

/// Linear extrapolation of the last converged increment `(du, its size)` to a step of `size`
/// (a secant predictor; see [`solve_path`]); `None` before the first increment.
fn secant_prediction(
    committed: &[Vector3<f64>],
    last_increment: Option<&(Vec<Vector3<f64>>, f64)>,
    size: f64,
) -> Option<Vec<Vector3<f64>>> {
    last_increment.map(|(du, size_before)| {
        let ratio = size / size_before;
        committed
            .iter()
            .zip(du)
            .map(|(u, du)| u + du * ratio)
            .collect::<Vec<_>>()
    })
}

/// The step `trial` solved; with `relax` (under opening control, at the last cut) a step that
/// fails is solved again, relaxed: it has met a fold of the branch it followed, not a limit
/// point of the path.
fn solved_or_relaxed(trial: &Step<'_>, relax: bool) -> Result<Outcome> {
    Ok(match trial.solve(false)? {
        Outcome::Failed { reason } if relax => match trial.solve(true)? {
            Outcome::Failed { reason: relaxed } => Outcome::Failed {
                reason: format!("{reason}; relaxed, it {relaxed}"),
            },
            converged => converged,
        },
        outcome => outcome,
    })
}

/// Why the path ends where a step fails after its last halving: under load-point control the
/// path's limit point; under opening control (`controlled`), where the path has none, a fold
/// that the relaxation did not cross either.
fn path_end(
    controlled: bool,
    lambda: f64,
    target: f64,
    fraction: f64,
    cuts: u32,
    reason: &str,
) -> String {
    let what = if controlled {
        "no balanced state past"
    } else {
        "limit point at"
    };
    format!(
        "{what} load factor {lambda:.6}: the step to {target:.6} ({fraction} of the nominal \
         step, after {cuts} halvings) {reason}"
    )
}

/// The size of each body: the diagonal of its reference bounding box (m), the yardstick of
/// [`lost_support`].
fn body_sizes(problem: &Problem) -> Vec<f64> {
    let model = &problem.model;
    model
        .bodies
        .iter()
        .map(|body| {
            let (lo, hi) = crate::mesh::bounding_box(&model.reference[body.nodes.clone()]);
            (hi - lo).norm()
        })
        .collect()
}

/// Why the converged displacement `u` cannot be a static state: a node of a body moved farther
/// than the body's own size (`sizes`, from [`body_sizes`]). A static path's strains stay far
/// below one, so such a motion is rigid, and a rigid motion that no force resists is set by
/// round-off: a piece that a crack has cut free with nothing holding it (the far end of a prism
/// whose pulled face is held only along the pull slid 0.7 m sideways by the end of its path).
/// `None` when every body stays within its size.
fn lost_support(problem: &Problem, sizes: &[f64], u: &[Vector3<f64>]) -> Option<String> {
    problem
        .model
        .bodies
        .iter()
        .zip(sizes)
        .find_map(|(body, &size)| {
            let (node, moved) = body
                .nodes
                .clone()
                .map(|n| (n, u[n].norm()))
                .max_by(|a, b| a.1.total_cmp(&b.1))?;
            (moved > size).then(|| {
                format!(
                    "node {node} of body `{}` moved {moved:.3e} m, more than the body's size \
                     ({size:.3e} m): a piece of it has no support (a crack has cut it free, or a \
                     rigid motion is unrestrained); hold it with a boundary condition",
                    body.name
                )
            })
        })
}

/// A converged state of the path.
struct Committed {
    u: Vec<Vector3<f64>>,
    /// `f_int - f_ext` at the prescribed components, zero at the free ones.
    reaction: Vec<Vector3<f64>>,
    history: MaterialHistory,
}

enum Outcome {
    Converged {
        state: Committed,
        iterations: usize,
        /// `|r|` relative to `scale`.
        residual: f64,
        /// The force scale the step was judged on.
        scale: f64,
    },
    Failed {
        reason: String,
    },
}

/// One load step of the path, from the committed state to load factor `lambda`.
struct Step<'a> {
    problem: &'a Problem,
    settings: &'a StaticSettings,
    equation: &'a [[usize; 3]],
    free: usize,
    constraint_of: &'a [[Option<u16>; 3]],
    control: Option<&'a Control>,
    committed: &'a Committed,
    /// The pieces of the mesh free to move as a rigid body, refused if loaded.
    free_pieces: &'a [FreePiece],
    /// Where Newton starts, if not at the committed displacement (prescribed components are
    /// set anyway).
    predicted: Option<&'a [Vector3<f64>]>,
    lambda: f64,
    /// The largest force scale of the committed steps.
    path_scale: f64,
}

impl Step<'_> {
    fn solve(&self, relaxed: bool) -> Result<Outcome> {
        let problem = self.problem;
        let n = problem.model.node_count();
        let time = self.lambda * self.settings.end_time;
        let mut u = self.predicted.unwrap_or(&self.committed.u).to_vec();
        prescribe(problem, self.constraint_of, time, &mut u);
        let target_opening = self.control.map(|c| {
            // The controlled condition keeps its (predicted) displacement, not its function's.
            c.set_delta(&mut u, c.delta(self.predicted.unwrap_or(&self.committed.u)));
            c.opening.eval(time)
        });
        let mut f_ext = vec![Vector3::zeros(); n];
        if !problem.external_forces(time, &mut f_ext) {
            f_ext.iter_mut().for_each(|f| *f = Vector3::zeros());
        }
        check_loaded(self.free_pieces, &f_ext)?;
        let mut last = f64::INFINITY;
        let (max_iterations, mut relaxation) = if relaxed {
            let model = &problem.model;
            let tau_0 = model.critical_time_step().0;
            let relaxation = Relaxation::new(self.equation, self.free, &model.mass, tau_0);
            (RELAXATION_ITERATIONS, Some(relaxation))
        } else {
            (self.settings.max_iterations, None)
        };
        for iteration in 0..=max_iterations {
            let (f_int, history) = match trial_forces(problem, &u, &self.committed.history) {
                Ok(forces) => forces,
                Err(inverted) => {
                    return Ok(Outcome::Failed {
                        reason: format!(
                            "inverted element {} at iteration {iteration} ({})",
                            inverted.element,
                            inverted.describe(problem, &u, &self.committed.u)
                        ),
                    })
                }
            };
            let mut residual = vec![0.0; self.free];
            let mut reaction = vec![Vector3::zeros(); n];
            let (mut reaction_sq, mut external_sq) = (0.0, 0.0);
            for i in 0..n {
                for d in 0..3 {
                    let r = f_int[i][d] - f_ext[i][d];
                    external_sq += f_ext[i][d] * f_ext[i][d];
                    match self.equation[i][d] {
                        usize::MAX => {
                            reaction_sq += r * r;
                            reaction[i][d] = r;
                        }
                        k => residual[k] = r,
                    }
                }
            }
            let scale = reaction_sq
                .sqrt()
                .max(external_sq.sqrt())
                .max(self.path_scale);
            let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            last = if scale > 0.0 { norm / scale } else { norm };
            // The opening is linear in `u`: Newton's first iteration meets it to round-off.
            let opening_residual = match (self.control, target_opening) {
                (Some(c), Some(target)) => c.opening_of(&u) - target,
                _ => 0.0,
            };
            let opening_error =
                opening_residual.abs() / target_opening.map_or(1.0, |t| t.abs().max(1e-300));
            if (norm <= self.settings.tolerance * scale || norm == 0.0) && opening_error < 1e-9 {
                return Ok(Outcome::Converged {
                    state: Committed {
                        u,
                        reaction,
                        history,
                    },
                    iterations: iteration,
                    residual: last,
                    scale,
                });
            }
            if !last.is_finite() || iteration == max_iterations {
                break;
            }
            let shift = relaxation.as_mut().map(|r| r.shift(norm));
            let tangents = forward_difference_tangents(problem, &u, &self.committed.history);
            // At a limit point the tangent of this control is singular: a step that meets one
            // fails like one that does not converge, and is cut.
            // Under opening control, bordering (Batoz & Dhatt 1979): with `a = K^-1 r` and
            // `b = K^-1 k` (`k` the summed columns of the moved components), the step
            // `du = -a - b d_delta` meets the opening when `d_delta = (r_g - G a) / (G b)`.
            let solved = solve_tangent(
                problem,
                &u,
                self.equation,
                self.free,
                &residual,
                &tangents,
                TangentTerms {
                    moved: self.control.map(|c| c.moved_mask.as_slice()),
                    diagonal: shift.as_deref(),
                },
            );
            let (a, b) = match solved {
                Ok(ab) => ab,
                Err(SolverError::SingularStiffness(why)) => {
                    return Ok(Outcome::Failed {
                        reason: format!("met a singular tangent at iteration {iteration} ({why})"),
                    })
                }
                Err(e) => return Err(e),
            };
            let d_delta = match (self.control, b.as_deref()) {
                (Some(c), Some(b)) => (opening_residual - c.along(&a)) / c.along(b),
                _ => 0.0,
            };
            for (ui, eq) in u.iter_mut().zip(self.equation) {
                for d in 0..3 {
                    if eq[d] != usize::MAX {
                        ui[d] -= a[eq[d]] + b.as_ref().map_or(0.0, |b| b[eq[d]] * d_delta);
                    }
                }
            }
            if let Some(c) = self.control {
                let delta = c.delta(&u) + d_delta;
                c.set_delta(&mut u, delta);
            }
        }
        // A relaxation that does not balance the step may be moving a piece that nothing holds:
        // how far it went tells.
        let motion = if relaxed {
            let (node, moved) = u
                .iter()
                .zip(&self.committed.u)
                .map(|(a, b)| (a - b).norm())
                .enumerate()
                .fold(
                    (0, 0.0),
                    |best, (i, m)| if m > best.1 { (i, m) } else { best },
                );
            format!("; it moved node {node} by {moved:.3e} m")
        } else {
            String::new()
        };
        Ok(Outcome::Failed {
            reason: format!(
                "did not converge in {max_iterations} iterations (relative residual {last:.3e}, \
                 tolerance {:.1e}){motion}",
                self.settings.tolerance
            ),
        })
    }
}

/// Internal forces at `u`, each element of a material with a history updated once from its
/// `committed` history; the updated (trial) history with them, or the first inverted element.
/// The sum at every node runs over its elements in ascending order (elements are evaluated in
/// parallel, summed in order), so the result does not depend on the number of threads.
fn trial_forces(
    problem: &Problem,
    u: &[Vector3<f64>],
    committed: &MaterialHistory,
) -> std::result::Result<(Vec<Vector3<f64>>, MaterialHistory), Inverted> {
    let model = &problem.model;
    let mut history = committed.clone();
    let mut f = vec![Vector3::zeros(); model.node_count()];
    for (b, body) in model.bodies.iter().enumerate() {
        let elements = body.elements.clone();
        let material = &*body.material;
        let force = |e: usize, state: &mut [f32], cauchy: Option<&mut [f64; 6]>| {
            let local = e - elements.start;
            let update = material.static_element_forces(
                local,
                &model.grad_n(e),
                model.volume(e),
                &model.element_displacements(e, u),
                ElementState {
                    history: state,
                    cauchy,
                },
            );
            (update.forces, update.det)
        };
        let forces: Vec<([Vector3<f64>; 4], f64)> = match history.bodies[b].as_mut() {
            Some(trial) => {
                let len = trial.state_len;
                trial
                    .values
                    .par_chunks_mut(len)
                    .zip(trial.cauchy.par_iter_mut())
                    .enumerate()
                    .map(|(local, (state, cauchy))| {
                        force(elements.start + local, state, Some(cauchy))
                    })
                    .collect()
            }
            None => elements
                .clone()
                .into_par_iter()
                .map(|e| force(e, &mut [], None))
                .collect(),
        };
        for (e, (fe, det)) in elements.zip(forces) {
            if !(det > 0.0) {
                return Err(Inverted { element: e, det });
            }
            for (&node, fa) in model.tets[e].iter().zip(fe) {
                f[node as usize] += fa;
            }
        }
    }
    Ok((f, history))
}

/// Columns of the path's history: the time of the conditions' functions (the load factor times
/// `end_time`), the load step, its Newton iterations and final relative residual, under opening
/// control the opening and the controlled displacement, then the probes and the reactions of
/// each condition named as in an explicit run's history (`<probe>_<x|y|z>`,
/// `<condition>_reaction_<x|y|z>`).
fn history_columns(problem: &Problem, controlled: bool) -> Vec<String> {
    let mut c: Vec<String> = ["time", "step", "iterations", "residual"]
        .map(String::from)
        .to_vec();
    if controlled {
        c.extend(["control_opening", "control_displacement"].map(String::from));
    }
    c.extend(problem.probe_columns());
    c
}

#[allow(clippy::too_many_arguments)]
fn history_row(
    problem: &Problem,
    constraint_of: &[[Option<u16>; 3]],
    state: &Committed,
    control: Option<&Control>,
    time: f64,
    step: usize,
    iterations: usize,
    residual: f64,
) -> Vec<f64> {
    let mut row = vec![time, step as f64, iterations as f64, residual];
    if let Some(c) = control {
        row.extend([c.opening_of(&state.u), c.delta(&state.u)]);
    }
    problem.push_probe_values(&mut row, &state.u, None, &state.reaction, constraint_of);
    row
}
