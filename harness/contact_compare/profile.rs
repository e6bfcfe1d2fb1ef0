//! Performance profiles (Dolan & More 2002, "Benchmarking optimization software with
//! performance profiles", Math. Program. 91) and the work-precision diagram of a comparison.
//!
//! Profile at one tolerance: with `t_{p,s}` the (median) time solver `s` needed on problem `p`,
//! infinite when it did not solve it (ABH's criterion, [`ComparisonRow::meets`]: error at most
//! the tolerance within the time limit),
//!
//! `r_{p,s} = t_{p,s} / min_s t_{p,s}`,   `rho_s(tau) = card{p : r_{p,s} <= tau} / n_p`.
//!
//! `rho_s(1)` is the share of problems on which `s` was fastest, `rho_s(inf)` the share it
//! solved at all. A problem no solver solved stays in `n_p` with infinite ratios for everyone,
//! so no curve reaches 1 (ABH chose their limits so that this never happened; here it shows).

use super::{same_tolerance, Comparison, ComparisonRow};
use crate::results::{PlotData, ReferenceLine, Series};

/// The performance profile of a comparison at one tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct PerformanceProfile {
    /// The tolerance of the profile.
    pub tolerance: f64,
    /// Solver names, the index `s` of `ratios`.
    pub solvers: Vec<String>,
    /// Problem names, the index `p` of `ratios`.
    pub problems: Vec<String>,
    /// `ratios[s][p] = r_{p,s}`; infinite where `s` did not solve `p`.
    pub ratios: Vec<Vec<f64>>,
}

/// The profile of `comparison` at `tolerance` over its problems and solvers; a missing row
/// counts as a failure.
pub fn performance_profile(comparison: &Comparison, tolerance: f64) -> PerformanceProfile {
    let problems = comparison.problem_names();
    let times: Vec<Vec<f64>> = comparison
        .solvers
        .iter()
        .map(|s| {
            problems
                .iter()
                .map(|p| {
                    comparison
                        .row(p, s, tolerance)
                        .filter(|r| r.meets(comparison.time_limit_s))
                        .map_or(f64::INFINITY, |r| r.seconds)
                })
                .collect()
        })
        .collect();
    PerformanceProfile {
        tolerance,
        solvers: comparison.solvers.clone(),
        problems,
        ratios: ratios(&times),
    }
}

/// `r_{p,s}` from `times[s][p]` (infinite: not solved). A time equal to the best gives exactly
/// 1, also when the best time is 0.
pub fn ratios(times: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let problems = times.first().map_or(0, |t| t.len());
    let best: Vec<f64> = (0..problems)
        .map(|p| times.iter().map(|t| t[p]).fold(f64::INFINITY, f64::min))
        .collect();
    times
        .iter()
        .map(|t| {
            t.iter()
                .zip(&best)
                .map(|(&t, &b)| {
                    if !t.is_finite() {
                        f64::INFINITY
                    } else if t == b {
                        1.0
                    } else {
                        t / b
                    }
                })
                .collect()
        })
        .collect()
}

impl PerformanceProfile {
    /// `rho_s(tau)` of solver index `s`; a failure (infinite ratio) never counts, not even at
    /// `tau = inf`.
    pub fn rho(&self, s: usize, tau: f64) -> f64 {
        if self.problems.is_empty() {
            return 0.0;
        }
        let within = self.ratios[s]
            .iter()
            .filter(|&&r| r.is_finite() && r <= tau)
            .count();
        within as f64 / self.problems.len() as f64
    }

    /// Problems no solver solved.
    pub fn unsolved(&self) -> Vec<&str> {
        (0..self.problems.len())
            .filter(|&p| self.ratios.iter().all(|r| r[p].is_infinite()))
            .map(|p| self.problems[p].as_str())
            .collect()
    }

    /// The largest finite ratio (1 when every solved problem was solved fastest).
    pub fn max_ratio(&self) -> f64 {
        self.ratios
            .iter()
            .flatten()
            .copied()
            .filter(|r| r.is_finite())
            .fold(1.0, f64::max)
    }

