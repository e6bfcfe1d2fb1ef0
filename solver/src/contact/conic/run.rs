//! One `solve` call of the conic solver: Clarabel's settings and status in our terms, the
//! single program of the relaxed mode and the Tresca fixed point of the Coulomb mode.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus};

use super::program::{contact_laws, ConicProgram, Law};
use super::{associated_natural_map, ConicSolver};
use crate::contact::problem::{natural_map_error, ContactProblem};
use crate::contact::solver::{
    ContactSolver, ContactSolverError, SolveLimits, SolveStatus, SolverReport,
};

/// Clarabel settings for `limits`: quiet; gap and feasibility tolerances `tol`; infeasibility
/// tolerances never looser than Clarabel's default 1e-8, because a contact problem always has
/// the feasible point `r = 0` and a loose tolerance would only make false certificates likelier;
/// presolve off and structural zeros kept, so that the data updates of the Coulomb fixed point
/// stay allowed (presolve only drops rows with infinite `b`, which we never have).
fn clarabel_settings(limits: &SolveLimits, tol: f64, seconds_left: f64) -> DefaultSettings<f64> {
    DefaultSettings {
        verbose: false,
        max_iter: u32::try_from(limits.max_iterations).unwrap_or(u32::MAX),
        time_limit: seconds_left,
        tol_gap_abs: tol,
        tol_gap_rel: tol,
        tol_feas: tol,
        tol_infeas_abs: tol.min(1e-8),
        tol_infeas_rel: tol.min(1e-8),
        presolve_enable: false,
        input_sparse_dropzeros: false,
        ..DefaultSettings::default()
    }
}

/// One Clarabel solve: the status, its `x` and the interior-point iterations.
pub(super) struct Solve {
    pub(super) status: SolverStatus,
    pub(super) x: Vec<f64>,
    pub(super) iterations: usize,
}

impl Solve {
    /// The multipliers worth returning from this solve: none from infeasibility certificates
    /// (a direction, not a force) or from non-finite output.
    fn usable_x(&self) -> Option<&[f64]> {
        let certificate = matches!(
            self.status,
            SolverStatus::PrimalInfeasible
                | SolverStatus::DualInfeasible
                | SolverStatus::AlmostPrimalInfeasible
                | SolverStatus::AlmostDualInfeasible
                | SolverStatus::Unsolved
        );
        (!certificate && self.x.iter().all(|v| v.is_finite())).then_some(&self.x)
    }
}

/// Clarabel's status in our terms; `AlmostSolved` is decided by the caller (see
/// [`Run::judge_almost_solved`]) and appears here as a failure.
fn map_status(status: SolverStatus) -> SolveStatus {
    match status {
        SolverStatus::Solved => SolveStatus::Converged,
        SolverStatus::MaxIterations => SolveStatus::MaxIterations,
        SolverStatus::MaxTime => SolveStatus::TimeLimit,
        other => SolveStatus::Failed(format!("{other:?}")),
    }
}

/// The state of one `solve` call: limits, clock, counters, notes.
pub(super) struct Run<'a> {
    solver_name: String,
    max_outer: usize,
    problem: &'a ContactProblem,
    limits: &'a SolveLimits,
    clock: Instant,
    /// Clarabel's gap and feasibility tolerance for each solve.
    inner_tolerance: f64,
    iterations: usize,
    pub(super) outer_iterations: usize,
    notes: Vec<String>,
}

impl<'a> Run<'a> {
    pub(super) fn new(
        solver: &ConicSolver,
        problem: &'a ContactProblem,
        limits: &'a SolveLimits,
        clock: Instant,
    ) -> Self {
        Self {
            solver_name: solver.name(),
            max_outer: solver.max_outer,
            problem,
            limits,
            clock,
            inner_tolerance: limits.tolerance,
            iterations: 0,
            outer_iterations: 0,
            notes: Vec::new(),
        }
    }

    pub(super) fn note_asymmetry(&mut self) {
        let (skew, norm) = self.problem.w.asymmetry();
        if skew > 0.0 {
            self.notes.push(format!(
                "W asymmetry ||W-W^T||_F/||W||_F = {:.1e} removed by symmetrisation",
                skew / norm
            ));
        }
    }

    pub(super) fn finish(self, r: Vec<f64>, status: SolveStatus) -> SolverReport {
        SolverReport {
            r,
            status,
            iterations: self.iterations,
            outer_iterations: self.outer_iterations,
            seconds: self.clock.elapsed().as_secs_f64(),
            notes: self.notes,
        }
    }

    /// Seconds left of `limits.time_limit` (infinite without one).
    fn seconds_left(&self) -> f64 {
        match self.limits.time_limit {
            Some(limit) => limit.as_secs_f64() - self.clock.elapsed().as_secs_f64(),
            None => f64::INFINITY,
        }
    }

