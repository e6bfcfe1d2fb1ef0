//! Contact as a conic program solved by Clarabel (FORMULATION section 4, "Conic solver").
//!
//! Every mode minimises the quadratic `1/2 r^T W r + q^T r` over the multipliers `r` (three per
//! contact, local order `[normal, t1, t2]`) on a product of cones, one factor per contact:
//!
//! - frictionless (`mu = 0`): `r_N >= 0`, `r_T = 0`. The tangential components are eliminated
//!   from the program (they are not variables at all), so a frictionless problem is the QP in the
//!   normal components with `P = W_NN`. Its optimality conditions are Signorini's, so the result
//!   is the exact solution of FC(W, q, 0). (A second-order cone with `mu = 0` is never used: it
//!   would force `r_T = 0` but leave `r_N` free.)
//! - stick (`mu = inf`): `r_N >= 0`, `r_T` free; optimality gives `u_T = 0`, the stick law.
//! - Coulomb (`0 < mu < inf`) depends on [`ConicMode`]:
//!   - [`ConicMode::Relaxed`]: `(mu r_N, r_T)` in a second-order cone, one SOCP. This is the
//!     associated (convex) relaxation of Coulomb's law (Anitescu & Tasora 2010; Acary, Cadoux,
//!     Lemarechal & Malick 2011, "convex relaxation"): its optimality conditions are
//!     `K ∋ r _|_ u ∈ K*` without the De Saxce shift, so a sliding contact opens normally,
//!     `u_N = mu |u_T|`, about `mu` times its slip. It is not the Coulomb solution.
//!   - [`ConicMode::Coulomb`]: a fixed point on the normal force (Acary, Cadoux, Lemarechal &
//!     Malick 2011, the Tresca fixed point): solve Tresca problems `|r_T| <= s_a`, `r_N >= 0` with
//!     `s_a = mu_a r_N,a` of the previous iterate, until the normal forces stop changing. A fixed
//!     point satisfies Coulomb's law exactly; convergence is not guaranteed (it is for small `mu`
//!     times the normal-tangential coupling), hence the cap [`ConicSolver::max_outer`].
//!
//! Clarabel solves `min 1/2 x^T P x + c^T x` s.t. `A x + s = b`, `s ∈ K`, reading only the upper
//! triangle of `P`; `P = (W + W^T)/2` is built explicitly and any asymmetry of `W` is reported
//! in the notes, because a one-triangle solver otherwise solves a different problem unnoticed.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::Vector3;

use super::problem::{
    contact_natural_map, natural_map_error, project_on_coulomb_cone, ContactProblem,
};
use super::solver::{ContactSolver, ContactSolverError, SolveLimits, SolveStatus, SolverReport};

/// How Coulomb contacts (`0 < mu < inf`) enter the conic program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConicMode {
    /// One SOCP with the associated (convex) relaxation `(mu r_N, r_T) ∈ SOC`; sliding contacts
    /// open normally by about `mu` times their slip. Not Coulomb's law.
    Relaxed,
    /// Fixed point of Tresca problems on the normal force; converges to Coulomb's law.
    Coulomb,
}

/// FC(W, q, mu) as conic programs for Clarabel (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConicSolver {
    pub mode: ConicMode,
    /// Cap on the Tresca solves of the Coulomb fixed point (ignored by the relaxed mode).
    pub max_outer: usize,
}

impl ConicSolver {
    pub fn new(mode: ConicMode) -> Self {
        Self {
            mode,
            max_outer: 50,
        }
    }
}

impl ContactSolver for ConicSolver {
    fn name(&self) -> String {
        match self.mode {
            ConicMode::Relaxed => "conic/relaxed".into(),
            ConicMode::Coulomb => "conic/coulomb".into(),
        }
    }