    /// The profile as step curves against `log2 tau` (Dolan & More's axis), one per solver,
    /// from `tau = 1` to a little beyond the largest finite ratio.
    pub fn plot(&self) -> PlotData {
        let x_end = (self.max_ratio().log2() * 1.1).max(1.0);
        let series = self
            .solvers
            .iter()
            .enumerate()
            .map(|(s, name)| {
                let mut breaks: Vec<f64> = self.ratios[s]
                    .iter()
                    .copied()
                    .filter(|r| r.is_finite() && *r > 1.0)
                    .collect();
                breaks.sort_by(f64::total_cmp);
                breaks.dedup();
                let (mut x, mut y) = (vec![0.0], vec![self.rho(s, 1.0)]);
                for b in breaks {
                    let before = *y.last().expect("starts with tau = 1");
                    x.extend([b.log2(), b.log2()]);
                    y.extend([before, self.rho(s, b)]);
                }
                x.push(x_end);
                y.push(*y.last().expect("starts with tau = 1"));
                Series {
                    name: name.clone(),
                    x,
                    y,
                }
            })
            .collect();
        PlotData {
            title: format!("Performance profile, tolerance {:e}", self.tolerance),
            x_label: "log2 tau (time / fastest time)".into(),
            y_label: "share of problems solved".into(),
            series,
            // Lines at 0 and 1 fix the y axis to the whole range of shares.
            reference_lines: vec![
                ReferenceLine {
                    label: "all problems".into(),
                    y: 1.0,
                    band: None,
                },
                ReferenceLine {
                    label: String::new(),
                    y: 0.0,
                    band: None,
                },
            ],
            log_log: false,
        }
    }
}

/// The work-precision diagram, aggregated over the problems: per solver one curve over the
/// tolerances, each point the total median time over all problems (x) against the worst error
/// reached on any problem (y), log-log. Aggregating keeps one readable curve per solver; the
/// worst error shows whether a solver meets a tolerance everywhere. A solve that returned no
/// multipliers (NaN error) leaves its point out.
pub fn work_precision_plot(comparison: &Comparison) -> PlotData {
    let series = comparison
        .solvers
        .iter()
        .map(|s| {
            let points: Vec<(f64, f64)> = comparison
                .tolerances
                .iter()
                .map(|&tol| {
                    let rows: Vec<&ComparisonRow> = comparison
                        .rows
                        .iter()
                        .filter(|r| &r.solver == s && same_tolerance(r.tolerance, tol))
                        .collect();
                    aggregate(&rows)
                })
                .collect();
            Series {
                name: s.clone(),
                x: points.iter().map(|p| p.0).collect(),
                y: points.iter().map(|p| p.1).collect(),
            }
        })
        .collect();
    PlotData {
        title: "Work-precision (all problems)".into(),
        x_label: "total time over the problems [s]".into(),
        y_label: "worst error ||F||/||q||".into(),
        series,
        reference_lines: Vec::new(),
        log_log: true,
    }
}

