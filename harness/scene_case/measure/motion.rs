//! The measures of the final motion: the spin of a body, and the error of a displacement or
//! velocity field against an affine field (the patch tests).

use impact_solver::problem::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;

use super::field::boundary_node_flags;
use super::{FieldQuantity, Measure, MeasureError, NodeScope};
use impact_solver::analysis::Execution;

/// Evaluates `measure` when it is a measure of the final motion; `None` for a measure of another
/// family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
) -> Result<Option<f64>, MeasureError> {
    Ok(Some(match measure {
        Measure::BodySpin { body, scale } => body_spin(problem, run, body)? * scale,
        Measure::AffineFieldError {
            quantity,
            translation,
            gradient,
            center,
            nodes,
        } => {
            let affine = Affine {
                translation,
                gradient,
                center,
            };
            affine_field_error(problem, run, *quantity, &affine, *nodes)?
        }
        _ => return Ok(None),
    }))
}

/// `|omega|` (rad/s) of body `body` at the end of the run: `omega = I^-1 L` with the angular
/// momentum `L` and the inertia tensor `I` about its centre of mass, in the deformed placement.
fn body_spin(problem: &Problem, run: &Execution, body: &str) -> Result<f64, MeasureError> {
    let b = problem
        .model
        .body_index(body)
        .ok_or_else(|| MeasureError::NoBody {
            body: body.to_string(),
        })?;
    let v = run.v.as_ref().ok_or(MeasureError::NeedsExplicitRun)?;
    let nodes = problem.model.bodies[b].nodes.clone();
    let (mass, x) = (&problem.model.mass, |n: usize| {
        problem.model.reference[n] + run.u[n]
    });
    let total: f64 = nodes.clone().map(|n| mass[n]).sum();
    let center = nodes
        .clone()
        .fold(Vector3::zeros(), |a, n| a + x(n) * mass[n])
        / total;
    let v_center = nodes
        .clone()
        .fold(Vector3::zeros(), |a, n| a + v[n] * mass[n])
        / total;
    let (mut l, mut inertia) = (Vector3::zeros(), Matrix3::zeros());
    for n in nodes {
        let r = x(n) - center;
        l += r.cross(&(v[n] - v_center)) * mass[n];
        inertia += (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass[n];
    }
    let omega = inertia.try_inverse().ok_or(MeasureError::SingularInertia)? * l;
    Ok(omega.norm())
}

/// The affine field `t + G (x - c)` of a patch test, as the case file gives it.
struct Affine<'a> {
    translation: &'a [f64; 3],
    gradient: &'a [[f64; 3]; 3],
    center: &'a [f64; 3],
}

/// `max_n |field_n - exact(x_n)| / max_n |exact(x_n)|` over the nodes of `scope`: the exact
/// field is the affine one, scaled by the end time for the displacement of an explicit run
/// (its motion grows at a constant velocity).
fn affine_field_error(
    problem: &Problem,
    run: &Execution,
    quantity: FieldQuantity,
    affine: &Affine,
    scope: NodeScope,
) -> Result<f64, MeasureError> {
    let explicit_time = run.summary.as_ref().map_or(1.0, |s| s.time);
    let (field, scale) = match quantity {
        FieldQuantity::Displacement => (
            &run.u,
            if run.summary.is_some() {
                explicit_time
            } else {
                1.0
            },
        ),
        FieldQuantity::Velocity => (run.v.as_ref().ok_or(MeasureError::NeedsExplicitRun)?, 1.0),
    };
    let g = Matrix3::from_row_slice(&affine.gradient.concat());
    let (t, c) = (
        Vector3::from(*affine.translation),
        Vector3::from(*affine.center),
    );
    let boundary = boundary_node_flags(problem);
    let exact = |x: &Vector3<f64>| (t + g * (x - c)) * scale;
    let norm = problem
        .model
        .reference
        .iter()
        .map(|x| exact(x).norm())
        .fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for (n, x) in problem.model.reference.iter().enumerate() {
        if scope == NodeScope::Interior && boundary[n] {
            continue;
        }
        worst = worst.max((field[n] - exact(x)).norm());
    }
    Ok(worst / norm)
}
