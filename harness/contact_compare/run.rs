//! Reading the problems and running every solver on every problem at every tolerance.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use impact_solver::contact::problem::{natural_map_error, ContactProblem};
use impact_solver::contact::problem_file::read_problem;
use impact_solver::contact::registry::SolverKind;
use impact_solver::contact::solver::{ContactSolver, SolveLimits};

use super::error::CompareError;
use super::{describe, Comparison, ComparisonRow, Unreadable, NORMALISATION};

/// Sweep cap of the Gauss-Seidel solvers: the tolerance or the time limit should stop them
/// first (ABH's NSGS runs used the time limit).
pub const GAUSS_SEIDEL_MAX_SWEEPS: usize = 100_000;
/// Interior-point iteration cap of each conic solve (Clarabel needs 10-40).
pub const CONIC_MAX_ITERATIONS: usize = 200;
/// Newton iteration cap of `newton/alart-curnier`: the tolerance or the time limit should stop
/// it first.
pub const NEWTON_MAX_ITERATIONS: usize = 1000;

/// A solver to compare: its name, its iteration cap, and how to make a fresh one.
pub struct SolverEntry {
    /// The solver's name (`contact::registry` spelling).
    pub name: String,
    /// Most iterations per solve (sweeps, or interior-point iterations per conic solve).
    pub max_iterations: usize,
    /// Builds a fresh solver, so that no state carries over between solves.
    pub make: Box<dyn Fn() -> Box<dyn ContactSolver>>,
}

/// The entries of `names` (every solver of the registry when empty); an unknown name is the
/// registry's error listing the known ones.
pub fn solver_entries(names: &[String]) -> Result<Vec<SolverEntry>, CompareError> {
    let kinds: Vec<SolverKind> = if names.is_empty() {
        SolverKind::ALL.to_vec()
    } else {
        names
            .iter()
            .map(|name| SolverKind::from_name(name))
            .collect::<Result<_, _>>()?
    };
    Ok(kinds
        .into_iter()
        .map(|kind| SolverEntry {
            name: kind.name().to_string(),
            // Comparison caps, not the stepper's: a comparison runs each solver to the
            // tolerance or the time limit.
            max_iterations: match kind {
                SolverKind::GaussSeidelThesis | SolverKind::GaussSeidelExact => {
                    GAUSS_SEIDEL_MAX_SWEEPS
                }
                SolverKind::ConicRelaxed | SolverKind::ConicCoulomb => CONIC_MAX_ITERATIONS,
                SolverKind::NewtonAlartCurnier => NEWTON_MAX_ITERATIONS,
            },
            make: Box::new(move || -> Box<dyn ContactSolver> { kind.build() }),
        })
        .collect())
}

/// How a comparison runs.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareSettings {
    /// The tolerances every solver runs at.
    pub tolerances: Vec<f64>,
    /// Time limit of one solve (s), passed to the solver and applied to the profiles.
    pub time_limit_s: f64,
    /// A solve is repeated until its repeats took this long in total ...
    pub min_timing_s: f64,
    /// ... or this many repeats were made; the median time is kept.
    pub max_repeats: usize,
}

impl Default for CompareSettings {
    fn default() -> Self {
        Self {
            tolerances: super::DEFAULT_TOLERANCES.to_vec(),
            time_limit_s: super::DEFAULT_TIME_LIMIT_S,
            min_timing_s: 0.2,
            max_repeats: 5,
        }
    }
}

/// A problem read from a file.
#[derive(Debug, Clone)]
pub struct LoadedProblem {
    /// The file stem.
    pub name: String,
    /// The problem file.
    pub file: PathBuf,
    /// The problem, checked.
    pub problem: ContactProblem,
}