/// Total time and worst error of some rows; NaN when there are none or an error is NaN.
fn aggregate(rows: &[&ComparisonRow]) -> (f64, f64) {
    if rows.is_empty() || rows.iter().any(|r| r.error.is_nan()) {
        return (f64::NAN, f64::NAN);
    }
    (
        rows.iter().map(|r| r.seconds).sum(),
        rows.iter().map(|r| r.error).fold(0.0, f64::max),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact_compare::{describe, Comparison, ComparisonRow, NORMALISATION};

    const INF: f64 = f64::INFINITY;

    fn row(problem: &str, solver: &str, seconds: f64, error: f64) -> ComparisonRow {
        ComparisonRow {
            problem: problem.into(),
            solver: solver.into(),
            tolerance: 1e-6,
            error,
            absolute_error: error,
            iterations: 1,
            outer_iterations: 1,
            seconds,
            repeats: 1,
            status: "converged".into(),
            solved: false,
            notes: vec![],
        }
    }

    fn comparison(rows: Vec<ComparisonRow>) -> Comparison {
        let p = crate::contact_compare::test_problem(&[(0, 0, 1.0)], &[-1.0, 0.0, 0.0], &[0.1]);
        Comparison {
            normalisation: NORMALISATION.into(),
            tolerances: vec![1e-6],
            time_limit_s: 10.0,
            solvers: vec!["A".into(), "B".into()],
            problems: ["p1", "p2", "p3"]
                .iter()
                .map(|n| describe(&p, n, n))
                .collect(),
            unreadable: vec![],
            rows,
        }
    }

    /// Two solvers, three problems. A: 1 s, 2 s, and p3 "converged" but with an error above the
    /// tolerance (a failure). B: 2 s, 1 s, 4 s. Ratios A: 1, 2, inf; B: 2, 1, 1.
    #[test]
    fn profile_of_a_hand_made_example() {
        let c = comparison(vec![
            row("p1", "A", 1.0, 1e-7),
            row("p2", "A", 2.0, 1e-9),
            row("p3", "A", 0.5, 1e-3),
            row("p1", "B", 2.0, 1e-7),
            row("p2", "B", 1.0, 1e-7),
            row("p3", "B", 4.0, 1e-8),
        ]);
        let p = performance_profile(&c, 1e-6);
        assert_eq!(p.ratios, vec![vec![1.0, 2.0, INF], vec![2.0, 1.0, 1.0]]);
        let third = 1.0 / 3.0;
        assert_eq!(p.rho(0, 1.0), 1.0 / 3.0);
        assert_eq!(p.rho(0, 1.999), third);
        assert_eq!(p.rho(0, 2.0), 2.0 * third);
        assert_eq!(p.rho(0, 1e9), 2.0 * third, "A never solves p3");
        assert_eq!(p.rho(1, 1.0), 2.0 * third);
        assert_eq!(p.rho(1, 2.0), 1.0);
        assert!(p.unsolved().is_empty());
        assert_eq!(p.max_ratio(), 2.0);
    }

    #[test]
    fn time_limit_missing_rows_and_unsolved_problems_count_as_failures() {
        let mut slow = row("p2", "A", 11.0, 1e-9); // within tolerance, beyond the 10 s limit
        slow.status = "time-limit".into();
        let c = comparison(vec![
            row("p1", "A", 3.0, 1e-7),
            slow,
            row("p3", "A", 1.0, 1e-2),
            row("p1", "B", 1.0, 2e-6),
            row("p2", "B", 1.0, 1e-3),
            // B on p3 never ran.
        ]);
        let p = performance_profile(&c, 1e-6);
        assert_eq!(p.ratios, vec![vec![1.0, INF, INF], vec![INF, INF, INF]]);
        assert_eq!(p.unsolved(), vec!["p2", "p3"]);
        assert_eq!(p.rho(0, INF), 1.0 / 3.0);
        assert_eq!(p.rho(1, INF), 0.0);
    }

    #[test]
    fn the_profile_plot_is_a_step_function_in_log2_tau() {
        let c = comparison(vec![
            row("p1", "A", 1.0, 0.0),
            row("p2", "A", 4.0, 0.0),
            row("p3", "A", 1.0, 0.0),
            row("p1", "B", 2.0, 0.0),
            row("p2", "B", 1.0, 0.0),
            row("p3", "B", 1.0, 0.0),
        ]);
        let plot = performance_profile(&c, 1e-6).plot();
        let a = &plot.series[0];
        // rho_A = 2/3 from tau = 1, steps to 1 at tau = 4 (log2 = 2), then runs on to 2.2.
        assert_eq!(a.x[..3], [0.0, 2.0, 2.0]);
        assert!((a.x[3] - 2.2).abs() < 1e-12, "{:?}", a.x);
        assert_eq!(a.y, vec![2.0 / 3.0, 2.0 / 3.0, 1.0, 1.0]);
        let b = &plot.series[1];
        assert_eq!(b.x[..3], [0.0, 1.0, 1.0]);
        assert_eq!(b.y[..3], [2.0 / 3.0, 2.0 / 3.0, 1.0]);
    }

    #[test]
    fn work_precision_sums_times_and_takes_the_worst_error() {
        let c = comparison(vec![
            row("p1", "A", 1.0, 1e-7),
            row("p2", "A", 2.0, 1e-9),
            row("p3", "A", 0.5, 1e-3),
            row("p1", "B", 2.0, f64::NAN),
        ]);
        let plot = work_precision_plot(&c);
        assert_eq!((plot.series[0].x[0], plot.series[0].y[0]), (3.5, 1e-3));
        assert!(
            plot.series[1].x[0].is_nan(),
            "a NaN error leaves the point out"
        );
        assert!(plot.log_log);
    }
}
