//! The measures of the final stresses, strains and reactions: the error against a closed-form
//! homogeneous stress, means and scatter over a box of elements, and a constraint's reaction.

use impact_solver::material::MaterialModel;
use impact_solver::problem::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;

use super::columns::Histories;
use super::field::max_abs;
use super::{Measure, TensorComponent};
use crate::curve::CurveError;
use crate::reference::analytic::{corotated_cauchy, svk_cauchy};
use impact_solver::analysis::Execution;
use impact_solver::kinematics::matrix_from_voigt;

/// Why a measure of the final stresses, strains or reactions has no value.
#[derive(Debug, thiserror::Error)]
pub enum StressError {
    /// An explicit run's reaction is read from its history, which lacks the column (the
    /// message lists those it has) or was not kept.
    #[error(transparent)]
    Column(#[from] CurveError),
    /// A reaction's history column without a record.
    #[error("`{column}` has no record")]
    Empty {
        /// The column.
        column: String,
    },
    /// No element centroid in the box of a stress measure.
    #[error("no element centroid lies in the box {min:?} - {max:?}: widen it")]
    EmptyBox {
        /// Lower corner (m).
        min: [f64; 3],
        /// Upper corner (m).
        max: [f64; 3],
    },
    /// The homogeneous stress has a closed form for the elastic laws only.
    #[error(
        "uniform_stress_error has no closed form for {material}: it compares \
         saint_venant_kirchhoff and linear_elastic bodies"
    )]
    NoClosedForm {
        /// The material's name.
        material: String,
    },
    /// No constraint of that name: the message lists the scene's.
    #[error("no constraint named `{constraint}`; the scene has {constraints:?}")]
    NoConstraint {
        /// The constraint asked for.
        constraint: String,
        /// The constraints of the scene.
        constraints: Vec<String>,
    },
}

