//! The tables of a comparison as plain text cells, shared by `README.md` of the command and by
//! the run report (which escapes them), so that both show the same numbers.

use super::{performance_profile, Comparison, ComparisonRow};
use crate::report::format::{markdown_cell, num, seconds};

/// A table of plain-text cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The column headings.
    pub head: Vec<String>,
    /// The rows, each with one cell per heading.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// A GitHub-flavoured Markdown table.
    pub fn to_markdown(&self) -> String {
        let line = |cells: &[String]| {
            let cells: Vec<String> = cells.iter().map(|c| markdown_cell(c)).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut md = line(&self.head);
        md.push_str(&format!("|{}\n", "---|".repeat(self.head.len())));
        for row in &self.rows {
            md.push_str(&line(row));
        }
        md
    }
}

fn strings(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// One row per problem: its descriptors.
pub fn descriptor_table(c: &Comparison) -> Table {
    Table {
        head: strings(&[
            "problem",
            "contacts",
            "unknowns",
            "mu",
            "stick / frictionless",
            "asymmetry ‖W−Wᵀ‖/‖W‖",
            "rank of sym(W) / unknowns",
            "cond sym(W)",
            "nonzeros",
        ]),
        rows: c
            .problems
            .iter()
            .map(|p| {
                // Without a finite mu (every contact sticks) the range is empty: NaN in the
                // descriptors, "n/a" here; the stick count beside it says why.
                let mu = if p.mu_min.is_nan() {
                    "n/a".to_string()
                } else if p.mu_min == p.mu_max {
                    num(p.mu_min)
                } else {
                    format!("{} - {}", num(p.mu_min), num(p.mu_max))
                };
                vec![
                    p.name.clone(),
                    p.contacts.to_string(),
                    p.unknowns.to_string(),
                    mu,
                    format!("{} / {}", p.stick_contacts, p.frictionless_contacts),
                    num(p.asymmetry),
                    format!("{} / {}", p.rank, p.unknowns),
                    condition(p.condition),
                    p.nonzeros.to_string(),
                ]
            })
            .collect(),
    }
}

/// The condition number of sym(W), or "n/a (rank 0)" when it has no positive eigenvalue (an
/// all-zero `W`): the descriptors hold NaN then.
fn condition(c: f64) -> String {
    if c.is_nan() {
        "n/a (rank 0)".to_string()
    } else {
        num(c)
    }
}

/// One cell of the error matrix: error, a tick when solved, the cost, and the status when it
/// is not `converged`.
pub fn cell(r: &ComparisonRow) -> String {
    let mark = if r.solved { "✓" } else { "✗" };
    let status = if r.status == "converged" {
        String::new()
    } else {
        format!(" {}", r.status)
    };
    format!(
        "{} {mark}{status} ({} it, {})",
        num(r.error),
        r.iterations,
        seconds(r.seconds)
    )
}

/// At one tolerance: one row per problem, one column per solver, each cell the error reached
/// (✓ solved in the sense of the profiles), iterations and median time.
pub fn error_matrix(c: &Comparison, tolerance: f64) -> Table {
    let mut head = vec!["problem".to_string()];
    head.extend(c.solvers.iter().cloned());
    Table {
        head,
        rows: c
            .problems
            .iter()
            .map(|p| {
                let mut row = vec![p.name.clone()];
                row.extend(c.solvers.iter().map(|s| {
                    c.row(&p.name, s, tolerance)
                        .map_or_else(|| "not run".to_string(), cell)
                }));
                row
            })
            .collect(),
    }
}

/// Per solver and tolerance: problems solved, total time, worst error, and `rho(1)` (the share
/// of problems it was fastest on).
pub fn solver_summary(c: &Comparison) -> Table {
    let mut rows = Vec::new();
    for &tol in &c.tolerances {
        let profile = performance_profile(c, tol);
        for (s, name) in c.solvers.iter().enumerate() {
            let mine: Vec<&ComparisonRow> = c
                .rows
                .iter()
                .filter(|r| &r.solver == name && super::same_tolerance(r.tolerance, tol))
                .collect();
            let worst = mine.iter().map(|r| r.error).fold(0.0, |a: f64, e| {
                if e.is_nan() || a.is_nan() {
                    f64::NAN
                } else {
                    a.max(e)
                }
            });
            rows.push(vec![
                name.clone(),
                format!("{tol:e}"),
                format!(
                    "{}/{}",
                    mine.iter().filter(|r| r.solved).count(),
                    c.problems.len()
                ),
                seconds(mine.iter().map(|r| r.seconds).sum()),
                num(worst),
                num(profile.rho(s, 1.0)),
            ]);
        }
    }
    Table {
        head: strings(&[
            "solver",
            "tolerance",
            "solved",
            "total time",
            "worst error",
            "fastest on (share)",
        ]),
        rows,
    }
}

/// Every row of the comparison.
pub fn long_table(c: &Comparison) -> Table {
    Table {
        head: strings(&[
            "problem",
            "solver",
            "tolerance",
            "error",
            "iterations",
            "outer",
            "median time",
            "repeats",
            "status",
            "solved",
            "notes",
        ]),
        rows: c
            .rows
            .iter()
            .map(|r| {
                vec![
                    r.problem.clone(),
                    r.solver.clone(),
                    format!("{:e}", r.tolerance),
                    num(r.error),
                    r.iterations.to_string(),
                    r.outer_iterations.to_string(),
                    seconds(r.seconds),
                    r.repeats.to_string(),
                    r.status.clone(),
                    if r.solved { "yes" } else { "no" }.to_string(),
                    r.notes.join("; "),
                ]
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_tables_escape_separators() {
        let t = Table {
            head: strings(&["a", "b"]),
            rows: vec![vec!["x|y".into(), "1".into()]],
        };
        assert_eq!(t.to_markdown(), "| a | b |\n|---|---|\n| x\\|y | 1 |\n");
    }

    /// An all-zero `W` has no condition number and an all-stick problem no friction range:
    /// the descriptor table says "n/a", never "NaN".
    #[test]
    fn undefined_descriptors_read_n_a() {
        let zero_w = crate::contact_compare::test_problem(&[], &[-1.0, 0.0, 0.0], &[0.3]);
        let stick = crate::contact_compare::test_problem(
            &[(0, 0, 2.0), (1, 1, 2.0), (2, 2, 2.0)],
            &[-1.0, 0.0, 0.0],
            &[f64::INFINITY],
        );
        let c = Comparison {
            normalisation: String::new(),
            tolerances: vec![1e-6],
            time_limit_s: 1.0,
            solvers: Vec::new(),
            problems: vec![
                super::super::describe(&zero_w, "zero", "zero.json"),
                super::super::describe(&stick, "stick", "stick.json"),
            ],
            unreadable: Vec::new(),
            rows: Vec::new(),
        };
        let t = descriptor_table(&c);
        let column = |name: &str| t.head.iter().position(|h| h == name).unwrap();
        assert_eq!(t.rows[0][column("cond sym(W)")], "n/a (rank 0)");
        assert_eq!(t.rows[0][column("mu")], "0.3");
        assert_eq!(t.rows[1][column("mu")], "n/a");
        assert_eq!(t.rows[1][column("cond sym(W)")], "1");
        assert!(!t.to_markdown().contains("NaN"), "{}", t.to_markdown());
    }
}
