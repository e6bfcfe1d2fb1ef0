//! Reading and writing contact problems in the `contact-problem/1` JSON format of
//! `references/contact-problems/README.md`.
//!
//! Our extensions, all optional, are ignored by a reader that does not know them:
//! - `mu` entries may be `null`: infinite friction (stick, `r_T` free);
//! - `frames`: per contact the rows `n, t1, t2` of its local frame in global axes (9 numbers);
//! - `solutions`: the multipliers solvers returned, `[{ "solver": name, "r": [3 nc] }]`;
//! - `compliance`: the multipliers' unit, `r = compliance * force` (our problems are scaled to a
//!   unit mean diagonal of `W`, so `r`, `q` and `u` are lengths); absent means 1.

use std::path::{Path, PathBuf};

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use super::problem::{ContactProblem, SparseMatrix};

/// The format tag every file carries in its `format` field.
pub const FORMAT: &str = "contact-problem/1";

/// Why a contact-problem file could not be read, checked or written. Each names the file (or
/// the problem) and what is wrong with it.
#[derive(Debug, thiserror::Error)]
pub enum ProblemFileError {
    /// The file could not be read.
    #[error("cannot read contact problem `{}`: {source}", path.display())]
    Read {
        /// The problem file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file is not JSON of the `contact-problem/1` layout.
    #[error("contact problem `{}` is not `{FORMAT}` JSON: {source}", path.display())]
    NotJson {
        /// The problem file.
        path: PathBuf,
        /// The JSON reader's error, with line and column.
        source: serde_json::Error,
    },
    /// The file could not be written.
    #[error("cannot write contact problem `{}`: {source}", path.display())]
    Write {
        /// The problem file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file reads, but the problem it holds does not check.
    #[error("contact problem `{}`: {problem}", path.display())]
    Invalid {
        /// The problem file.
        path: PathBuf,
        /// What does not check.
        problem: InvalidProblem,
    },
}

/// What is wrong with a problem that reads as JSON ([`ProblemFile::to_problem`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvalidProblem {
    /// The `format` field is not [`FORMAT`]; holds what the file says.
    #[error("format is `{0}`, expected `{FORMAT}`")]
    Format(String),
    /// The `dimension` field is not 3; holds it.
    #[error("dimension {0} is not supported; only 3-D contact problems are")]
    Dimension(usize),
    /// `contacts` is 0: there is nothing to solve, and the descriptors of an empty problem
    /// (friction range, condition number) are undefined.
    #[error("`contacts` is 0; a contact problem needs at least one contact")]
    NoContacts,
    /// The lengths of `mu` and `q` do not match the number of contacts.
    #[error("{contacts} contacts need {contacts} mu and {} q values, found {mu} and {q}", 3 * contacts)]
    Sizes {
        /// The `contacts` field: the number of contacts.
        contacts: usize,
        /// Length of `mu` (should be `contacts`).
        mu: usize,
        /// Length of `q` (should be `3 contacts`).
        q: usize,
    },
    /// `W` is not the `3 contacts` square matrix.
    #[error("W is {rows} x {cols}, expected {n} x {n}")]
    MatrixShape {
        /// Rows the file gives for `W`.
        rows: usize,
        /// Columns the file gives for `W`.
        cols: usize,
        /// The size required, `3 contacts`.
        n: usize,
    },
    /// A negative (or NaN) friction coefficient.
    #[error("mu of contact {contact} is {mu}; it must be >= 0")]
    Friction {
        /// Index of the contact, from 0.
        contact: usize,
        /// Its friction coefficient (dimensionless).
        mu: f64,
    },
    /// A NaN or infinite entry of `q` or `W`.
    #[error("q or W holds a value that is not finite")]
    NotFinite,
    /// The number of local frames differs from the number of contacts.
    #[error("{frames} frames for {contacts} contacts")]
    Frames {
        /// Number of frames the file gives.
        frames: usize,
        /// The number of contacts.
        contacts: usize,
    },
    /// A `compliance` that is zero, negative or not finite; holds it.
    #[error("compliance {0} must be positive and finite")]
    Compliance(f64),
    /// A triplet of `W` outside the matrix (the message of [`SparseMatrix::from_triplets`]).
    #[error("{0}")]
    Matrix(#[from] super::problem::TripletOutside),
}

const CONVENTION: &str = "find r, u with u = W r + q, r in K_mu (per contact [normal, t1, t2], \
                          |r_T| <= mu r_N), u_hat = u + [mu |u_T|, 0, 0] in the dual cone, \
                          u_hat . r = 0 (Coulomb); mu null: stick (r_T free, u_T = 0)";

/// A sparse matrix as the file stores it: its shape and `(row, column, value)` triplets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixFile {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Entries `(row, column, value)`, 0-based; repeated positions add up.
    pub triplets: Vec<(usize, usize, f64)>,
}

/// A solution stored with a problem.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredSolution {
    /// Name of the solver that returned it (`contact::registry` spelling).
    pub solver: String,
    /// The multipliers, `3 contacts` values `[r_N, r_T1, r_T2]` per contact, in the unit of the
    /// file's `compliance`.
    pub r: Vec<f64>,
}