    fn setup_error(&self, message: String, fix: &str) -> ContactSolverError {
        ContactSolverError::Setup {
            solver: self.solver_name.clone(),
            problem: self.problem.source.clone(),
            message,
            fix: fix.into(),
        }
    }

    /// A Clarabel solver for `program` with the time left.
    fn new_clarabel(
        &self,
        program: &ConicProgram,
    ) -> Result<DefaultSolver<f64>, ContactSolverError> {
        let settings = clarabel_settings(
            self.limits,
            self.inner_tolerance,
            self.seconds_left().max(0.0),
        );
        let built = catch_unwind(AssertUnwindSafe(|| {
            DefaultSolver::new(
                &program.p,
                &program.c,
                &program.a,
                &program.b,
                &program.cones,
                settings,
            )
        }));
        match built {
            Ok(Ok(solver)) => Ok(solver),
            Ok(Err(e)) => Err(self.setup_error(
                format!("Clarabel rejected the problem: {e}"),
                "use a finite tolerance > 0 and a problem whose W, q and mu sizes agree",
            )),
            Err(_) => Err(self.setup_error(
                "Clarabel panicked while setting up the problem".into(),
                "report the problem file; solve it with Gauss-Seidel meanwhile",
            )),
        }
    }

    /// Runs `solver` once and collects the result. A panic inside Clarabel becomes a failed
    /// status (the harness runs many problems; one must not end the run).
    fn run_clarabel(&mut self, solver: &mut DefaultSolver<f64>) -> Solve {
        let solved = catch_unwind(AssertUnwindSafe(|| solver.solve()));
        let solve = match solved {
            Ok(()) => Solve {
                status: solver.solution.status,
                x: solver.solution.x.clone(),
                iterations: solver.solution.iterations as usize,
            },
            Err(_) => Solve {
                status: SolverStatus::NumericalError,
                x: Vec::new(),
                iterations: 0,
            },
        };
        if solved.is_err() {
            self.notes.push("Clarabel panicked during solve".into());
        }
        self.iterations += solve.iterations;
        solve
    }

    /// Builds and runs one program (no reuse).
    pub(super) fn solve_once(
        &mut self,
        program: &ConicProgram,
    ) -> Result<Solve, ContactSolverError> {
        let mut solver = self.new_clarabel(program)?;
        Ok(self.run_clarabel(&mut solver))
    }

    /// `AlmostSolved` met only Clarabel's reduced tolerances (5e-5 by default). We accept it as
    /// converged only when the residual we can check ourselves, the natural map of the problem
    /// this mode really solves at `r`, is within `limits.tolerance`; a note says which way it
    /// went.
    fn judge_almost_solved(&mut self, residual: f64) -> SolveStatus {
        let accepted = residual <= self.limits.tolerance;
        self.notes.push(format!(
            "Clarabel reported AlmostSolved; natural-map residual {residual:.1e} {} tolerance \
             {:.1e}: {}",
            if accepted { "<=" } else { ">" },
            self.limits.tolerance,
            if accepted {
                "accepted as converged"
            } else {
                "reported as failed"
            },
        ));
        if accepted {
            SolveStatus::Converged
        } else {
            SolveStatus::Failed("AlmostSolved".into())
        }
    }

    /// Result of a single program (frictionless, stick, relaxed): `r` and status.
    pub(super) fn conclude_single(
        &mut self,
        program: &ConicProgram,
        solve: Solve,
    ) -> (Vec<f64>, SolveStatus) {
        let r = match solve.usable_x() {
            Some(x) => program.r_of(x),
            None => vec![0.0; program.size],
        };
        let status = if solve.status == SolverStatus::AlmostSolved {
            let residual = associated_natural_map(self.problem, &r);
            self.judge_almost_solved(residual)
        } else {
            map_status(solve.status)
        };
        (r, status)
    }

