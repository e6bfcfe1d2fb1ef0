//! Why a structural reference (hinge, elastic refinement, static path) cannot be computed on a
//! case's scene.

/// Why a structural reference cannot be computed: the scene lacks what the reference names (a
/// body, a condition, a column), or the solver refuses the derived problem. Each message names
/// the entity and what to change in the case.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The solver refuses the scene, its material or the derived problem.
    #[error(transparent)]
    Solver(#[from] impact_solver::SolverError),
    /// The microplane parameters are refused.
    #[error(transparent)]
    Parameters(#[from] impact_solver::material::microplane::ParameterError),
    /// The hinge's named body is not microplane concrete.
    #[error("the hinge reference names body `{body}`, which is no microplane body of the scene")]
    HingeBody {
        /// The body named.
        body: String,
    },
    /// No microplane body for the hinge.
    #[error("the hinge reference needs a microplane body or region in the scene")]
    HingeNeedsMicroplane,
    /// The material point gave no crack-opening curve.
    #[error(
        "the uniaxial tension of body `{body}` at element size {element_size} m gave no \
         crack-opening curve"
    )]
    NoOpeningCurve {
        /// The body (or `body/region`).
        body: String,
        /// The element size (m).
        element_size: f64,
    },
    /// A notch outside `[0, 0.9 depth)`.
    #[error("the hinge reference's notch {notch} m must lie in [0, 0.9 depth = {limit} m)")]
    Notch {
        /// The notch depth given (m).
        notch: f64,
        /// 0.9 times the beam's depth (m).
        limit: f64,
    },
    /// `pre_peak: own` with another law.
    #[error(
        "the hinge reference's `pre_peak: own` needs `law: own`: the rising branch and the \
         crack-opening law must come from the same test"
    )]
    PrePeakNeedsOwnLaw,
    /// A scene without bodies.
    #[error("the scene has no body")]
    NoBody,
    /// The refined body is not a box mesh.
    #[error(
        "body `{body}` is not a box mesh: the elastic refinement reference refines box meshes only"
    )]
    NotABox {
        /// The body.
        body: String,
    },
    /// The scene lacks the named boundary condition.
    #[error("the scene has no boundary condition `{condition}`")]
    NoCondition {
        /// The condition named.
        condition: String,
    },
    /// The built problem lacks the named constraint.
    #[error("no constraint `{condition}` in the built problem")]
    NoConstraint {
        /// The condition named.
        condition: String,
    },
    /// The static path kept no history.
    #[error("the static path records a history only for bodies with a history")]
    NoHistory,
    /// The static path's history lacks the column.
    #[error("the static path's history has no column `{column}`; it has {columns:?}")]
    NoColumn {
        /// The column named.
        column: String,
        /// The history's columns.
        columns: Vec<String>,
    },
}