    /// `limits.tolerance` is Clarabel's tolerance (duality gap, absolute and relative, and
    /// feasibility) of the single conic solve; in the Coulomb mode it bounds the relative change
    /// of the normal forces between two Tresca solves (2-norms), and each conic solve gets a
    /// tenth of it. `max_iterations` caps the interior-point iterations of each conic solve;
    /// `time_limit` covers the whole call (each solve gets the time left).
    ///
    /// Clarabel's tolerances are absolute where the objective is below one, so the program is
    /// solved on the problem scaled to `W / w` and `q / s` (`w` the mean diagonal of `W`, `s`
    /// the largest `|q|`); the solution `r = r~ s / w` is the same, because FC(W, q, mu) is
    /// homogeneous. Natural-map tests inside (AlmostSolved) read the scaled problem.
    fn solve(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
    ) -> Result<SolverReport, ContactSolverError> {
        let clock = Instant::now();
        validate(problem)?;
        let n = problem.w.size;
        let trace: f64 = (0..n).map(|i| problem.w.get(i, i)).sum();
        let w_scale = if trace > 0.0 { trace / n as f64 } else { 1.0 };
        let q_scale = problem.q.iter().fold(0.0f64, |m, q| m.max(q.abs()));
        if q_scale == 0.0 || (w_scale == 1.0 && q_scale == 1.0) {
            return self.solve_scaled(problem, limits, clock);
        }
        let mut scaled = problem.clone();
        scaled.w.values.iter_mut().for_each(|v| *v /= w_scale);
        scaled.q.iter_mut().for_each(|v| *v /= q_scale);
        let mut report = self.solve_scaled(&scaled, limits, clock)?;
        let back = q_scale / w_scale;
        report.r.iter_mut().for_each(|r| *r *= back);
        Ok(report)
    }
}

impl ConicSolver {
    fn solve_scaled(
        &mut self,
        problem: &ContactProblem,
        limits: &SolveLimits,
        clock: Instant,
    ) -> Result<SolverReport, ContactSolverError> {
        let mut run = Run::new(self, problem, limits, clock);
        run.note_asymmetry();
        if problem.contacts() == 0 {
            return Ok(run.finish(Vec::new(), SolveStatus::Converged));
        }
        let has_coulomb = problem.mu.iter().any(|m| *m > 0.0 && m.is_finite());
        let (r, status) = if self.mode == ConicMode::Coulomb && has_coulomb {
            run.coulomb_fixed_point()?
        } else {
            // One program: relaxed cones for Coulomb contacts (only reached in relaxed mode or
            // when there are none).
            let laws = contact_laws(problem, |mu| Law::Associated { mu });
            let program = ConicProgram::build(problem, &laws);
            let solve = run.solve_once(&program)?;
            run.outer_iterations = 1;
            run.conclude_single(&program, solve)
        };
        Ok(run.finish(r, status))
    }
}

/// The constraint one contact gets in a conic program.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    /// `r_N >= 0`; `r_T` eliminated (zero).
    Frictionless,
    /// `r_N >= 0`; `r_T` free.
    Stick,
    /// `(mu r_N, r_T) ∈ SOC(3)`: the associated relaxation.
    Associated { mu: f64 },
    /// `r_N >= 0` and `|r_T| <= bound` (an SOC whose axis entry is the constant `bound`).
    Tresca { bound: f64 },
}

/// Laws of all contacts: `mu = 0` frictionless, `mu = inf` stick, otherwise `coulomb(mu)`.
fn contact_laws(problem: &ContactProblem, coulomb: impl Fn(f64) -> Law) -> Vec<Law> {
    problem
        .mu
        .iter()
        .map(|&mu| {
            if mu == 0.0 {
                Law::Frictionless
            } else if mu.is_infinite() {
                Law::Stick
            } else {
                coulomb(mu)
            }
        })
        .collect()
}

/// Clarabel's data `P, c, A, b, K` for one set of contact laws, and how its variables map to `r`.
struct ConicProgram {
    /// Index into `r` (length `3 nc`) of each Clarabel variable.
    variables: Vec<usize>,
    p: CscMatrix<f64>,
    c: Vec<f64>,
    a: CscMatrix<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    /// Per contact, the row of `b` holding its Tresca bound (`None` for other laws).
    bound_rows: Vec<Option<usize>>,
    size: usize,
}