/// Evaluates `measure` when it reads the final stresses, strains or reactions; `None` for a
/// measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, StressError> {
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
) -> Result<f64, StressError> {
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
                return Err(StressError::NoClosedForm {
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
) -> Result<f64, StressError> {
    let c = problem
        .constraints
        .iter()
        .position(|c| c.name == constraint)
        .ok_or_else(|| StressError::NoConstraint {
            constraint: constraint.to_string(),
            constraints: problem.constraints.iter().map(|c| c.name.clone()).collect(),
        })?;
    Ok(match (&run.static_solution, &run.summary) {
        (Some(s), None) => s.constraint_reaction(problem, c)[axis],
        _ => {
            let column = format!("{constraint}_reaction_{}", ["x", "y", "z"][axis]);
            *h.column(&column)?
                .last()
                .ok_or(StressError::Empty { column })?
        }
    })
}

/// One Cauchy stress component of every element whose reference centroid lies in `[min, max]`.
fn element_stress_in_box(
    problem: &Problem,
    run: &Execution,
    component: TensorComponent,
    min: &[f64; 3],
    max: &[f64; 3],
) -> Result<Vec<f64>, StressError> {
    let fields = run.element_fields(&problem.model);
    let values: Vec<f64> = problem
        .model
        .tets
        .iter()
        .enumerate()
        .filter(|(_, tet)| {
            let centroid = tet
                .iter()
                .map(|&n| problem.model.reference[n as usize])
                .sum::<Vector3<f64>>()
                / 4.0;
            (0..3).all(|a| centroid[a] >= min[a] && centroid[a] <= max[a])
        })
        .map(|(e, _)| fields.cauchy[e][component as usize])
        .collect();
    if values.is_empty() {
        return Err(StressError::EmptyBox {
            min: *min,
            max: *max,
        });
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::super::synthetic::{bar, concrete_bar, history, rest, run, POISSON, YOUNG};
    use super::super::{Measure, MeasureError, TensorAxis, TensorComponent};
    use super::StressError;
    use crate::curve::CurveError;
    use impact_solver::analysis::Execution;
    use impact_solver::problem::Problem;
    use impact_solver::Vector3;

    /// Stretch of the bar's first cell (`x < 1`); the second stretches twice as much.
    const STRETCH: f64 = 1e-3;

    /// `u_x` stretches the cell `x < 1` by `STRETCH` and the cell `x > 1` by `2 STRETCH`: each
    /// element's deformation is homogeneous, `F = diag(1 + s, 1, 1)`.
    fn two_stretches(x: &Vector3<f64>) -> Vector3<f64> {
        let ux = if x.x <= 1.0 {
            STRETCH * x.x
        } else {
            STRETCH + 2.0 * STRETCH * (x.x - 1.0)
        };
        Vector3::new(ux, 0.0, 0.0)
    }

    /// The strain of a stretch `s` along x: `E_xx = ((1 + s)^2 - 1) / 2 = s + s^2 / 2`, the
    /// same in the Green-Lagrange and the spatial measure (`F` is diagonal).
    fn strain(s: f64) -> f64 {
        s + s * s / 2.0
    }

    /// Lame's constants of the bar: `nu = 1/4` makes both `0.4 E`.
    fn lame() -> (f64, f64) {
        let (e, nu) = (YOUNG, POISSON);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    fn value(problem: &Problem, measure: Measure, run: &Execution) -> f64 {
        measure.evaluate(problem, run).unwrap()
    }

    fn error(problem: &Problem, measure: Measure, run: &Execution) -> StressError {
        match measure.evaluate(problem, run) {
            Err(MeasureError::Stress(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    fn mean(component: TensorComponent, max_x: f64) -> Measure {
        Measure::ElementStressMean {
            component,
            min: [0.0; 3],
            max: [max_x, 1.0, 1.0],
        }
    }

    /// Linear elasticity in the co-rotated frame: `sigma = lambda tr(e) I + 2 mu e`, so a
    /// stretch along x gives `sigma_xx = (lambda + 2 mu) e` and `sigma_yy = lambda e`.
    #[test]
    fn stresses_and_strains_of_two_known_stretches() {
        let problem = bar();
        let r = run(&problem, two_stretches, None);
        let (lambda, mu) = lame();
        let (left, right) = (strain(STRETCH), strain(2.0 * STRETCH));
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        let xx = value(&problem, mean(TensorComponent::Xx, 1.0), &r);
        assert!(rel(xx, (lambda + 2.0 * mu) * left) < 1e-9, "{xx}");
        let yy = value(&problem, mean(TensorComponent::Yy, 1.0), &r);
        assert!(rel(yy, lambda * left) < 1e-9, "{yy}");
        // Six elements of each cell.
        let xx = value(&problem, mean(TensorComponent::Xx, 2.0), &r);
        assert!(
            rel(xx, (lambda + 2.0 * mu) * (left + right) / 2.0) < 1e-9,
            "{xx}"
        );
        let scatter = Measure::ElementStressScatter {
            component: TensorComponent::Xx,
            min: [0.0; 3],
            max: [2.0, 1.0, 1.0],
        };
        let s = value(&problem, scatter, &r);
        assert!(
            rel(s, (right - left) / ((right + left) / 2.0)) < 1e-9,
            "{s}"
        );
        let strain_mean = Measure::ElementStrainMean {
            component: TensorComponent::Xx,
        };
        let e = value(&problem, strain_mean, &r);
        assert!(rel(e, (left + right) / 2.0) < 1e-9, "{e}");
        let top = value(&problem, Measure::MaxStressOverModulus, &r);
        assert!(
            rel(top, (lambda + 2.0 * mu) * right / YOUNG) < 1e-9,
            "{top}"
        );
    }

    /// Against the stress of the first cell's stretch, the first cell is exact and the second
    /// is off by `(lambda + 2 mu)(e_2 - e_1)` on `xx`, the largest component of the exact
    /// stress `(lambda + 2 mu) e_1`.
    #[test]
    fn the_error_against_a_closed_form_stress() {
        let problem = bar();
        let gradient = [[STRETCH, 0.0, 0.0], [0.0; 3], [0.0; 3]];
        let uniform = run(&problem, |x| Vector3::new(STRETCH * x.x, 0.0, 0.0), None);
        let measure = || Measure::UniformStressError { gradient };
        let e = value(&problem, measure(), &uniform);
        assert!(e < 1e-9, "{e}");
        let r = run(&problem, two_stretches, None);
        let (left, right) = (strain(STRETCH), strain(2.0 * STRETCH));
        let e = value(&problem, measure(), &r);
        let expected = (right - left) / left;
        assert!((e - expected).abs() < 1e-9 * expected, "{e}");
    }

    /// An explicit run's reaction is the last record of its column, over the divisor.
    #[test]
    fn a_reaction_from_the_history() {
        let problem = bar();
        let h = history(&[("end_reaction_y", &[0.0, -3.0, -8.0])]);
        let r = run(&problem, rest, Some(h));
        let reaction = Measure::Reaction {
            constraint: "end".into(),
            component: TensorAxis::Y,
            divide_by: 4.0,
        };
        assert_eq!(value(&problem, reaction, &r), -2.0);
    }

    #[test]
    fn each_error_names_the_box_the_material_or_the_constraint() {
        let problem = bar();
        let r = run(&problem, rest, None);
        let outside = Measure::ElementStressMean {
            component: TensorComponent::Xx,
            min: [5.0; 3],
            max: [6.0; 3],
        };
        let e = error(&problem, outside, &r);
        assert!(
            matches!(e, StressError::EmptyBox { min, .. } if min == [5.0; 3]),
            "{e}"
        );
        let reaction = |constraint: &str| Measure::Reaction {
            constraint: constraint.into(),
            component: TensorAxis::X,
            divide_by: 1.0,
        };
        let e = error(&problem, reaction("start"), &r);
        assert!(
            matches!(&e, StressError::NoConstraint { constraint, constraints }
                if constraint == "start" && constraints == &["end"]),
            "{e}"
        );
        let e = error(&problem, reaction("end"), &r);
        assert!(
            matches!(e, StressError::Column(CurveError::NoHistory)),
            "{e}"
        );
        let empty = run(&problem, rest, Some(history(&[("end_reaction_x", &[])])));
        let e = error(&problem, reaction("end"), &empty);
        assert!(
            matches!(&e, StressError::Empty { column } if column == "end_reaction_x"),
            "{e}"
        );
        let concrete = concrete_bar();
        let uniform = Measure::UniformStressError {
            gradient: [[0.0; 3]; 3],
        };
        let e = error(&concrete, uniform, &run(&concrete, rest, None));
        assert!(matches!(e, StressError::NoClosedForm { .. }), "{e}");
        assert!(e.to_string().contains("microplane"), "{e}");
    }
}
