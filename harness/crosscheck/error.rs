//! Why a cross-check cannot run: the scene does not have the shape the reference script can
//! reproduce, an answer or cache is missing or stale, or a query file is damaged.

/// Why a cross-check cannot run or refresh. Each message names the file, condition, body or
/// answer field and, where there is one, the fix.
#[derive(Debug, thiserror::Error)]
pub enum CrosscheckError {
    /// The solver refuses the scene or a run fails.
    #[error(transparent)]
    Solver(#[from] impact_solver::SolverError),
    /// A file cannot be read or written.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// The reason.
        message: String,
    },
    /// A case file cannot be read.
    #[error(transparent)]
    Case(#[from] crate::case_file::CatalogueError),
    /// An answer cannot be serialised.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// The elastic-beam cross-check without a scene.
    #[error("elastic_beam needs a scene")]
    NeedsScene,
    /// A quantity that the cross-check did not measure.
    #[error("`{quantity}` was not measured")]
    NotMeasured {
        /// The quantity.
        quantity: String,
    },
    /// The model has no body of that name.
    #[error("no body `{body}`")]
    NoBody {
        /// The body.
        body: String,
    },
    /// No node at a deflection point.
    #[error("no node of `{body}` at {point:?}: choose mesh divisions that put one there")]
    NoNodeAt {
        /// The body.
        body: String,
        /// The point (m).
        point: [f64; 3],
    },
    /// The built problem lacks a constraint.
    #[error("no constraint `{name}` in the built problem")]
    NoConstraint {
        /// The condition.
        name: String,
    },
    /// The explicit run kept no history.
    #[error("the explicit run kept no history")]
    NoHistory,
    /// The history lacks a column.
    #[error("the history has no column `{column}`")]
    NoColumn {
        /// The column.
        column: String,
    },
    /// The scene lacks a boundary condition.
    #[error("the scene has no boundary condition `{name}`")]
    NoCondition {
        /// The condition.
        name: String,
    },
    /// A condition that does not select a box.
    #[error(
        "boundary condition `{name}` selects {selector}: the elastic-beam cross-check needs a box \
         selector, which the reference script can reproduce"
    )]
    NotABoxSelector {
        /// The condition.
        name: String,
        /// Its selector, as written by `Debug`.
        selector: String,
    },
    /// The scene lacks the beam's body.
    #[error("the scene has no body `{body}`")]
    NoSceneBody {
        /// The body.
        body: String,
    },
    /// The beam is not a box mesh.
    #[error("body `{body}` needs a box mesh")]
    BodyNotBox {
        /// The body.
        body: String,
    },
    /// The beam's box does not start at the origin.
    #[error("body `{body}`: the box must start at the origin (it starts at {origin:?})")]
    NotAtOrigin {
        /// The body.
        body: String,
        /// The box's origin (m).
        origin: [f64; 3],
    },
    /// The beam is not linear elastic.
    #[error("body `{body}` must be linear elastic: the cross-check is an elastic solution")]
    NotElastic {
        /// The body.
        body: String,
    },
    /// A support or plate that is not a full-width strip of a face.
    #[error(
        "boundary condition `{name}` must select a full-width strip of the face y = {y} (it \
         selects {min:?} to {max:?})"
    )]
    NotAStrip {
        /// The condition.
        name: String,
        /// The face (m).
        y: f64,
        /// Lower corner of its box (m).
        min: [f64; 3],
        /// Upper corner of its box (m).
        max: [f64; 3],
    },
    /// A condition whose motion the reference script cannot reproduce.
    #[error("{role} `{name}` must {requirement}")]
    Motion {
        /// `support`, `plate` or `pin`.
        role: &'static str,
        /// The condition.
        name: String,
        /// What it must be.
        requirement: &'static str,
    },
    /// A number missing from scikit-fem's answer.
    #[error("scikit-fem's answer has no number at {at}")]
    AnswerNumber {
        /// Where in the answer.
        at: String,
    },
    /// A list missing from an answer.
    #[error("{script}'s answer has no `{field}`")]
    AnswerField {
        /// `scikit-fem` or `ipctk`.
        script: &'static str,
        /// The field.
        field: &'static str,
    },
    /// ipctk answered a different number of queries.
    #[error("ipctk answered {answered} queries, there are {queries}")]
    AnswerCount {
        /// Queries answered.
        answered: usize,
        /// Queries asked.
        queries: usize,
    },
    /// A list of levels is empty.
    #[error("{levels} is empty")]
    NoLevels {
        /// `implicit_levels` or `explicit_levels`.
        levels: &'static str,
    },
    /// An answer without provenance.
    #[error("the answer has no `provenance`")]
    NoProvenance,
    /// A provenance without a key.
    #[error("the answer's provenance has no `{key}`")]
    ProvenanceKey {
        /// The key.
        key: String,
    },
    /// No cached answer.
    #[error(
        "no cached answer at {path} ({message}). Fix: refresh it with `cargo run --release \
         --features python --bin impact-vv -- crosscheck-refresh` (needs the packages of \
         references/crosscheck/requirements.txt)"
    )]
    NoCache {
        /// The cache file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// The cached answer was computed for another request.
    #[error(
        "the cached answer in {path} was computed for another request ({differences}). Fix: \
         refresh it with `cargo run --release --features python --bin impact-vv -- \
         crosscheck-refresh`"
    )]
    StaleCache {
        /// The cache file.
        path: String,
        /// Where the requests differ.
        differences: String,
    },
    /// The reference script cannot be read.
    #[error("cannot read the reference script {path}: {message}")]
    ReadScript {
        /// The script.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// The reference script raised an exception.
    #[error("{name} raised {error}{hint}")]
    Raised {
        /// The script.
        name: String,
        /// Python's error.
        error: String,
        /// The fix for a missing package, or nothing.
        hint: String,
    },
    /// The reference script answered something that is not JSON.
    #[error("{name} answered invalid JSON: {message}")]
    InvalidJson {
        /// The script.
        name: String,
        /// The JSON reader's error.
        message: String,
    },
    /// This build cannot run Python.
    #[error(
        "{name} cannot run: this build has no Python. Fix: build with `--features python` and \
         install the packages: `python3 -m pip install -r references/crosscheck/requirements.txt`"
    )]
    NoPython {
        /// The script.
        name: String,
    },
    /// A damaged CCD query file, or a recording that cannot be made.
    #[error("{file}: {problem}")]
    Queries {
        /// The query or case file.
        file: String,
        /// What is wrong.
        problem: QueryProblem,
    },
}

