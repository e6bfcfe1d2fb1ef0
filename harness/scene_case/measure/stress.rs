//! The measures of the final stresses, strains and reactions: the error against a closed-form
//! homogeneous stress, means and scatter over a box of elements, and a constraint's reaction.

use impact_solver::material::MaterialModel;
use impact_solver::problem::Problem;
use nalgebra::Matrix3;

use super::columns::Histories;
use super::field::{element_stress_in_box, max_abs};
use super::{Measure, MeasureError};
use crate::reference::analytic::{corotated_cauchy, svk_cauchy};
use impact_solver::analysis::Execution;
use impact_solver::kinematics::matrix_from_voigt;

/// Evaluates `measure` when it reads the final stresses, strains or reactions; `None` for a
/// measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, MeasureError> {
    Ok(Some(match measure {
        Measure::UniformStressError { gradient } => uniform_stress_error(problem, run, gradient)?,
        Measure::MaxStressOverModulus => {
            let fields = run.element_fields(&problem.model);
            fields
                .cauchy
                .iter()
                .enumerate()
                .map(|(e, s)| {
                    s.iter().fold(0.0f64, |a, x| a.max(x.abs()))
                        / problem.model.material_of(e).constants().youngs_modulus
                })
                .fold(0.0, f64::max)
        }
        Measure::ElementStressMean {
            component,
            min,
            max,
        } => {
            let values = element_stress_in_box(problem, run, *component, min, max)?;
            values.iter().sum::<f64>() / values.len() as f64
        }
        Measure::ElementStressScatter {
            component,
            min,
            max,
        } => {
            let values = element_stress_in_box(problem, run, *component, min, max)?;
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            (hi - lo) / mean.abs()
        }
        Measure::ElementStrainMean { component } => {
            let fields = run.element_fields(&problem.model);
            fields
                .green_lagrange
                .iter()
                .map(|s| s[*component as usize])
                .sum::<f64>()
                / fields.green_lagrange.len() as f64
        }
        Measure::Reaction {
            constraint,
            component,
            divide_by,
        } => reaction(problem, run, h, constraint, *component as usize)? / divide_by,
        _ => return Ok(None),
    }))
}

/// The largest `max|sigma - sigma_exact| / max|sigma_exact|` over the elements, with the exact
/// Cauchy stress of the homogeneous deformation `F = I + s grad u` in closed form (Saint-Venant-
/// Kirchhoff, or co-rotated linear elastic); `s` is the end time of an explicit run, whose
/// deformation grows at a constant rate, and 1 for a static one.
fn uniform_stress_error(
    problem: &Problem,
    run: &Execution,
    gradient: &[[f64; 3]; 3],
) -> Result<f64, MeasureError> {
    let explicit_time = run.summary.as_ref().map_or(1.0, |s| s.time);
    let scale = if run.summary.is_some() {
        explicit_time
    } else {
        1.0
    };
    let f = Matrix3::identity() + Matrix3::from_row_slice(&gradient.concat()) * scale;
    let fields = run.element_fields(&problem.model);
    let mut worst: f64 = 0.0;
    for (e, s) in fields.cauchy.iter().enumerate() {
        let material = problem.model.material_of(e);
        let exact = match material.model() {
            Some(MaterialModel::SaintVenantKirchhoff(c)) => svk_cauchy(&c, &f),
            Some(MaterialModel::LinearElastic(c)) => corotated_cauchy(&c, &f),
            _ => {
                return Err(MeasureError::NoClosedForm {
                    material: material.name().to_string(),
                })
            }
        };
        let diff = matrix_from_voigt(s) - exact;
        worst = worst.max(max_abs(&diff) / max_abs(&exact));
    }
    Ok(worst)
}

/// Component `axis` of the reaction of `constraint` (N): at equilibrium for a static solution,
/// the last record of its history column for an explicit run.
fn reaction(
    problem: &Problem,
    run: &Execution,
    h: &Histories,
    constraint: &str,
    axis: usize,
) -> Result<f64, MeasureError> {
    let c = problem
        .constraints
        .iter()
        .position(|c| c.name == constraint)
        .ok_or_else(|| MeasureError::NoConstraint {
            constraint: constraint.to_string(),
        })?;
    Ok(match (&run.static_solution, &run.summary) {
        (Some(s), None) => s.constraint_reaction(problem, c)[axis],
        _ => *h
            .column(&format!("{constraint}_reaction_{}", ["x", "y", "z"][axis]))?
            .last()
            .ok_or(MeasureError::Empty)?,
    })
}
