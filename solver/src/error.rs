//! Errors are values: each names the entity at fault and the fix.

use std::path::PathBuf;

use crate::dynamics::InstabilityReport;

#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    #[error(
        "mesh `{mesh}`: element {element} has non-positive volume {volume:.6e} m^3 (nodes {nodes:?}); \
         its nodes are numbered in the wrong sense or it is collapsed. Fix: number the nodes so the \
         volume is positive (swap two of them) or regenerate the mesh; it is never flipped silently"
    )]
    InvertedElement {
        mesh: String,
        element: usize,
        volume: f64,
        nodes: [u32; 4],
    },

    #[error(
        "mesh `{mesh}`: element {element} is degenerate (smallest altitude {altitude:.3e} m against \
         longest edge {edge:.3e} m, ratio {ratio:.3e} below {limit:.1e}). Fix: remesh the region"
    )]
    DegenerateElement {
        mesh: String,
        element: usize,
        altitude: f64,
        edge: f64,
        ratio: f64,
        limit: f64,
    },

    #[error(
        "mesh `{mesh}`: element {element} refers to node {node} but the mesh has {count} nodes"
    )]
    NodeOutOfRange {
        mesh: String,
        element: usize,
        node: u32,
        count: usize,
    },

    #[error("cannot read mesh file `{path}`: {reason}")]
    MeshRead {
        path: PathBuf,
        reason: crate::mesh::gmsh::GmshError,
    },

    #[error(
        "time step {requested:.6e} s is above the stable limit {stable:.6e} s (smallest altitude over \
         dilatational wave speed, element {element}). Fix: lower `time_step` or set \
         `allow_unstable_time_step: true` to run above the limit on purpose"
    )]
    TimeStepAboveStable {
        requested: f64,
        stable: f64,
        element: usize,
    },

    #[error("{0}")]
    Unstable(Box<InstabilityReport>),

    #[error("scene: {entity}: {message}")]
    InvalidScene { entity: String, message: String },

    #[error(
        "body `{body}`: its material ({material}) keeps a history, which its forces advance. Fix: \
         compute them with Model::advance_internal_forces, once per step"
    )]
    ForcesAdvanceHistory {
        body: String,
        material: &'static str,
    },

    #[error(
        "static analysis did not converge at load step {step} of {steps}: residual {residual:.3e} N \
         after {iterations} Newton iterations (tolerance {tolerance:.3e}). Fix: use more load steps"
    )]
    StaticNotConverged {
        step: usize,
        steps: usize,
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },

    #[error(
        "static analysis: the tangent stiffness is singular ({0}). Fix: restrain rigid-body motion"
    )]
    SingularStiffness(String),

    #[error(
        "element {element}: deformation gradient has det F = {det:.3e} <= 0 (element inverted)"
    )]
    ElementInverted { element: usize, det: f64 },

    #[error(
        "run stopped at its time limit of {limit_s:.0} s wall time at step {step} (t = {time:.6e} s); \
         output up to there is written. Fix: raise the case's time limit or coarsen the case"
    )]
    TimeLimit {
        limit_s: f64,
        step: usize,
        time: f64,
    },

    #[error(
        "interrupted by a signal at step {step} (t = {time:.6e} s): the output up to there is \
         written"
    )]
    Interrupted { step: usize, time: f64 },

    #[error("cannot write `{path}`: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

pub type Result<T, E = SolverError> = std::result::Result<T, E>;
