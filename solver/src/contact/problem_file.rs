//! Reading and writing contact problems in the `contact-problem/1` JSON format of
//! `shared/data/contact-problems/README.md`.
//!
//! Our extensions, all optional, are ignored by a reader that does not know them:
//! - `mu` entries may be `null`: infinite friction (stick, `r_T` free);
//! - `frames`: per contact the rows `n, t1, t2` of its local frame in global axes (9 numbers);
//! - `solutions`: the multipliers solvers returned, `[{ "solver": name, "r": [3 nc] }]`;
//! - `compliance`: the multipliers' unit, `r = compliance * force` (our problems are scaled to a
//!   unit mean diagonal of `W`, so `r`, `q` and `u` are lengths); absent means 1.

use std::path::Path;

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use super::problem::{ContactProblem, SparseMatrix};

pub const FORMAT: &str = "contact-problem/1";

const CONVENTION: &str = "find r, u with u = W r + q, r in K_mu (per contact [normal, t1, t2], \
                          |r_T| <= mu r_N), u_hat = u + [mu |u_T|, 0, 0] in the dual cone, \
                          u_hat . r = 0 (Coulomb); mu null: stick (r_T free, u_T = 0)";

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixFile {
    pub rows: usize,
    pub cols: usize,
    pub triplets: Vec<(usize, usize, f64)>,
}

/// A solution stored with a problem.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredSolution {
    pub solver: String,
    pub r: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProblemFile {
    pub format: String,
    #[serde(default)]
    pub convention: String,
    #[serde(default)]
    pub source: String,
    pub dimension: usize,
    pub contacts: usize,
    pub mu: Vec<Option<f64>>,
    pub q: Vec<f64>,
    #[serde(rename = "W")]
    pub w: MatrixFile,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<Vec<[f64; 9]>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub solutions: Vec<StoredSolution>,
    /// `r = compliance * force` (m/N for our scaled problems); absent: 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compliance: Option<f64>,
}

impl ProblemFile {
    pub fn from_problem(problem: &ContactProblem, solutions: Vec<StoredSolution>) -> Self {
        let n = problem.w.size;
        Self {
            format: FORMAT.into(),
            convention: CONVENTION.into(),
            source: problem.source.clone(),
            dimension: 3,
            contacts: problem.contacts(),
            mu: problem
                .mu
                .iter()
                .map(|&m| m.is_finite().then_some(m))
                .collect(),
            q: problem.q.clone(),
            w: MatrixFile {
                rows: n,
                cols: n,
                triplets: problem.w.triplets(),
            },
            frames: problem.frames.as_ref().map(|frames| {
                frames
                    .iter()
                    .map(|f| std::array::from_fn(|k| f[(k / 3, k % 3)]))
                    .collect()
            }),
            solutions,
            compliance: (problem.compliance != 1.0).then_some(problem.compliance),
        }
    }