impl ConicProgram {
    fn build(problem: &ContactProblem, laws: &[Law]) -> Self {
        let size = problem.q.len();
        // Frictionless contacts keep only their normal component.
        let mut index_of = vec![None; size];
        let mut variables = Vec::with_capacity(size);
        for (a, law) in laws.iter().enumerate() {
            let kept = if *law == Law::Frictionless { 1 } else { 3 };
            for k in 0..kept {
                index_of[3 * a + k] = Some(variables.len());
                variables.push(3 * a + k);
            }
        }
        let p = build_p(problem, &index_of, variables.len());
        let c = variables.iter().map(|&i| problem.q[i]).collect();
        let rows = ConeRows::build(laws, &index_of);
        let a = CscMatrix::new_from_triplets(
            rows.b.len(),
            variables.len(),
            rows.rows,
            rows.columns,
            rows.values,
        );
        Self {
            variables,
            p,
            c,
            a,
            b: rows.b,
            cones: rows.cones,
            bound_rows: rows.bound_rows,
            size,
        }
    }

    /// `r` (local, `3 nc`) from Clarabel's `x`; eliminated components are zero.
    fn r_of(&self, x: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.size];
        for (&i, &v) in self.variables.iter().zip(x) {
            r[i] = v;
        }
        r
    }

    /// `b` with new Tresca bounds (`bounds[a]` for contacts that have one).
    fn b_with_bounds(&self, bounds: &[f64]) -> Vec<f64> {
        let mut b = self.b.clone();
        for (row, bound) in self.bound_rows.iter().zip(bounds) {
            if let Some(row) = row {
                b[*row] = *bound;
            }
        }
        b
    }
}

