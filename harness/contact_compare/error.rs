//! Why a contact comparison cannot run: bad arguments, missing inputs, an unwritable folder.

/// Why `contact-compare` (or a replay of recorded problems) cannot run; each message names the
/// argument, file or folder and what to give instead.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A solver name the registry does not know (the message lists the known ones).
    #[error(transparent)]
    UnknownSolver(#[from] impact_solver::contact::registry::UnknownSolver),
    /// No input given.
    #[error("no contact-problem files or folders given")]
    NoInputs,
    /// A folder of problems cannot be listed.
    #[error("cannot list folder `{folder}`: {message}")]
    ListFolder {
        /// The folder.
        folder: String,
        /// The operating system's reason.
        message: String,
    },
    /// A folder holds no problem file.
    #[error("folder `{folder}` holds no contact-problem files (*.json)")]
    EmptyFolder {
        /// The folder.
        folder: String,
    },
    /// An input path that does not exist.
    #[error("contact-problem file or folder `{path}` does not exist")]
    Missing {
        /// The path given.
        path: String,
    },
    /// A tolerance that is not positive.
    #[error("tolerance {tolerance} is not positive")]
    Tolerance {
        /// The tolerance given.
        tolerance: f64,
    },
    /// No tolerance at all.
    #[error("no tolerance given (--tolerances 1e-4,1e-6,1e-8)")]
    NoTolerance,
    /// A time limit that is not a positive, finite number.
    #[error(
        "--time-limit {limit} must be a positive, finite number of seconds (e.g. --time-limit 10)"
    )]
    TimeLimit {
        /// The limit given (s).
        limit: f64,
    },
    /// No file could be read as a problem.
    #[error("none of the {files} file(s) could be read as a contact problem")]
    NothingReadable {
        /// Files tried.
        files: usize,
    },
    /// The output folder cannot be written before the solves.
    #[error("cannot write into `{out}`: {message}; give a writable folder with --out")]
    NotWritable {
        /// The output folder.
        out: String,
        /// The operating system's reason.
        message: String,
    },
    /// The outputs cannot be written after the solves.
    #[error("cannot write into `{out}`: {message}")]
    Write {
        /// The output folder.
        out: String,
        /// The reason.
        message: String,
    },
}