    /// The problem, checked: sizes agree, values are finite, `mu >= 0`.
    pub fn to_problem(&self, name: &str) -> Result<ContactProblem, String> {
        if self.format != FORMAT {
            return Err(format!("format is `{}`, expected `{FORMAT}`", self.format));
        }
        if self.dimension != 3 {
            return Err(format!(
                "dimension {} is not supported; only 3-D contact problems are",
                self.dimension
            ));
        }
        let n = 3 * self.contacts;
        if self.mu.len() != self.contacts || self.q.len() != n {
            return Err(format!(
                "{} contacts need {} mu and {n} q values, found {} and {}",
                self.contacts,
                self.contacts,
                self.mu.len(),
                self.q.len()
            ));
        }
        if self.w.rows != n || self.w.cols != n {
            return Err(format!(
                "W is {} x {}, expected {n} x {n}",
                self.w.rows, self.w.cols
            ));
        }
        let mu: Vec<f64> = self.mu.iter().map(|m| m.unwrap_or(f64::INFINITY)).collect();
        if let Some((a, m)) = mu.iter().enumerate().find(|(_, m)| !(**m >= 0.0)) {
            return Err(format!("mu of contact {a} is {m}; it must be >= 0"));
        }
        if self.q.iter().any(|v| !v.is_finite())
            || self.w.triplets.iter().any(|(_, _, v)| !v.is_finite())
        {
            return Err("q or W holds a value that is not finite".into());
        }
        let frames = match &self.frames {
            None => None,
            Some(f) if f.len() == self.contacts => Some(
                f.iter()
                    .map(|v| Matrix3::from_row_slice(v))
                    .collect::<Vec<_>>(),
            ),
            Some(f) => return Err(format!("{} frames for {} contacts", f.len(), self.contacts)),
        };
        Ok(ContactProblem {
            w: SparseMatrix::from_triplets(n, &self.w.triplets)?,
            q: self.q.clone(),
            mu,
            frames,
            compliance: match self.compliance {
                None => 1.0,
                Some(c) if c > 0.0 && c.is_finite() => c,
                Some(c) => return Err(format!("compliance {c} must be positive and finite")),
            },
            source: if self.source.is_empty() {
                name.to_string()
            } else {
                format!("{name} ({})", self.source)
            },
        })
    }

    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read contact problem `{}`: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| {
            format!(
                "contact problem `{}` is not `{FORMAT}` JSON: {e}",
                path.display()
            )
        })
    }

    pub fn write(&self, path: &Path) -> Result<(), String> {
        let text = serde_json::to_string(self).expect("a problem serialises");
        std::fs::write(path, text)
            .map_err(|e| format!("cannot write contact problem `{}`: {e}", path.display()))
    }
}

/// Reads a problem file into a checked problem; errors name the file.
pub fn read_problem(path: &Path) -> Result<(ContactProblem, Vec<StoredSolution>), String> {
    let file = ProblemFile::read(path)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let problem = file
        .to_problem(&name)
        .map_err(|e| format!("contact problem `{}`: {e}", path.display()))?;
    Ok((problem, file.solutions))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_problem_survives_writing_and_reading_bit_for_bit() {
        let w = SparseMatrix::from_triplets(
            6,
            &[
                (0, 0, 1.0 / 3.0),
                (1, 1, 2.0),
                (2, 2, 2.0),
                (3, 3, 0.1),
                (0, 3, 1e-17),
                (3, 0, 1e-17),
            ],
        )
        .unwrap();
        let problem = ContactProblem {
            w,
            q: vec![-1.0, 0.5, 0.0, -0.1, 0.0, std::f64::consts::PI],
            mu: vec![f64::INFINITY, 0.3],
            frames: Some(vec![Matrix3::identity(), Matrix3::identity()]),
            compliance: 2.5e-9,
            source: "unit".into(),
        };
        let file = ProblemFile::from_problem(
            &problem,
            vec![StoredSolution {
                solver: "x".into(),
                r: vec![0.1; 6],
            }],
        );
        let dir = std::env::temp_dir().join(format!("impact-problem-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.json");
        file.write(&path).unwrap();
        let (back, solutions) = read_problem(&path).unwrap();
        assert_eq!(back.w, problem.w);
        assert_eq!(back.q, problem.q);
        assert_eq!(back.mu, problem.mu);
        assert_eq!(back.frames, problem.frames);
        assert_eq!(back.compliance, problem.compliance);
        assert_eq!(solutions[0].r, vec![0.1; 6]);
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn malformed_problems_are_refused_with_the_reason() {
        let mut file = ProblemFile::from_problem(
            &ContactProblem {
                w: SparseMatrix::from_triplets(3, &[(0, 0, 1.0)]).unwrap(),
                q: vec![-1.0, 0.0, 0.0],
                mu: vec![0.2],
                frames: None,
                compliance: 1.0,
                source: String::new(),
            },
            vec![],
        );
        file.mu = vec![Some(-0.1)];
        assert!(file
            .to_problem("p")
            .unwrap_err()
            .contains("mu of contact 0"));
        file.mu = vec![Some(0.1)];
        file.q.push(0.0);
        assert!(file.to_problem("p").unwrap_err().contains("3 q values"));
    }
}