/// What is wrong with a CCD query file or a recording of queries.
#[derive(Debug, thiserror::Error)]
pub enum QueryProblem {
    /// The file cannot be written.
    #[error("cannot write: {0}")]
    Write(String),
    /// The file cannot be read.
    #[error("cannot read: {0}")]
    Read(String),
    /// Shorter than the header.
    #[error("truncated: {bytes} bytes, shorter than the {header}-byte header")]
    ShortHeader {
        /// The file's bytes.
        bytes: usize,
        /// The header's bytes.
        header: usize,
    },
    /// Not a query file.
    #[error("bad magic {found:?}: not a CCD query file (expected {expected:?})")]
    Magic {
        /// The first eight bytes.
        found: String,
        /// The format's magic.
        expected: String,
    },
    /// Fewer bytes than the header announces.
    #[error("truncated: the header announces {count} queries ({expected} bytes), the file has {bytes} bytes")]
    Truncated {
        /// Queries announced.
        count: u64,
        /// Bytes they need.
        expected: usize,
        /// The file's bytes.
        bytes: usize,
    },
    /// Bytes after the last query.
    #[error("{extra} bytes after the {count} queries the header announces")]
    Trailing {
        /// Bytes too many.
        extra: usize,
        /// Queries announced.
        count: u64,
    },
    /// A count whose size overflows.
    #[error("impossible query count {0}")]
    Count(u64),
    /// A query of unknown source.
    #[error("query {index} has unknown source code {code}")]
    Source {
        /// The query's index.
        index: usize,
        /// Its source code byte.
        code: u8,
    },
    /// Recording every zero steps.
    #[error("record every 0 steps: give 1 or more")]
    EveryZero,
    /// A recording end time that is not positive.
    #[error("end time {0} s must be positive")]
    EndTime(f64),
    /// A case file without a scene.
    #[error("the case has no scene to record CCD queries from")]
    NoScene,
    /// A scene that is not explicit dynamics.
    #[error(
        "the scene's analysis is not explicit dynamics; CCD queries are recorded from explicit runs"
    )]
    NotExplicit,
    /// A scene without contact.
    #[error("the scene has no contact pair")]
    NoContact,
    /// The scene cannot be built or its solver started.
    #[error("{0}")]
    Solver(impact_solver::SolverError),
    /// The run failed.
    #[error("the run failed: {0}")]
    RunFailed(String),
}