/// The problem files named by `inputs`: files as given, folders replaced by their `*.json`
/// files sorted by name. A missing path, or nothing found at all, is an error naming it.
pub fn collect_problem_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, CompareError> {
    if inputs.is_empty() {
        return Err(CompareError::NoInputs);
    }
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let entries = std::fs::read_dir(input).map_err(|e| CompareError::ListFolder {
                folder: input.display().to_string(),
                message: e.to_string(),
            })?;
            let mut found: Vec<PathBuf> = entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "json"))
                .collect();
            if found.is_empty() {
                return Err(CompareError::EmptyFolder {
                    folder: input.display().to_string(),
                });
            }
            found.sort();
            files.extend(found);
        } else if input.exists() {
            files.push(input.clone());
        } else {
            return Err(CompareError::Missing {
                path: input.display().to_string(),
            });
        }
    }
    Ok(files)
}

/// Reads every file; a file that cannot be read or checked, or whose name repeats an earlier
/// one, is reported with its reason and left out, the others are read.
pub fn load_problems(files: &[PathBuf]) -> (Vec<LoadedProblem>, Vec<Unreadable>) {
    let mut problems: Vec<LoadedProblem> = Vec::new();
    let mut unreadable = Vec::new();
    for file in files {
        let name = problem_name(file);
        let outcome = read_problem(file)
            .map(|(p, _)| p)
            .map_err(|e| e.to_string())
            .and_then(|problem| match problems.iter().find(|p| p.name == name) {
                Some(other) => Err(format!(
                    "contact problem `{}`: its name `{name}` is also that of `{}`; rename one",
                    file.display(),
                    other.file.display()
                )),
                None => Ok(problem),
            });
        match outcome {
            Ok(problem) => problems.push(LoadedProblem {
                name,
                file: file.clone(),
                problem,
            }),
            Err(message) => unreadable.push(Unreadable {
                file: file.display().to_string(),
                message,
            }),
        }
    }
    (problems, unreadable)
}

fn problem_name(file: &Path) -> String {
    file.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.display().to_string())
}

/// Runs every solver on every problem at every tolerance, in that nesting (problem outermost),
/// and calls `on_row` after each solve. Solvers run one at a time so that timings do not
/// compete for cores.
pub fn compare(
    problems: &[LoadedProblem],
    unreadable: Vec<Unreadable>,
    solvers: &[SolverEntry],
    settings: &CompareSettings,
    on_row: &mut dyn FnMut(&ComparisonRow),
) -> Comparison {
    compare_until(problems, unreadable, solvers, settings, None, on_row)
}

/// [`compare`] that stops before the next solve (or repeat) once `stop` is set, a signal's
/// flag: a solve under way runs to its end, at most the time limit. The comparison then holds
/// the rows that finished and only the problems they belong to, so that the tables and
/// profiles describe what ran rather than count the rest as failures.
pub fn compare_until(
    problems: &[LoadedProblem],
    unreadable: Vec<Unreadable>,
    solvers: &[SolverEntry],
    settings: &CompareSettings,
    stop: Option<&AtomicBool>,
    on_row: &mut dyn FnMut(&ComparisonRow),
) -> Comparison {
    let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    let mut rows = Vec::new();
    'problems: for p in problems {
        for s in solvers {
            for &tolerance in &settings.tolerances {
                if stopped() {
                    break 'problems;
                }
                let row = solve_row_until(p, s, tolerance, settings, stop);
                on_row(&row);
                rows.push(row);
            }
        }
    }
    let ran = |p: &&LoadedProblem| !stopped() || rows.iter().any(|r| r.problem == p.name);
    Comparison {
        normalisation: NORMALISATION.into(),
        tolerances: settings.tolerances.clone(),
        time_limit_s: settings.time_limit_s,
        solvers: solvers.iter().map(|s| s.name.clone()).collect(),
        problems: problems
            .iter()
            .filter(ran)
            .map(|p| describe(&p.problem, &p.name, &p.file.display().to_string()))
            .collect(),
        unreadable,
        rows,
    }
}