/// A contact problem FC(W, q, mu) as the `contact-problem/1` JSON file holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProblemFile {
    /// The format tag, [`FORMAT`].
    pub format: String,
    /// The problem's statement in words (what `W`, `q`, `mu` and `r` mean); informative.
    #[serde(default)]
    pub convention: String,
    /// Where the problem comes from (run, pair, step, pass); informative.
    #[serde(default)]
    pub source: String,
    /// Space dimension; only 3 is read.
    pub dimension: usize,
    /// Number of contacts `nc`.
    pub contacts: usize,
    /// Friction coefficient of each contact; `null` (`None`) sticks.
    pub mu: Vec<Option<f64>>,
    /// The free term `q` of `u = W r + q`, `[normal, t1, t2]` per contact (`3 nc` values), in the
    /// unit of `u` (a length for our scaled problems).
    pub q: Vec<f64>,
    /// The Delassus operator `W` (`3 nc` square), in local contact coordinates.
    #[serde(rename = "W")]
    pub w: MatrixFile,
    /// Local frame of each contact: the rows `n, t1, t2` in global axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<Vec<[f64; 9]>>,
    /// Solutions stored with the problem, for comparison.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub solutions: Vec<StoredSolution>,
    /// `r = compliance * force` (m/N for our scaled problems); absent: 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compliance: Option<f64>,
}

impl ProblemFile {
    /// The file of `problem`, with `solutions` stored beside it.
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

    /// The problem, checked: at least one contact, sizes agree, values are finite, `mu >= 0`.
    pub fn to_problem(&self, name: &str) -> Result<ContactProblem, InvalidProblem> {
        if self.format != FORMAT {
            return Err(InvalidProblem::Format(self.format.clone()));
        }
        if self.dimension != 3 {
            return Err(InvalidProblem::Dimension(self.dimension));
        }
        if self.contacts == 0 {
            return Err(InvalidProblem::NoContacts);
        }
        let n = 3 * self.contacts;
        if self.mu.len() != self.contacts || self.q.len() != n {
            return Err(InvalidProblem::Sizes {
                contacts: self.contacts,
                mu: self.mu.len(),
                q: self.q.len(),
            });
        }
        if self.w.rows != n || self.w.cols != n {
            return Err(InvalidProblem::MatrixShape {
                rows: self.w.rows,
                cols: self.w.cols,
                n,
            });
        }
        let mu: Vec<f64> = self.mu.iter().map(|m| m.unwrap_or(f64::INFINITY)).collect();
        if let Some((a, m)) = mu.iter().enumerate().find(|(_, m)| !(**m >= 0.0)) {
            return Err(InvalidProblem::Friction { contact: a, mu: *m });
        }
        if self.q.iter().any(|v| !v.is_finite())
            || self.w.triplets.iter().any(|(_, _, v)| !v.is_finite())
        {
            return Err(InvalidProblem::NotFinite);
        }
        let frames = match &self.frames {
            None => None,
            Some(f) if f.len() == self.contacts => Some(
                f.iter()
                    .map(|v| Matrix3::from_row_slice(v))
                    .collect::<Vec<_>>(),
            ),
            Some(f) => {
                return Err(InvalidProblem::Frames {
                    frames: f.len(),
                    contacts: self.contacts,
                })
            }
        };
        Ok(ContactProblem {
            w: SparseMatrix::from_triplets(n, &self.w.triplets).map_err(InvalidProblem::Matrix)?,
            q: self.q.clone(),
            mu,
            frames,
            compliance: match self.compliance {
                None => 1.0,
                Some(c) if c > 0.0 && c.is_finite() => c,
                Some(c) => return Err(InvalidProblem::Compliance(c)),
            },
            source: if self.source.is_empty() {
                name.to_string()
            } else {
                format!("{name} ({})", self.source)
            },
        })
    }