    /// Coulomb by a fixed point on the normal force (Acary, Cadoux, Lemarechal & Malick 2011):
    /// `s^0 = 0`, i.e. the start is the frictionless solution (Coulomb contacts with `r_T = 0`,
    /// a QP in fewer variables); then repeat: solve the Tresca problem `|r_T,a| <= s_a`,
    /// `r_N >= 0`, set `s_a = mu_a r_N,a`, until `||r_N^k - r_N^(k-1)|| <= tol ||r_N^k||`.
    ///
    /// The Tresca program keeps its structure between iterations; only the bounds in `b`
    /// change, so one Clarabel solver is reused with `update_b` (Clarabel has no warm start:
    /// each solve starts from its own initial point, the reuse saves setup and the symbolic
    /// factorisation). If Clarabel does not allow the update, the solver is rebuilt.
    ///
    /// The conic solves use `tolerance / 10` (ACLM 2011: inner tolerance a tenth of the outer
    /// one): with the same tolerance, the change of `r_N` between solves sat at the solves' own
    /// noise, about 1e-7 at 1e-8 (measured on `confeti-ex13-4contact-fc3d-sbm`: 12 instead of 7
    /// outer iterations, convergence by chance).
    ///
    /// A bound `s_a = 0` (a contact with no normal force in the previous iterate) gives an SOC
    /// without interior, `|r_T| <= 0`, so Slater's condition fails. Clarabel (0.11, homogeneous
    /// embedding) copes: with every bound 0 on contacts loaded to slide it reports Solved in as
    /// many iterations as the frictionless QP and returns that QP's solution to 1e-7, `r_T` at
    /// roundoff (unit test `a_zero_tresca_bound_is_solved_with_zero_tangential_force`); the
    /// external problems, with many separated contacts, gave no other status. Such contacts
    /// therefore stay in the cone, with no special case. Bounds are `mu max(r_N, 0)`, so a
    /// slightly negative `r_N` from the interior-point tolerance never makes the cone empty.
    pub(super) fn coulomb_fixed_point(
        &mut self,
    ) -> Result<(Vec<f64>, SolveStatus), ContactSolverError> {
        let problem = self.problem;
        self.inner_tolerance = self.limits.tolerance / 10.0;
        let start_laws = contact_laws(problem, |_| Law::Frictionless);
        let start_program = ConicProgram::build(problem, &start_laws);
        let start = self.solve_once(&start_program)?;
        let (mut r, status) = self.conclude_single(&start_program, start);
        if !status.converged() {
            self.notes.push(format!(
                "the frictionless start of the Coulomb fixed point ended {}",
                status.label()
            ));
            return Ok((r, status));
        }

        let bounds = |r: &[f64]| -> Vec<f64> {
            problem
                .mu
                .iter()
                .enumerate()
                .map(|(a, &mu)| {
                    if mu > 0.0 && mu.is_finite() {
                        mu * r[3 * a].max(0.0)
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let laws = contact_laws(problem, |_| Law::Tresca { bound: 0.0 });
        let mut program = ConicProgram::build(problem, &laws);
        program.b = program.b_with_bounds(&bounds(&r));
        let mut clarabel = self.new_clarabel(&program)?;
        let mut rebuilt = false;
        let mut almost = false;
        let mut change = f64::INFINITY;
        for outer in 1..=self.max_outer {
            if outer > 1 {
                let left = self.seconds_left();
                if left <= 0.0 {
                    return Ok((r, SolveStatus::TimeLimit));
                }
                program.b = program.b_with_bounds(&bounds(&r));
                let updated = clarabel.is_data_update_allowed()
                    && clarabel.update_b(&program.b).is_ok()
                    && clarabel
                        .update_settings(clarabel_settings(self.limits, self.inner_tolerance, left))
                        .is_ok();
                if !updated {
                    if !rebuilt {
                        self.notes.push(
                            "Clarabel refused the data update; the Tresca solver is rebuilt \
                             each outer iteration"
                                .into(),
                        );
                        rebuilt = true;
                    }
                    clarabel = self.new_clarabel(&program)?;
                }
            }
            self.outer_iterations = outer;
            let solve = self.run_clarabel(&mut clarabel);
            match solve.status {
                SolverStatus::Solved => {}
                SolverStatus::AlmostSolved => almost = true,
                other => {
                    // The previous iterate solved its own problem; this one did not.
                    self.notes
                        .push(format!("Tresca solve {outer} ended {other:?}"));
                    return Ok((r, map_status(other)));
                }
            }
            let Some(x) = solve.usable_x() else {
                return Ok((r, SolveStatus::Failed("non-finite Tresca solution".into())));
            };
            let next = program.r_of(x);
            change = normal_change(&r, &next);
            r = next;
            if change <= self.limits.tolerance {
                let status = if almost {
                    let residual = natural_map_error(problem, &r).relative;
                    self.judge_almost_solved(residual)
                } else {
                    SolveStatus::Converged
                };
                return Ok((r, status));
            }
        }
        self.notes.push(format!(
            "Coulomb fixed point: {} Tresca solves without the normal forces settling; last \
             relative change {change:.1e} > tolerance {:.1e}",
            self.max_outer, self.limits.tolerance
        ));
        Ok((r, SolveStatus::MaxIterations))
    }
}

/// `||r_N^new - r_N^old||_2 / ||r_N^new||_2`: 0 when they are equal (also both zero), infinite
/// when they differ and the new normal forces are all zero.
fn normal_change(old: &[f64], new: &[f64]) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for (o, n) in old.iter().step_by(3).zip(new.iter().step_by(3)) {
        diff += (n - o) * (n - o);
        norm += n * n;
    }
    if diff == 0.0 {
        0.0
    } else if norm == 0.0 {
        f64::INFINITY
    } else {
        (diff / norm).sqrt()
    }
}