/// One problem, solver and tolerance: solved from zero, timed over repeats, and measured.
pub fn solve_row(
    p: &LoadedProblem,
    entry: &SolverEntry,
    tolerance: f64,
    settings: &CompareSettings,
) -> ComparisonRow {
    solve_row_until(p, entry, tolerance, settings, None)
}

/// [`solve_row`] that makes no further timing repeat once `stop` is set.
fn solve_row_until(
    p: &LoadedProblem,
    entry: &SolverEntry,
    tolerance: f64,
    settings: &CompareSettings,
    stop: Option<&AtomicBool>,
) -> ComparisonRow {
    let limits = SolveLimits {
        tolerance,
        max_iterations: entry.max_iterations,
        // A limit beyond what a Duration holds (inf, 1e300 s) is no limit; the command and the
        // case reader refuse what is not positive, and this must not panic on what gets past.
        time_limit: Duration::try_from_secs_f64(settings.time_limit_s).ok(),
    };
    let mut row = ComparisonRow {
        problem: p.name.clone(),
        solver: entry.name.clone(),
        tolerance,
        error: f64::NAN,
        absolute_error: f64::NAN,
        iterations: 0,
        outer_iterations: 0,
        seconds: f64::NAN,
        repeats: 0,
        status: String::new(),
        solved: false,
        notes: Vec::new(),
    };
    if entry.name.starts_with("conic/") && p.problem.mu.iter().all(|&m| m == 0.0) {
        row.notes
            .push("frictionless problem: conic/relaxed and conic/coulomb solve the same QP".into());
    }
    let mut times = Vec::new();
    let mut first = None;
    let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    while times.is_empty()
        || (times.len() < settings.max_repeats.max(1)
            && times.iter().sum::<f64>() < settings.min_timing_s
            && !stopped())
    {
        let mut solver = (entry.make)();
        let started = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| solver.solve(&p.problem, &limits)));
        times.push(started.elapsed().as_secs_f64());
        match outcome {
            Ok(Ok(report)) => {
                if first.is_none() {
                    first = Some(report);
                }
            }
            Ok(Err(e)) => {
                row.status = "error".into();
                row.notes.push(e.to_string());
                break;
            }
            Err(panic) => {
                row.status = "panicked".into();
                row.notes
                    .push(format!("the solver panicked: {}", panic_text(&panic)));
                break;
            }
        }
    }
    row.repeats = times.len();
    row.seconds = median(&mut times);
    if let Some(report) = first {
        if report.r.len() == p.problem.q.len() {
            let e = measured_error(&p.problem, &report.r);
            row.error = e.relative;
            row.absolute_error = e.absolute;
        } else {
            row.notes.push(format!(
                "the solver returned {} multipliers for {} unknowns",
                report.r.len(),
                p.problem.q.len()
            ));
        }
        row.iterations = report.iterations;
        row.outer_iterations = report.outer_iterations;
        row.status = report.status.label().into();
        if let impact_solver::contact::solver::SolveStatus::Failed(why) = &report.status {
            row.notes.push(why.clone());
        }
        row.notes.extend(report.notes);
    }
    row.solved = row.meets(settings.time_limit_s);
    row
}

/// The natural-map error of `r` ([`natural_map_error`]), computed on the problem scaled by
/// `s = max |q_i|` when the direct sums overflow: for `|q| ~ 1e300`, `||q||_2^2` is infinite and
/// the relative error would read inf/inf = NaN. FC(W, q, mu) is homogeneous: `r/s` solves
/// FC(W, q/s, mu) when `r` solves FC(W, q, mu), and the natural map scales by `s`, so the
/// relative error is the same and the absolute one is `s` times the scaled one. Problems whose
/// direct error is finite keep it bit for bit.
pub fn measured_error(
    problem: &ContactProblem,
    r: &[f64],
) -> impact_solver::contact::problem::NaturalMapError {
    let direct = natural_map_error(problem, r);
    let s = problem.q.iter().fold(0.0f64, |m, q| m.max(q.abs()));
    if direct.relative.is_finite() || !(s > 0.0 && s.is_finite()) {
        return direct;
    }
    let mut scaled = problem.clone();
    scaled.q.iter_mut().for_each(|q| *q /= s);
    let r: Vec<f64> = r.iter().map(|v| v / s).collect();
    let mut e = natural_map_error(&scaled, &r);
    e.absolute *= s;
    e
}

