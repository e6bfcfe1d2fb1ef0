//! Errors are values: each names the entity at fault and the fix.
//!
//! The lowest layer of the crate: every layer returns [`SolverError`], so this module imports
//! nothing from the others. The reports its variants carry live here too, [`GmshError`] (the
//! mesh reader's, re-exported as `mesh::gmsh::GmshError`) and [`InstabilityReport`] (the
//! explicit integrator's, re-exported as `dynamics::InstabilityReport`).

use std::path::PathBuf;

mod gmsh;
mod instability;

pub use gmsh::GmshError;
pub use instability::InstabilityReport;

/// Every error the solver returns: each variant names the mesh, element, body or file at fault
/// and its message says the fix.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// An element of a mesh has zero or negative reference volume (wrong node order or
    /// collapsed); it is rejected rather than flipped.
    #[error(
        "mesh `{mesh}`: element {element} has non-positive volume {volume:.6e} m^3 (nodes {nodes:?}); \
         its nodes are numbered in the wrong sense or it is collapsed. Fix: number the nodes so the \
         volume is positive (swap two of them) or regenerate the mesh; it is never flipped silently"
    )]
    InvertedElement {
        /// Name of the mesh (its body or file) as the scene gives it.
        mesh: String,
        /// Index of the element in the mesh, from 0.
        element: usize,
        /// Signed reference volume of the element (m^3), `<= 0`.
        volume: f64,
        /// The element's four node indices in the mesh, in the order read.
        nodes: [u32; 4],
    },

    #[error(
        "mesh `{mesh}`: element {element} is degenerate (smallest altitude {altitude:.3e} m against \
         longest edge {edge:.3e} m, ratio {ratio:.3e} below {limit:.1e}). Fix: remesh the region"
    )]
    /// An element is a sliver: its smallest altitude over its longest edge is below the limit
    /// (`Mesh::validate`), so it would dictate a tiny stable time step.
    DegenerateElement {
        /// Name of the mesh (its body or file) as the scene gives it.
        mesh: String,
        /// Index of the element in the mesh, from 0.
        element: usize,
        /// Smallest of the element's four altitudes (m).
        altitude: f64,
        /// Longest of the element's six edges (m).
        edge: f64,
        /// `altitude / edge`, dimensionless.
        ratio: f64,
        /// The smallest ratio accepted (`min_altitude_ratio`), dimensionless.
        limit: f64,
    },

    #[error(
        "mesh `{mesh}`: element {element} refers to node {node} but the mesh has {count} nodes"
    )]
    /// An element's connectivity names a node the mesh does not have.
    NodeOutOfRange {
        /// Name of the mesh (its body or file) as the scene gives it.
        mesh: String,
        /// Index of the element in the mesh, from 0.
        element: usize,
        /// The node index the element refers to (0-based).
        node: u32,
        /// Number of nodes in the mesh; valid indices are `0..count`.
        count: usize,
    },

    #[error("cannot read mesh file `{path}`: {reason}")]
    /// A mesh file could not be read or parsed (the Gmsh reader).
    MeshRead {
        /// The mesh file as given.
        path: PathBuf,
        /// What went wrong: the I/O error, or the entity of the file at fault and the fix.
        reason: GmshError,
    },

    #[error(
        "time step {requested:.6e} s is above the stable limit {stable:.6e} s (smallest altitude over \
         dilatational wave speed, element {element}). Fix: lower `time_step` or set \
         `allow_unstable_time_step: true` to run above the limit on purpose"
    )]
    /// The scene's time step exceeds the stability limit of the central-difference scheme,
    /// `dt <= h_min / c_d` (FORMULATION section 2), and the scene did not allow it.
    TimeStepAboveStable {
        /// The time step the scene asks for (s).
        requested: f64,
        /// The stable limit: smallest altitude over dilatational wave speed (s).
        stable: f64,
        /// Index (over the model's elements) of the element that sets the limit.
        element: usize,
    },

    /// The explicit run blew up (energy growth or non-finite state); the report says where and
    /// when.
    #[error("{0}")]
    Unstable(Box<InstabilityReport>),

    #[error("scene: {entity}: {message}")]
    /// The scene description is inconsistent (an unknown name, a bad value, a missing part).
    InvalidScene {
        /// The scene entry at fault, e.g. "region `top`" or "body `slab`".
        entity: String,
        /// What is wrong with it and how to fix it.
        message: String,
    },

    #[error(
        "body `{body}`: its material ({material}) keeps a history, which its forces advance. Fix: \
         compute them with Model::advance_internal_forces, once per step"
    )]
    /// Internal forces were asked for without advancing a history material (microplane
    /// concrete) whose forces update its state; use `Model::advance_internal_forces`.
    ForcesAdvanceHistory {
        /// Name of the body whose material keeps a history.
        body: String,
        /// The material's name (`Material::name`).
        material: &'static str,
    },

    #[error(
        "static analysis did not converge at load step {step} of {steps}: residual {residual:.3e} N \
         after {iterations} Newton iterations (tolerance {tolerance:.3e}). Fix: use more load steps"
    )]
    /// Newton's method of the static analysis did not reach the tolerance within its iterations
    /// at one load step.
    StaticNotConverged {
        /// The load step that failed, from 1.
        step: usize,
        /// Number of load steps of the analysis.
        steps: usize,
        /// Newton iterations spent on this load step.
        iterations: usize,
        /// Norm of the out-of-balance force on the free degrees of freedom at the last
        /// iteration (N).
        residual: f64,
        /// The residual norm at which the step counts as converged (N).
        tolerance: f64,
    },

    #[error(
        "static analysis: the tangent stiffness is singular ({0}). Fix: restrain rigid-body motion"
    )]
    /// The static tangent stiffness could not be factorised: the body can move as a rigid body
    /// or an element has lost its stiffness. Holds the factorisation's explanation.
    SingularStiffness(String),

    #[error(
        "element {element}: deformation gradient has det F = {det:.3e} <= 0 (element inverted)"
    )]
    /// An element turned inside out during the motion (`J = det F <= 0`).
    ElementInverted {
        /// Index of the element over the model's elements, from 0.
        element: usize,
        /// The Jacobian `J = det F` of the deformation gradient, dimensionless.
        det: f64,
    },

    #[error(
        "run stopped at its time limit of {limit_s:.0} s wall time at step {step} (t = {time:.6e} s); \
         output up to there is written. Fix: raise the case's time limit or coarsen the case"
    )]
    /// The run reached its wall-clock limit; the output up to the last step is written.
    TimeLimit {
        /// The wall-clock limit (s of real time).
        limit_s: f64,
        /// Number of time steps completed when the run stopped.
        step: usize,
        /// Simulated time at that step (s).
        time: f64,
    },

    #[error(
        "interrupted by a signal at step {step} (t = {time:.6e} s): the output up to there is \
         written"
    )]
    /// SIGINT or SIGTERM stopped the run at the end of a step; the output up to there is written.
    Interrupted {
        /// Number of time steps completed when the run stopped.
        step: usize,
        /// Simulated time at that step (s).
        time: f64,
    },

    #[error("remeshing: {entity}: {message}")]
    /// A remeshing step cannot go on: an old element inverted in the current configuration, a new
    /// node or element outside the old mesh, fields of the wrong length (`remesh`).
    Remesh {
        /// The mesh, node, element or field at fault, e.g. "old element 12".
        entity: String,
        /// What is wrong and how to fix it.
        message: String,
    },

    #[error("cannot write `{path}`: {source}")]
    /// An output file or folder could not be created or written.
    Write {
        /// The file or folder being written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
}

/// The solver's result type: `SolverError` unless another error type is named.
pub type Result<T, E = SolverError> = std::result::Result<T, E>;