    /// Reads and parses a problem file (unchecked: see [`Self::to_problem`]).
    pub fn read(path: &Path) -> Result<Self, ProblemFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| ProblemFileError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|source| ProblemFileError::NotJson {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Writes the problem as JSON to `path`.
    pub fn write(&self, path: &Path) -> Result<(), ProblemFileError> {
        let text = serde_json::to_string(self).expect("a problem serialises");
        std::fs::write(path, text).map_err(|source| ProblemFileError::Write {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// Reads a problem file into a checked problem; errors name the file.
pub fn read_problem(
    path: &Path,
) -> Result<(ContactProblem, Vec<StoredSolution>), ProblemFileError> {
    let file = ProblemFile::read(path)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let problem = file
        .to_problem(&name)
        .map_err(|problem| ProblemFileError::Invalid {
            path: path.to_path_buf(),
            problem,
        })?;
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
        let negative = file.to_problem("p").unwrap_err();
        assert_eq!(
            negative,
            InvalidProblem::Friction {
                contact: 0,
                mu: -0.1
            }
        );
        assert!(negative.to_string().contains("mu of contact 0"));
        file.mu = vec![Some(0.1)];
        file.q.push(0.0);
        let sizes = file.to_problem("p").unwrap_err();
        assert_eq!(
            sizes,
            InvalidProblem::Sizes {
                contacts: 1,
                mu: 1,
                q: 4
            }
        );
        assert!(sizes.to_string().contains("3 q values"));
        file.contacts = 0;
        file.mu.clear();
        file.q.clear();
        file.w = MatrixFile {
            rows: 0,
            cols: 0,
            triplets: Vec::new(),
        };
        let empty = file.to_problem("p").unwrap_err();
        assert_eq!(empty, InvalidProblem::NoContacts);
        assert!(empty.to_string().contains("`contacts` is 0"), "{empty}");
    }

    /// Reading names the file: one that is missing, one that is not JSON, and one whose
    /// problem does not check, each with its own error.
    #[test]
    fn file_errors_name_the_file() {
        let dir = std::env::temp_dir().join(format!("problem-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let missing = dir.join("missing.json");
        let e = read_problem(&missing).unwrap_err();
        assert!(matches!(e, ProblemFileError::Read { .. }), "{e}");
        assert!(e.to_string().contains("missing.json"), "{e}");
        let text = dir.join("text.json");
        std::fs::write(&text, "not json").unwrap();
        let e = read_problem(&text).unwrap_err();
        assert!(matches!(e, ProblemFileError::NotJson { .. }), "{e}");
        let wrong = dir.join("wrong.json");
        std::fs::write(
            &wrong,
            r#"{"format": "contact-problem/2", "dimension": 3, "contacts": 0, "mu": [], "q": [],
                "W": {"rows": 0, "cols": 0, "triplets": []}}"#,
        )
        .unwrap();
        let e = read_problem(&wrong).unwrap_err();
        assert!(
            matches!(
                &e,
                ProblemFileError::Invalid {
                    problem: InvalidProblem::Format(f),
                    ..
                } if f == "contact-problem/2"
            ),
            "{e}"
        );
        assert!(e.to_string().contains("wrong.json"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