/// `P = (W + W^T)/2` restricted to the kept components, upper triangle in CSC: Clarabel reads
/// only that triangle, so the symmetrisation is made here, explicitly, rather than by omission.
fn build_p(problem: &ContactProblem, index_of: &[Option<usize>], n: usize) -> CscMatrix<f64> {
    let (mut rows, mut columns, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for (i, j, v) in problem.w.triplets() {
        let (Some(ki), Some(kj)) = (index_of[i], index_of[j]) else {
            continue;
        };
        // A diagonal entry counts once; W_ij and W_ji each add half to the upper entry.
        let (row, column, value) = if ki == kj {
            (ki, kj, v)
        } else {
            (ki.min(kj), ki.max(kj), 0.5 * v)
        };
        rows.push(row);
        columns.push(column);
        values.push(value);
    }
    CscMatrix::new_from_triplets(n, n, rows, columns, values)
}

/// The rows `A x + s = b`, `s ∈ K` of the contact laws: first one non-negative cone collecting
/// every `r_N >= 0` (`A = -1`, `b = 0`), then one `SOC(3)` per Coulomb contact (the first entry
/// of a Clarabel SOC is its axis).
struct ConeRows {
    rows: Vec<usize>,
    columns: Vec<usize>,
    values: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    bound_rows: Vec<Option<usize>>,
}

impl ConeRows {
    fn build(laws: &[Law], index_of: &[Option<usize>]) -> Self {
        let mut out = Self {
            rows: Vec::new(),
            columns: Vec::new(),
            values: Vec::new(),
            b: Vec::new(),
            cones: Vec::new(),
            bound_rows: vec![None; laws.len()],
        };
        let var = |a: usize, k: usize| index_of[3 * a + k].expect("kept component");
        // r_N >= 0 where the law needs it explicitly (the associated SOC implies it).
        let mut nonnegative = 0;
        for (a, law) in laws.iter().enumerate() {
            if !matches!(law, Law::Associated { .. }) {
                out.push_row(&[(var(a, 0), -1.0)], 0.0);
                nonnegative += 1;
            }
        }
        if nonnegative > 0 {
            out.cones
                .push(SupportedConeT::NonnegativeConeT(nonnegative));
        }
        for (a, law) in laws.iter().enumerate() {
            match *law {
                // s = (mu r_N, r_T): A = -diag(mu, 1, 1), b = 0.
                Law::Associated { mu } => {
                    out.push_row(&[(var(a, 0), -mu)], 0.0);
                    out.push_row(&[(var(a, 1), -1.0)], 0.0);
                    out.push_row(&[(var(a, 2), -1.0)], 0.0);
                }
                // s = (bound, r_T): the axis row has no entries, b = bound.
                Law::Tresca { bound } => {
                    out.bound_rows[a] = Some(out.b.len());
                    out.push_row(&[], bound);
                    out.push_row(&[(var(a, 1), -1.0)], 0.0);
                    out.push_row(&[(var(a, 2), -1.0)], 0.0);
                }
                Law::Frictionless | Law::Stick => continue,
            }
            out.cones.push(SupportedConeT::SecondOrderConeT(3));
        }
        out
    }

    fn push_row(&mut self, entries: &[(usize, f64)], b: f64) {
        let row = self.b.len();
        for &(column, value) in entries {
            self.rows.push(row);
            self.columns.push(column);
            self.values.push(value);
        }
        self.b.push(b);
    }
}

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
struct Solve {
    status: SolverStatus,
    x: Vec<f64>,
    iterations: usize,
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
struct Run<'a> {
    solver_name: String,
    max_outer: usize,
    problem: &'a ContactProblem,
    limits: &'a SolveLimits,
    clock: Instant,
    /// Clarabel's gap and feasibility tolerance for each solve.
    inner_tolerance: f64,
    iterations: usize,
    outer_iterations: usize,
    notes: Vec<String>,
}

impl<'a> Run<'a> {
    fn new(
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

    fn note_asymmetry(&mut self) {
        let (skew, norm) = self.problem.w.asymmetry();
        if skew > 0.0 {
            self.notes.push(format!(
                "W asymmetry ||W-W^T||_F/||W||_F = {:.1e} removed by symmetrisation",
                skew / norm
            ));
        }
    }

    fn finish(self, r: Vec<f64>, status: SolveStatus) -> SolverReport {
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
    fn solve_once(&mut self, program: &ConicProgram) -> Result<Solve, ContactSolverError> {
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
    fn conclude_single(&mut self, program: &ConicProgram, solve: Solve) -> (Vec<f64>, SolveStatus) {
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
    fn coulomb_fixed_point(&mut self) -> Result<(Vec<f64>, SolveStatus), ContactSolverError> {
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

/// Relative natural-map residual of the problem the single program solves: Coulomb contacts
/// with the associated law `r - P_K(r - u)` (no De Saxce shift), the others as in
/// [`natural_map_error`]; same `/||q||` normalisation.
pub fn associated_natural_map(problem: &ContactProblem, r: &[f64]) -> f64 {
    let u = problem.velocity(r);
    let mut sum = 0.0;
    for (a, &mu) in problem.mu.iter().enumerate() {
        let ra = Vector3::new(r[3 * a], r[3 * a + 1], r[3 * a + 2]);
        let ua = Vector3::new(u[3 * a], u[3 * a + 1], u[3 * a + 2]);
        let f = if mu > 0.0 && mu.is_finite() {
            ra - project_on_coulomb_cone(&(ra - ua), mu)
        } else {
            contact_natural_map(&ra, &ua, mu)
        };
        sum += f.norm_squared();
    }
    let q = problem.q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if q > 0.0 {
        sum.sqrt() / q
    } else {
        sum.sqrt()
    }
}

/// Sizes agree, numbers are finite, `mu` is `>= 0` or `+inf`.
fn validate(problem: &ContactProblem) -> Result<(), ContactSolverError> {
    let invalid = |message: String| ContactSolverError::InvalidProblem {
        problem: problem.source.clone(),
        message,
    };
    let n = 3 * problem.contacts();
    if problem.q.len() != n || problem.w.size != n {
        return Err(invalid(format!(
            "{} contacts need q and W of size {n}; got q {} and W {}",
            problem.contacts(),
            problem.q.len(),
            problem.w.size
        )));
    }
    if let Some(a) = problem.mu.iter().position(|m| m.is_nan() || *m < 0.0) {
        return Err(invalid(format!("mu[{a}] = {} is not >= 0", problem.mu[a])));
    }
    if problem
        .q
        .iter()
        .chain(&problem.w.values)
        .any(|v| !v.is_finite())
    {
        return Err(invalid("W or q holds a non-finite value".into()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use nalgebra::{DMatrix, DVector};

    use super::*;
    use crate::contact::problem::SparseMatrix;

    fn problem(w: &DMatrix<f64>, q: &[f64], mu: &[f64]) -> ContactProblem {
        let n = w.nrows();
        let triplets: Vec<_> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .filter(|&(i, j)| w[(i, j)] != 0.0)
            .map(|(i, j)| (i, j, w[(i, j)]))
            .collect();
        ContactProblem {
            w: SparseMatrix::from_triplets(n, &triplets).unwrap(),
            q: q.to_vec(),
            mu: mu.to_vec(),
            frames: None,
            compliance: 1.0,
            source: "unit test".into(),
        }
    }

    /// An SPD 6x6 matrix coupling two contacts in every component.
    fn coupled_w() -> DMatrix<f64> {
        let l = DMatrix::from_row_slice(
            6,
            6,
            &[
                1.0, 0.0, 0.0, 0.0, 0.0, 0.0, //
                0.2, 0.9, 0.0, 0.0, 0.0, 0.0, //
                -0.1, 0.3, 1.1, 0.0, 0.0, 0.0, //
                0.4, -0.2, 0.1, 1.2, 0.0, 0.0, //
                0.1, 0.2, -0.3, 0.2, 0.8, 0.0, //
                -0.2, 0.1, 0.2, -0.1, 0.3, 1.0, //
            ],
        );
        &l * l.transpose()
    }

    fn solve(p: &ContactProblem, mode: ConicMode) -> SolverReport {
        ConicSolver::new(mode)
            .solve(p, &SolveLimits::default())
            .expect("solves")
    }

    /// At the default 1e-8 Clarabel's multipliers are off by about 2e-8 relative; checks of the
    /// formulation against exact solutions at 1e-8 ask Clarabel for 1e-10.
    fn solve_tight(p: &ContactProblem, mode: ConicMode) -> SolverReport {
        let limits = SolveLimits {
            tolerance: 1e-10,
            ..Default::default()
        };
        ConicSolver::new(mode).solve(p, &limits).expect("solves")
    }

    fn assert_close(r: &[f64], exact: &[f64], tol: f64) {
        let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        for (k, (a, b)) in r.iter().zip(exact).enumerate() {
            assert!(
                (a - b).abs() <= tol * scale,
                "component {k}: {a} vs {b}\n{r:?}"
            );
        }
    }

    #[test]
    fn frictionless_single_contact_is_the_normal_projection() {
        let w = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, 0.1, 0.3, 1.0, 0.0, 0.1, 0.0, 1.5]);
        let p = problem(&w, &[-3.0, 1.0, -0.5], &[0.0]);
        for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
            let report = solve_tight(&p, mode);
            assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
            assert_close(&report.r, &[1.5, 0.0, 0.0], 1e-8);
            assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
            assert!(report.iterations > 0);
        }
    }

    #[test]
    fn frictionless_two_contacts_match_the_linear_solve_on_the_active_set() {
        let w = coupled_w();
        let n = [0, 3];
        let w_nn = DMatrix::from_fn(2, 2, |i, j| w[(n[i], n[j])]);
        // Both active: r_N = W_NN^-1 (-q_N).
        let r_n = DVector::from_vec(vec![1.0, 2.0]);
        let q_n = -(&w_nn * &r_n);
        let q = [q_n[0], 0.7, -0.2, q_n[1], 0.1, 0.4];
        let p = problem(&w, &q, &[0.0, 0.0]);
        let report = solve_tight(&p, ConicMode::Coulomb);
        assert_eq!(report.status, SolveStatus::Converged);
        assert_close(&report.r, &[1.0, 0.0, 0.0, 2.0, 0.0, 0.0], 1e-8);
        assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
        // Contact 1 separates: r = (1.5, 0), u_N,1 = 0.7 > 0.
        let q = [
            -w[(0, 0)] * 1.5,
            0.7,
            -0.2,
            -w[(3, 0)] * 1.5 + 0.7,
            0.1,
            0.4,
        ];
        let p = problem(&w, &q, &[0.0, 0.0]);
        let report = solve_tight(&p, ConicMode::Relaxed);
        assert_eq!(report.status, SolveStatus::Converged);
        assert_close(&report.r, &[1.5, 0.0, 0.0, 0.0, 0.0, 0.0], 1e-8);
        assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
        assert!((p.velocity(&report.r)[3] - 0.7).abs() < 1e-7);
    }

    #[test]
    fn stick_leaves_the_tangential_force_free() {
        let w = coupled_w();
        let exact = [1.0, 0.7, -0.4, 2.0, -1.5, 0.3];
        let q: Vec<f64> = (-(&w * DVector::from_row_slice(&exact)))
            .iter()
            .copied()
            .collect();
        let p = problem(&w, &q, &[f64::INFINITY, f64::INFINITY]);
        for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
            let report = solve_tight(&p, mode);
            assert_eq!(report.status, SolveStatus::Converged);
            assert_close(&report.r, &exact, 1e-8);
            assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
        }
    }

    #[test]
    fn relaxed_sliding_opens_the_contact_and_coulomb_does_not() {
        let w = DMatrix::identity(3, 3);
        let p = problem(&w, &[-1.0, 2.0, 0.0], &[0.3]);
        let relaxed = solve(&p, ConicMode::Relaxed);
        assert_eq!(relaxed.status, SolveStatus::Converged);
        let u = p.velocity(&relaxed.r);
        let slip = u[1].hypot(u[2]);
        // The associated law: u_N = mu |u_T| > 0, r on the cone; here r = P_K(-q).
        assert!(u[0] > 0.4, "{u:?}");
        assert!((u[0] - 0.3 * slip).abs() <= 1e-7 * slip, "{u:?}");
        assert!(associated_natural_map(&p, &relaxed.r) <= 1e-7);
        assert!(natural_map_error(&p, &relaxed.r).relative > 0.1);

        let coulomb = solve(&p, ConicMode::Coulomb);
        assert_eq!(
            coulomb.status,
            SolveStatus::Converged,
            "{:?}",
            coulomb.notes
        );
        assert_close(&coulomb.r, &[1.0, -0.3, 0.0], 1e-8);
        let u = p.velocity(&coulomb.r);
        assert!(u[0].abs() < 1e-8 && u[1] > 1.6, "{u:?}");
        assert!(natural_map_error(&p, &coulomb.r).relative <= 1e-7);
        assert!(coulomb.outer_iterations >= 1);
    }

    /// Contact 1 is separated in the frictionless start (bound 0, an SOC without interior) and
    /// is pressed closed by contact 0's friction through the coupling W_{N1,T0}.
    fn friction_closes_a_contact() -> ContactProblem {
        let mut w = DMatrix::identity(6, 6);
        w[(3, 1)] = 0.5;
        w[(1, 3)] = 0.5;
        problem(&w, &[-1.0, 2.0, 0.0, 0.1, 0.5, 0.0], &[0.3, 0.3])
    }

    #[test]
    fn coulomb_handles_zero_tresca_bounds() {
        let p = friction_closes_a_contact();
        let relaxed = solve(&p, ConicMode::Relaxed);
        assert_eq!(relaxed.status, SolveStatus::Converged);
        let report = solve(&p, ConicMode::Coulomb);
        assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
        // Exact: contact 0 slides (u_N = 0, u_T = 1.725 > 0); contact 1 is closed by
        // W_{N1,T0} r_T0 = -0.15 against its gap 0.1 and slides too (u_T = 0.485 > 0).
        assert_close(&report.r, &[1.0, -0.3, 0.0, 0.05, -0.015, 0.0], 1e-7);
        // Its friction needs the second Tresca solve (bound 0 in the first).
        assert!(report.outer_iterations >= 2);
        assert!(
            natural_map_error(&p, &report.r).relative <= 1e-7,
            "{:?}",
            report.r
        );
        // A contact separated throughout keeps a zero bound every iteration.
        let p = problem(
            &DMatrix::identity(6, 6),
            &[-1.0, 2.0, 0.0, 0.5, 1.0, 0.0],
            &[0.3, 0.3],
        );
        let report = solve(&p, ConicMode::Coulomb);
        assert_eq!(report.status, SolveStatus::Converged, "{:?}", report.notes);
        assert_close(&report.r, &[1.0, -0.3, 0.0, 0.0, 0.0, 0.0], 1e-8);
        assert!(natural_map_error(&p, &report.r).relative <= 1e-7);
    }

    /// What Clarabel does with an SOC without interior (`|r_T| <= 0`), on a contact whose
    /// tangential load would make it slide: it reports Solved, with `r_T` at roundoff.
    #[test]
    fn a_zero_tresca_bound_is_solved_with_zero_tangential_force() {
        let w = coupled_w();
        let q = [-1.0, 2.0, -1.0, -1.0, -0.5, 0.3];
        let p = problem(&w, &q, &[0.3, 0.3]);
        let limits = SolveLimits::default();
        let clock = Instant::now();
        let solver = ConicSolver::new(ConicMode::Coulomb);
        let mut run = Run::new(&solver, &p, &limits, clock);
        let frictionless = ConicProgram::build(&p, &contact_laws(&p, |_| Law::Frictionless));
        let reference = run.solve_once(&frictionless).unwrap();
        assert_eq!(reference.status, SolverStatus::Solved);
        let reference = frictionless.r_of(&reference.x);
        for bound in [0.0, 1e-300] {
            let laws = contact_laws(&p, |_| Law::Tresca { bound });
            let solve = run.solve_once(&ConicProgram::build(&p, &laws)).unwrap();
            println!(
                "bound {bound:e}: {:?} in {} iterations",
                solve.status, solve.iterations
            );
            assert_eq!(solve.status, SolverStatus::Solved);
            let r = ConicProgram::build(&p, &laws).r_of(&solve.x);
            assert_close(&r, &reference, 1e-7);
        }
    }

    #[test]
    fn caps_and_limits_are_reported_not_hidden() {
        let p = friction_closes_a_contact();
        let mut solver = ConicSolver::new(ConicMode::Coulomb);
        solver.max_outer = 1;
        let report = solver.solve(&p, &SolveLimits::default()).unwrap();
        assert_eq!(report.status, SolveStatus::MaxIterations);
        assert_eq!(report.outer_iterations, 1);
        let few = SolveLimits {
            max_iterations: 1,
            ..Default::default()
        };
        let report = ConicSolver::new(ConicMode::Relaxed)
            .solve(&p, &few)
            .unwrap();
        assert_eq!(report.status, SolveStatus::MaxIterations);
        assert_eq!(report.r.len(), 6);
        assert!(report.r.iter().all(|v| v.is_finite()));
        let none = SolveLimits {
            time_limit: Some(Duration::ZERO),
            ..Default::default()
        };
        for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
            let report = ConicSolver::new(mode).solve(&p, &none).unwrap();
            assert_eq!(report.status, SolveStatus::TimeLimit, "{mode:?}");
        }
    }

    #[test]
    fn asymmetry_is_removed_and_reported() {
        let mut w = coupled_w();
        w[(3, 0)] += 1e-3;
        let sym = (&w + w.transpose()) * 0.5;
        let q = [-1.0, 0.0, 0.0, -2.0, 0.0, 0.0];
        let report = solve(&problem(&w, &q, &[0.0, 0.0]), ConicMode::Relaxed);
        assert!(
            report.notes.iter().any(|n| n.contains("asymmetry")),
            "{:?}",
            report.notes
        );
        let symmetric = solve(&problem(&sym, &q, &[0.0, 0.0]), ConicMode::Relaxed);
        assert!(symmetric.notes.is_empty());
        assert_close(&report.r, &symmetric.r, 1e-8);
    }

    #[test]
    fn invalid_problems_are_errors_and_empty_ones_trivial() {
        let p = problem(&DMatrix::identity(3, 3), &[-1.0, 0.0, 0.0], &[-0.1]);
        let err = ConicSolver::new(ConicMode::Relaxed).solve(&p, &SolveLimits::default());
        assert!(matches!(
            err,
            Err(ContactSolverError::InvalidProblem { .. })
        ));
        let empty = problem(&DMatrix::zeros(0, 0), &[], &[]);
        let report = solve(&empty, ConicMode::Coulomb);
        assert_eq!(report.status, SolveStatus::Converged);
        assert!(report.r.is_empty());
        assert_eq!(ConicSolver::new(ConicMode::Coulomb).name(), "conic/coulomb");
        assert_eq!(ConicSolver::new(ConicMode::Relaxed).name(), "conic/relaxed");
    }
}
