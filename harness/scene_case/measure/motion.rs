//! The measures of the final motion: the spin of a body, and the error of a displacement or
//! velocity field against an affine field (the patch tests).

use impact_solver::problem::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;

use super::field::boundary_node_flags;
use super::{FieldQuantity, Measure, NodeScope};
use impact_solver::analysis::Execution;

/// Why a measure of the final motion has no value.
#[derive(Debug, thiserror::Error)]
pub enum MotionError {
    /// No body of that name: the message lists the scene's bodies.
    #[error("no body named `{body}`; the scene has {bodies:?}")]
    NoBody {
        /// The body asked for.
        body: String,
        /// The bodies of the scene.
        bodies: Vec<String>,
    },
    /// The measure reads the final velocities, which only an explicit run keeps.
    #[error("{measure} reads the final velocities of an explicit run; this run has none")]
    NeedsVelocities {
        /// The measure, as a case file names it.
        measure: &'static str,
    },
    /// The body's inertia tensor cannot be inverted (its nodes lie on a line).
    #[error("the inertia tensor of body `{body}` is singular: no spin")]
    SingularInertia {
        /// The body.
        body: String,
    },
}

/// Evaluates `measure` when it is a measure of the final motion; `None` for a measure of another
/// family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
) -> Result<Option<f64>, MotionError> {
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
fn body_spin(problem: &Problem, run: &Execution, body: &str) -> Result<f64, MotionError> {
    let b = problem
        .model
        .body_index(body)
        .ok_or_else(|| MotionError::NoBody {
            body: body.to_string(),
            bodies: problem
                .model
                .bodies
                .iter()
                .map(|b| b.name.clone())
                .collect(),
        })?;
    let v = run.v.as_ref().ok_or(MotionError::NeedsVelocities {
        measure: "body_spin",
    })?;
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
    let omega = inertia
        .try_inverse()
        .ok_or_else(|| MotionError::SingularInertia {
            body: body.to_string(),
        })?
        * l;
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
) -> Result<f64, MotionError> {
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
        FieldQuantity::Velocity => (
            run.v.as_ref().ok_or(MotionError::NeedsVelocities {
                measure: "affine_field_error of the velocity",
            })?,
            1.0,
        ),
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

#[cfg(test)]
mod tests {
    use super::super::synthetic::{bar, explicit, rest, run, value};
    use super::super::{FieldQuantity, Measure, MeasureError, NodeScope};
    use super::MotionError;
    use impact_solver::analysis::Execution;
    use impact_solver::Vector3;

    fn error(measure: Measure, run: &Execution) -> MotionError {
        match measure.evaluate(&bar(), run) {
            Err(MeasureError::Motion(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    fn spin(body: &str, scale: f64) -> Measure {
        Measure::BodySpin {
            body: body.into(),
            scale,
        }
    }

    /// A rigid motion is a translation plus a rotation `omega x (x - c)` about any point: the
    /// body's spin is `|omega|` whatever the translation, the point and the masses.
    #[test]
    fn the_spin_of_a_rigid_rotation_is_its_angular_velocity() {
        let problem = bar();
        let omega = Vector3::new(0.0, 0.0, 2.0);
        let v = |x: &Vector3<f64>| {
            Vector3::new(1.0, -3.0, 0.5) + omega.cross(&(x - Vector3::new(0.3, 0.2, 0.1)))
        };
        let r = explicit(run(&problem, rest, None), &problem, v, 1.0, 0.0);
        // |omega| = 2 rad/s, times R / v = 0.5 s.
        let s = value(spin("bar", 0.5), &r);
        assert!((s - 1.0).abs() < 1e-12, "{s}");
    }

    /// The exact velocity `t + G (X - c)` with `t = (1, 0, 0)`, `G_xx = 0.5`, `c = 0`: largest
    /// at `x = 2`, `|exact| = 2` m/s. One node off by 0.3 m/s makes the error 0.3 / 2; the bar
    /// has no interior node, so over the interior ones the error is 0.
    #[test]
    fn the_error_of_an_affine_field_with_one_node_off() {
        let problem = bar();
        let exact = |x: &Vector3<f64>| Vector3::new(1.0 + 0.5 * x.x, 0.0, 0.0);
        let corner = Vector3::new(2.0, 1.0, 1.0);
        let off = |x: &Vector3<f64>| {
            let bump = if *x == corner { 0.3 } else { 0.0 };
            exact(x) + Vector3::new(0.0, bump, 0.0)
        };
        let field = |quantity, nodes| Measure::AffineFieldError {
            quantity,
            translation: [1.0, 0.0, 0.0],
            gradient: [[0.5, 0.0, 0.0], [0.0; 3], [0.0; 3]],
            center: [0.0; 3],
            nodes,
        };
        let r = explicit(run(&problem, rest, None), &problem, off, 2.0, 0.0);
        let e = value(field(FieldQuantity::Velocity, NodeScope::All), &r);
        assert!((e - 0.15).abs() < 1e-15, "{e}");
        assert_eq!(
            value(field(FieldQuantity::Velocity, NodeScope::Interior), &r),
            0.0
        );
        // The displacement of an explicit run grows at the exact velocity for its end time,
        // 2 s: the exact displacement is twice the field, largest 4 m, and 0.3 / 4 off.
        let moved = explicit(
            run(&problem, |x| off(x) + exact(x), None),
            &problem,
            rest,
            2.0,
            0.0,
        );
        let e = value(field(FieldQuantity::Displacement, NodeScope::All), &moved);
        assert!((e - 0.075).abs() < 1e-15, "{e}");
        // A static displacement is compared unscaled.
        let still = run(&problem, off, None);
        let e = value(field(FieldQuantity::Displacement, NodeScope::All), &still);
        assert!((e - 0.15).abs() < 1e-15, "{e}");
    }

    #[test]
    fn each_error_names_the_body_or_the_field_it_lacks() {
        let problem = bar();
        let static_run = run(&problem, rest, None);
        let e = error(spin("ball", 1.0), &static_run);
        assert!(
            matches!(&e, MotionError::NoBody { body, bodies } if body == "ball" && bodies == &["bar"]),
            "{e}"
        );
        let e = error(spin("bar", 1.0), &static_run);
        assert!(matches!(e, MotionError::NeedsVelocities { .. }), "{e}");
        let velocity = Measure::AffineFieldError {
            quantity: FieldQuantity::Velocity,
            translation: [0.0; 3],
            gradient: [[0.0; 3]; 3],
            center: [0.0; 3],
            nodes: NodeScope::All,
        };
        let e = error(velocity, &static_run);
        assert!(matches!(e, MotionError::NeedsVelocities { .. }), "{e}");
        // Every node moved onto the x axis: no inertia about it.
        let line = run(&problem, |x| Vector3::new(0.0, -x.y, -x.z), None);
        let line = explicit(line, &problem, rest, 1.0, 0.0);
        let e = error(spin("bar", 1.0), &line);
        assert!(
            matches!(&e, MotionError::SingularInertia { body } if body == "bar"),
            "{e}"
        );
    }
}
