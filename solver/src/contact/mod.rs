//! Contact (thesis chapters 6 and 7).

pub mod ccd;
pub mod conic;
pub mod detection;
pub mod gauss_seidel;
pub mod local;
pub use detection::normals;
pub mod newton;
pub mod nsgs;
mod phase;
pub mod problem;
pub mod problem_file;
pub mod registry;
pub mod solver;
#[cfg(test)]
mod test_blocks;

use ccd::Trajectory;
use normals::NormalSettings;
use problem::ContactProblem;
use registry::SolverChoice;

pub use phase::ContactPhase;

/// A contact problem recorded during a run, with the multipliers the run's solver returned.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedProblem {
    /// Index of the time step (from 0) whose contact phase built the problem.
    pub step: usize,
    /// Name of the contact pair.
    pub pair: String,
    /// 0: the first body's nodes as slaves; 1: the roles swapped (7.2).
    pub pass: usize,
    /// The problem FC(W, q, mu) as the solver received it.
    pub problem: ContactProblem,
    /// Name of the run's solver (`registry` spelling).
    pub solver: String,
    /// Local multipliers `[r_N, r_T1, r_T2]` per contact.
    pub r: Vec<f64>,
    /// Whether the run's solver met its stopping test on this problem.
    pub converged: bool,
}

/// A vertex-face CCD query made by detection during a run, with our answer: for cross-checks of
/// [`ccd::vertex_face_ccd`] against another implementation on real inputs.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedCcdQuery {
    /// Index of the time step (from 0) whose detection made the query.
    pub step: usize,
    /// Name of the contact pair.
    pub pair: String,
    /// 0: the first body's nodes as slaves; 1: the roles swapped (7.2).
    pub pass: usize,
    /// The slave node's motion over the step.
    pub node: Trajectory,
    /// The master face's node motions, in the face's node order.
    pub face: [Trajectory; 3],
    /// The barycentric tolerance passed to `vertex_face_ccd`.
    pub tolerance: f64,
    /// The step fraction it returned, before detection dropped hits that do not move into the
    /// face.
    pub hit: Option<f64>,
}

/// Two bodies that may touch, and how their contact is solved (FORMULATION section 4).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// Name of the pair; labels its history columns and recorded problems.
    pub name: String,
    /// Indices of the two bodies in the model; the first one's nodes are the slaves of the
    /// first pass (7.2).
    pub bodies: [usize; 2],
    /// Coulomb coefficient; `f64::INFINITY` sticks, `0` is frictionless.
    pub friction: f64,
    /// `beta = beta_0 + 1/2` of the beta-2 corrections; 0 is exactly central differences.
    pub beta_0: f64,
    /// The solver of the pair's contact problems and its stopping rule.
    pub solver: SolverChoice,
    /// Record the contact problems of every `n`-th step (`None`: none).
    pub record_every: Option<usize>,
    /// Record every vertex-face CCD query of detection in every `n`-th step (`None`: none), as
    /// [`RecordedCcdQuery`]; recording changes no result.
    pub record_ccd_every: Option<usize>,
    /// Tolerance on barycentric coordinates in detection.
    pub detection_tolerance: f64,
    /// Repeat detection and resolution with the slave and master roles swapped (7.2).
    pub two_pass: bool,
    /// How contact normals are formed (facet or smoothed corner normals).
    pub normals: NormalSettings,
    /// Leave out of both surfaces the faces on a plane of symmetry
    /// (`phase::symmetry_face`). In a model cut by symmetry planes the two bodies' cut faces
    /// lie in one plane, and a node on one of them is tested against faces of the other that it
    /// slides on: its contact normal lies along the axis both are held on, the Delassus block
    /// along it is nearly zero, and the force that closes a gap of round-off size moves the
    /// nodes by centimetres along the normal's small free components (seen at a nail's tip
    /// after a remeshing of the block). No contact crosses such a plane: the mirror image
    /// continues each body.
    pub skip_symmetry_faces: bool,
    /// The largest relative speed (m/s) at which a penetration left from an earlier step is
    /// removed: a node found behind a face it did not cross in the step (a surface a remeshing
    /// moved, a node left inside) is pushed out over several steps rather than in one, which
    /// closing a depth `d` in a step `dt` would do at `d / dt` (35 um in 6e-9 s: 6 km/s, at the
    /// nail's plate). Penetrations made in the step are closed at once. `f64::INFINITY`
    /// (the default): every penetration is closed at once (thesis 6.5).
    pub penetration_release_speed: f64,
}

/// What the contact phase did in one step, per pair.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStep {
    /// Contacts that carry a force after resolution, over both passes.
    pub active: usize,
    /// Solver iterations (Gauss-Seidel sweeps or interior-point iterations) over the step.
    pub iterations: usize,
    /// Whether every solve of the step met its stopping test.
    pub converged: bool,
    /// Contacts detected but not enforced: no face found for a crossing node, or a normal no
    /// free node can move along.
    pub unresolved: usize,
    /// Sum of the normal components of the contact multipliers `r`; the time stepper turns
    /// multipliers into forces (N).
    pub normal_force: f64,
    /// Sum of the magnitudes of the tangential components, as `normal_force`.
    pub tangential_force: f64,
    /// Contacts whose force lies on the Coulomb cone (sliding).
    pub sliding: usize,
    /// Contact problems solved (passes with at least one contact).
    pub solves: usize,
    /// Of those, the ones whose solver did not converge.
    pub not_converged: usize,
}