/// The median of `values` (the mean of the middle two for an even count); NaN when empty.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

fn panic_text(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_solver::contact::registry;
    use impact_solver::contact::solver::{ContactSolverError, SolveStatus, SolverReport};

    /// A fake solver: returns the exact solution of a one-contact diagonal problem perturbed by
    /// `offset`, and claims convergence regardless.
    struct Fake {
        offset: f64,
    }

    impl ContactSolver for Fake {
        fn name(&self) -> String {
            "fake".into()
        }
        fn solve(
            &mut self,
            problem: &ContactProblem,
            _limits: &SolveLimits,
        ) -> Result<SolverReport, ContactSolverError> {
            // W = 2 I, q = [-1, 0, 0]: r = [0.5, 0, 0], u = 0.
            let mut r = vec![0.0; problem.q.len()];
            r[0] = 0.5 + self.offset;
            Ok(SolverReport {
                r,
                status: SolveStatus::Converged,
                iterations: 7,
                outer_iterations: 1,
                seconds: 0.0,
                notes: vec!["fake".into()],
            })
        }
    }

    fn one_contact() -> LoadedProblem {
        LoadedProblem {
            name: "one".into(),
            file: "one.json".into(),
            problem: crate::contact_compare::test_problem(
                &[(0, 0, 2.0), (1, 1, 2.0), (2, 2, 2.0)],
                &[-1.0, 0.0, 0.0],
                &[0.5],
            ),
        }
    }

    fn entry(name: &str, offset: f64) -> SolverEntry {
        SolverEntry {
            name: name.into(),
            max_iterations: 10,
            make: Box::new(move || Box::new(Fake { offset })),
        }
    }

    #[test]
    fn the_harness_measures_the_error_itself_and_not_the_status() {
        let settings = CompareSettings {
            tolerances: vec![1e-4, 1e-8],
            time_limit_s: 10.0,
            min_timing_s: 0.0,
            max_repeats: 3,
        };
        let solvers = [entry("exact", 0.0), entry("off", 1e-6)];
        let mut seen = 0;
        let c = compare(
            &[one_contact()],
            Vec::new(),
            &solvers,
            &settings,
            &mut |_| seen += 1,
        );
        assert_eq!((seen, c.rows.len()), (4, 4));
        let exact = c.row("one", "exact", 1e-8).unwrap();
        assert_eq!(exact.error, 0.0);
        assert!(exact.solved && exact.status == "converged" && exact.iterations == 7);
        assert_eq!(exact.repeats, 1, "min_timing_s = 0 times once");
        // r_N off by 1e-6: u_N = 2e-6, F_N = r_N - max(0, r_N - u_N) = 2e-6, over ||q|| = 1.
        let off = c.row("one", "off", 1e-8).unwrap();
        assert!((off.error - 2e-6).abs() < 1e-15, "{}", off.error);
        assert!(!off.solved, "converged by its own word, but 2e-6 > 1e-8");
        assert!(c.row("one", "off", 1e-4).unwrap().solved);
        assert_eq!(c.problems[0].contacts, 1);
    }

    #[test]
    fn repeats_stop_at_the_cap_and_a_panic_is_a_row_not_a_crash() {
        let settings = CompareSettings {
            tolerances: vec![1e-6],
            time_limit_s: 10.0,
            min_timing_s: 1e3,
            max_repeats: 4,
        };
        let panicking = SolverEntry {
            name: "todo".into(),
            max_iterations: 1,
            make: Box::new(|| Box::new(Panics)),
        };
        let c = compare(
            &[one_contact()],
            Vec::new(),
            &[entry("exact", 0.0), panicking],
            &settings,
            &mut |_| {},
        );
        assert_eq!(c.rows[0].repeats, 4);
        let row = &c.rows[1];
        assert_eq!(row.status, "panicked");
        assert!(row.error.is_nan() && !row.solved);
        assert!(row.notes[0].contains("not yet"), "{:?}", row.notes);
    }

    struct Panics;
    impl ContactSolver for Panics {
        fn name(&self) -> String {
            "todo".into()
        }
        fn solve(
            &mut self,
            _: &ContactProblem,
            _: &SolveLimits,
        ) -> Result<SolverReport, ContactSolverError> {
            panic!("not yet")
        }
    }

    #[test]
    fn unknown_solver_names_and_missing_inputs_are_errors_naming_them() {
        let e = solver_entries(&["conic/fast".into()])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("conic/fast") && e.contains("gauss-seidel/exact"),
            "{e}"
        );
        assert_eq!(solver_entries(&[]).unwrap().len(), registry::names().len());
        let e = collect_problem_files(&["/no/such/problem.json".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("/no/such/problem.json"), "{e}");
        assert!(collect_problem_files(&[]).is_err());
    }

    #[test]
    fn a_bad_file_is_reported_and_the_others_are_read() {
        let dir = std::env::temp_dir().join(format!("impact-vv-compare-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("b-good.json");
        let file = impact_solver::contact::problem_file::ProblemFile::from_problem(
            &one_contact().problem,
            vec![],
        );
        file.write(&good).unwrap();
        std::fs::write(dir.join("a-bad.json"), "{ not json").unwrap();
        std::fs::write(dir.join("notes.txt"), "ignored").unwrap();
        let files = collect_problem_files(std::slice::from_ref(&dir)).unwrap();
        assert_eq!(files, vec![dir.join("a-bad.json"), good.clone()]);
        let (problems, unreadable) = load_problems(&files);
        assert_eq!(problems.len(), 1);
        assert_eq!(problems[0].name, "b-good");
        assert_eq!(unreadable.len(), 1);
        assert!(
            unreadable[0].message.contains("a-bad.json"),
            "{:?}",
            unreadable
        );
        std::fs::remove_dir_all(dir).ok();
    }

    /// The problem of the fuzz findings (N2), `q = [-1e300, 2e300, 3e300]`, `mu = 0.1`, with an
    /// isotropic tangential block, `W = diag(15, 14, 14)`, so that the slip is along `q_T` and
    /// the Coulomb solution is analytic (closed and sliding): `r_N = 1e300 / 15`,
    /// `r_T = -mu r_N q_T / |q_T|` (`u_T = q_T (1 - 14 mu r_N / |q_T|)`, along `q_T`).
    fn huge_q() -> (LoadedProblem, Vec<f64>) {
        let problem = crate::contact_compare::test_problem(
            &[(0, 0, 15.0), (1, 1, 14.0), (2, 2, 14.0)],
            &[-1e300, 2e300, 3e300],
            &[0.1],
        );
        let r_n = 1e300 / 15.0;
        let q_t = (2e300f64).hypot(3e300);
        let exact = vec![r_n, -0.1 * r_n * (2e300 / q_t), -0.1 * r_n * (3e300 / q_t)];
        assert!(exact.iter().all(|v| v.is_finite()), "{exact:?}");
        let loaded = LoadedProblem {
            name: "q_huge".into(),
            file: "q_huge.json".into(),
            problem,
        };
        (loaded, exact)
    }

    /// `||q||_2^2` overflows for this problem, so the direct relative error is inf/inf = NaN
    /// even at the exact solution; measured on the scaled problem it is at roundoff, and a
    /// conic/coulomb solve at 1e-6 reaches its tolerance and counts as solved.
    #[test]
    fn the_error_of_a_problem_with_huge_q_is_measured_without_overflow() {
        let (p, exact) = huge_q();
        assert!(natural_map_error(&p.problem, &exact).relative.is_nan());
        let e = measured_error(&p.problem, &exact);
        assert!(e.relative < 1e-15, "{e:?}");
        assert!(e.absolute.is_finite(), "{e:?}");

        let settings = CompareSettings {
            tolerances: vec![1e-6],
            time_limit_s: 10.0,
            min_timing_s: 0.0,
            max_repeats: 1,
        };
        let solvers = solver_entries(&["conic/coulomb".into()]).unwrap();
        let c = compare(&[p], Vec::new(), &solvers, &settings, &mut |_| {});
        let row = &c.rows[0];
        assert!(row.error <= 1e-6, "{row:?}");
        assert!(row.solved && row.status == "converged", "{row:?}");
    }

    /// A time limit beyond what a `Duration` holds (inf, 1e300 s) is no limit, not a panic.
    #[test]
    fn an_unbounded_time_limit_does_not_panic() {
        for limit in [f64::INFINITY, 1e300] {
            let settings = CompareSettings {
                tolerances: vec![1e-6],
                time_limit_s: limit,
                min_timing_s: 0.0,
                max_repeats: 1,
            };
            let row = solve_row(&one_contact(), &entry("exact", 0.0), 1e-6, &settings);
            assert!(row.solved, "{limit}: {row:?}");
        }
    }

    /// A stop flag set while the first solve runs ends the comparison after it: one row, and
    /// only the problem it belongs to; set before the start, nothing runs.
    #[test]
    fn a_stop_flag_ends_the_comparison_after_the_solve_under_way() {
        let settings = CompareSettings {
            tolerances: vec![1e-4, 1e-8],
            time_limit_s: 10.0,
            min_timing_s: 1e3,
            max_repeats: 5,
        };
        let mut second = one_contact();
        second.name = "two".into();
        let problems = [one_contact(), second];
        let stop = AtomicBool::new(false);
        let solvers = [SolverEntry {
            name: "stops".into(),
            max_iterations: 10,
            make: Box::new(|| Box::new(SetsFlag)),
        }];
        STOP_FOR_TEST.store(false, Ordering::SeqCst);
        let c = compare_until(
            &problems,
            Vec::new(),
            &solvers,
            &settings,
            Some(&STOP_FOR_TEST),
            &mut |_| {},
        );
        assert_eq!(c.rows.len(), 1, "{:?}", c.rows);
        assert_eq!(c.rows[0].repeats, 1, "no repeat after the stop");
        assert_eq!(c.problem_names(), ["one"]);

        stop.store(true, Ordering::SeqCst);
        let c = compare_until(
            &problems,
            Vec::new(),
            &[entry("exact", 0.0)],
            &settings,
            Some(&stop),
            &mut |_| panic!("no solve after the stop"),
        );
        assert!(c.rows.is_empty() && c.problems.is_empty());
    }

    /// The flag [`SetsFlag`] raises, as a signal handler would during a solve.
    static STOP_FOR_TEST: AtomicBool = AtomicBool::new(false);

    /// A solver that raises [`STOP_FOR_TEST`] while it solves, then returns the exact answer
    /// of [`one_contact`].
    struct SetsFlag;
    impl ContactSolver for SetsFlag {
        fn name(&self) -> String {
            "stops".into()
        }
        fn solve(
            &mut self,
            problem: &ContactProblem,
            limits: &SolveLimits,
        ) -> Result<SolverReport, ContactSolverError> {
            STOP_FOR_TEST.store(true, Ordering::SeqCst);
            Fake { offset: 0.0 }.solve(problem, limits)
        }
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&mut []).is_nan());
    }
}
