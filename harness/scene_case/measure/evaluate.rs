//! Evaluating a per-run measure on a run's histories and final fields.

use impact_solver::material::MaterialModel;
use impact_solver::problem::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;

use super::field::{boundary_node_flags, element_stress_in_box, max_abs};
use super::{FieldQuantity, Measure, MeasureError, NodeScope};
use crate::curve::CurveError;
use crate::judge::{Measured, Reading};
use crate::reference::analytic::{corotated_cauchy, svk_cauchy};
use impact_solver::analysis::Execution;
use impact_solver::kinematics::matrix_from_voigt;

impl Measure {
    /// Evaluates a per-run measure.
    pub fn evaluate(&self, problem: &Problem, run: &Execution) -> Result<f64, MeasureError> {
        self.evaluate_read(problem, run).map(|m| m.value)
    }

    /// Evaluates a per-run measure, with its own verdict where it gives one (the crack tips).
    pub fn evaluate_read(
        &self,
        problem: &Problem,
        run: &Execution,
    ) -> Result<Measured, MeasureError> {
        let column = |name: &str| -> Result<Vec<f64>, CurveError> {
            let h = run.history.as_ref().ok_or(CurveError::NoHistory)?;
            h.column(name).ok_or_else(|| CurveError::NoColumn {
                name: name.into(),
                columns: h.columns().to_vec(),
            })
        };
        let time = || column("time");
        let explicit_time = run.summary.as_ref().map_or(1.0, |s| s.time);
        Ok(Measured::from(match self {
            Measure::HistoryMax { column: c } => {
                column(c)?.into_iter().fold(f64::NEG_INFINITY, f64::max)
            }
            Measure::HistoryPeakMagnitude { column: c } => {
                column(c)?.into_iter().fold(0.0, |a: f64, x| a.max(x.abs()))
            }
            Measure::HistoryMin { column: c } => {
                column(c)?.into_iter().fold(f64::INFINITY, f64::min)
            }
            Measure::HistoryFinal { column: c, scale } => {
                column(c)?.last().ok_or(MeasureError::Empty)? * scale
            }
            Measure::PeakTime { column: c } => {
                let (t, y) = (time()?, column(c)?);
                let i = (0..y.len())
                    .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                    .ok_or(MeasureError::Empty)?;
                t[i]
            }
            Measure::ValueAtPeak {
                column: c,
                of,
                scale,
            } => value_at_peak(&column(c)?, &column(of)?)? * scale,
            Measure::PeakOverNeighbours { column: c } => peak_over_neighbours(&column(c)?)?,
            Measure::DurationAbove {
                column: c,
                threshold,
            } => {
                let (t, y) = (time()?, column(c)?);
                (1..y.len())
                    .filter(|&i| y[i] > *threshold)
                    .map(|i| t[i] - t[i - 1])
                    .sum()
            }
            Measure::PlateauMean {
                column: c,
                from,
                to,
            } => {
                let (t, y) = (time()?, column(c)?);
                let window: Vec<f64> = (0..y.len())
                    .filter(|&i| t[i] >= *from && t[i] <= *to)
                    .map(|i| y[i])
                    .collect();
                if window.is_empty() {
                    return Err(MeasureError::NoRecordInWindow {
                        column: c.clone(),
                        from: *from,
                        to: *to,
                    });
                }
                window.iter().sum::<f64>() / window.len() as f64
            }
            Measure::ArrivalTime { column: c, level } => crossing(&time()?, &column(c)?, *level)?,
            Measure::FrontSpeed {
                from,
                to,
                distance,
                level,
            } => {
                let t = time()?;
                distance
                    / (crossing(&t, &column(to)?, *level)? - crossing(&t, &column(from)?, *level)?)
            }
            Measure::EnergyBalanceError => {
                run.summary
                    .as_ref()
                    .ok_or(MeasureError::NeedsExplicitRun)?
                    .max_relative_energy_error
            }
            Measure::KineticEnergyDrift => {
                let k = column("kinetic")?;
                let k0 = k[0];
                if !(k0 > 0.0) {
                    return Err(MeasureError::KineticZero);
                }
                k.iter().map(|x| (x - k0).abs() / k0).fold(0.0, f64::max)
            }
            Measure::MaxChange { column: c, scale } => {
                let y = column(c)?;
                y.iter().map(|x| (x - y[0]).abs()).fold(0.0, f64::max) / scale
            }
            Measure::RelativeDrift { columns } => {
                let c = [
                    column(&columns[0])?,
                    column(&columns[1])?,
                    column(&columns[2])?,
                ];
                let at = |i: usize| Vector3::new(c[0][i], c[1][i], c[2][i]);
                let initial = at(0).norm();
                if initial == 0.0 {
                    return Err(MeasureError::VectorZero);
                }
                (0..c[0].len())
                    .map(|i| (at(i) - at(0)).norm())
                    .fold(0.0, f64::max)
                    / initial
            }
            Measure::FinalEnergyRatio => {
                let (k, w) = (column("kinetic")?, column("stored_energy")?);
                (k[k.len() - 1] + w[w.len() - 1]) / k[0]
            }
            Measure::BodySpin { body, scale } => {
                let b = problem
                    .model
                    .body_index(body)
                    .ok_or_else(|| MeasureError::NoBody { body: body.clone() })?;
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
                    inertia +=
                        (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass[n];
                }
                let omega = inertia.try_inverse().ok_or(MeasureError::SingularInertia)? * l;
                omega.norm() * scale
            }
            Measure::AffineFieldError {
                quantity,
                translation,
                gradient,
                center,
                nodes,
            } => {
                let (field, scale) = match quantity {
                    FieldQuantity::Displacement => (
                        &run.u,
                        if run.summary.is_some() {
                            explicit_time
                        } else {
                            1.0
                        },
                    ),
                    FieldQuantity::Velocity => {
                        (run.v.as_ref().ok_or(MeasureError::NeedsExplicitRun)?, 1.0)
                    }
                };
                let g = Matrix3::from_row_slice(&gradient.concat());
                let (t, c) = (Vector3::from(*translation), Vector3::from(*center));
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
                    if *nodes == NodeScope::Interior && boundary[n] {
                        continue;
                    }
                    worst = worst.max((field[n] - exact(x)).norm());
                }
                worst / norm
            }
            Measure::UniformStressError { gradient } => {
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
                worst
            }
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
            } => {
                let c = problem
                    .constraints
                    .iter()
                    .position(|c| &c.name == constraint)
                    .ok_or_else(|| MeasureError::NoConstraint {
                        constraint: constraint.clone(),
                    })?;
                let axis = *component as usize;
                let value = match (&run.static_solution, &run.summary) {
                    (Some(s), None) => s.constraint_reaction(problem, c)[axis],
                    _ => *column(&format!("{constraint}_reaction_{}", ["x", "y", "z"][axis]))?
                        .last()
                        .ok_or(MeasureError::Empty)?,
                };
                value / divide_by
            }
            Measure::ZeroCrossingFrequency { column: c } => {
                let (t, y) = (time()?, column(c)?);
                let mean = y.iter().sum::<f64>() / y.len() as f64;
                let ups: Vec<f64> = (1..y.len())
                    .filter(|&i| y[i - 1] < mean && y[i] >= mean)
                    .map(|i| t[i - 1] + (mean - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]))
                    .collect();
                if ups.len() < 2 {
                    return Err(MeasureError::FewCrossings { column: c.clone() });
                }
                (ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0])
            }
            Measure::ContactReplay {
                solver,
                quantity,
                tolerance,
                only_converged,
            } => crate::replay::evaluate(
                &run.contact_problems,
                solver,
                *quantity,
                *tolerance,
                *only_converged,
            )?,
            Measure::FailureMode(spec) => {
                crate::beam::cracks::failure_mode_judged(problem, spec, run)?
                    .0
                    .code()
            }
            Measure::CrackTip(m) => {
                let report = crate::beam::crack_tip_report(problem, run.snapshots(), &m.beam)?;
                let (value, reading) = m.read(&report);
                return Ok(Measured {
                    value,
                    reading: reading.map(|r| Reading {
                        pass: r.status == crate::beam::cracks::TipStatus::Pass,
                        text: r.describe(report.rayleigh_speed),
                    }),
                });
            }
            Measure::ReactionAsymmetry { left, right, body } => {
                let spec = crate::beam::BeamSpec {
                    body: body.clone(),
                    ..Default::default()
                };
                let first = crate::beam::cracks::first_crack_time(problem, &spec, run.snapshots())?
                    .ok_or(MeasureError::NoCrackWindow)?;
                let (t, l, r) = (time()?, column(left)?, column(right)?);
                let upto = t.partition_point(|&t| t <= first);
                crate::beam::history::reaction_asymmetry(&l[..upto], &r[..upto])?
            }
            Measure::KineticOverInternalWork {
                kinetic,
                internal_work,
                above_fraction,
                until_peak_of,
                after_peak_down_to,
            } => {
                let (mut k, mut w) = (column(kinetic)?, column(internal_work)?);
                if let Some(c) = until_peak_of {
                    let end = crate::beam::history::records_through_peak(
                        &column(c)?,
                        *after_peak_down_to,
                    )
                    .map_err(|source| MeasureError::OfColumn {
                        column: c.clone(),
                        source,
                    })?;
                    k.truncate(end);
                    w.truncate(end);
                }
                crate::beam::history::kinetic_over_internal_work(&k, &w, *above_fraction)?
            }
            Measure::SecantStiffness {
                force,
                displacement,
                up_to_fraction,
            } => crate::beam::history::secant_stiffness(
                &column(force)?,
                &column(displacement)?,
                *up_to_fraction,
            )?,
            Measure::RisingBranchSlope {
                load,
                load_scale,
                opening,
                opening_minus,
                opening_scale,
                from,
                to,
            } => {
                let f: Vec<f64> = column(load)?.iter().map(|f| load_scale * f).collect();
                let mut w = column(opening)?;
                if let Some(minus) = opening_minus {
                    for (w, m) in w.iter_mut().zip(column(minus)?) {
                        *w -= m;
                    }
                }
                w.iter_mut().for_each(|w| *w *= opening_scale);
                crate::curve::rising_branch_slope(&f, &w, *from, *to)?.0
            }
            Measure::PeakBendingMoment {
                section_x,
                conditions,
                until_peak_of,
            } => {
                let end = match until_peak_of {
                    Some(c) => crate::beam::history::records_through_peak(&column(c)?, None)?,
                    None => usize::MAX,
                };
                let mut forces = Vec::with_capacity(conditions.len());
                for name in conditions {
                    let (c, x) = crate::beam::history::force_line(problem, name)?;
                    let mut f = column(&c)?;
                    f.truncate(end);
                    forces.push((f, x));
                }
                crate::beam::history::peak_bending_moment(*section_x, &forces)?
            }
            Measure::PeakRatio {
                numerator,
                denominator,
            } => crate::beam::history::peak_ratio(&column(numerator)?, &column(denominator)?)?,
            Measure::PeakTimeLag { column: c, after } => {
                crate::beam::history::peak_time_lag(&time()?, &column(c)?, &column(after)?)?
            }
            Measure::ForceEquilibriumError {
                body,
                contact,
                reactions,
                other_contacts,
                momentum,
            } => {
                let b = problem
                    .model
                    .body_index(body)
                    .ok_or_else(|| MeasureError::NoBody { body: body.clone() })?;
                let mass: f64 = problem.model.bodies[b]
                    .nodes
                    .clone()
                    .map(|n| problem.model.mass[n])
                    .sum();
                let g = problem.gravity.map_or(0.0, |g| g.y);
                let mut reactions = reactions
                    .iter()
                    .map(|r| column(r))
                    .collect::<Result<Vec<_>, _>>()?;
                // A force the body exerts on another body acts on it with the opposite sign.
                for c in other_contacts {
                    reactions.push(column(c)?.into_iter().map(|f| -f).collect());
                }
                crate::beam::history::force_equilibrium_error(
                    &time()?,
                    &column(contact)?,
                    &reactions,
                    &column(momentum)?,
                    mass * g,
                )?
            }
            Measure::CrackBand(m) => m.evaluate(&problem.model, &|c| column(c))?,
            Measure::CrackBandPoint(m) => m.evaluate(&problem.model)?,
            sweep => {
                return Err(MeasureError::SweepMeasure {
                    measure: format!("{sweep:?}"),
                })
            }
        }))
    }
}

/// First time `signal` reaches `level` (upward or downward, whichever way it starts from).
/// `|y_p| / mean(|y_i|, |i - p| <= 2)` at the row `p` of the largest `|y|` (the first of equal
/// ones): how far the peak stands above the rows around it
/// ([`Measure::PeakOverNeighbours`]).
fn peak_over_neighbours(y: &[f64]) -> Result<f64, MeasureError> {
    let p = (0..y.len())
        .reduce(|a, b| if y[b].abs() > y[a].abs() { b } else { a })
        .ok_or(MeasureError::Empty)?;
    let around = &y[p.saturating_sub(2)..(p + 3).min(y.len())];
    let mean = around.iter().map(|v| v.abs()).sum::<f64>() / around.len() as f64;
    if mean == 0.0 {
        return Err(MeasureError::ColumnZero);
    }
    Ok(y[p].abs() / mean)
}

fn crossing(time: &[f64], signal: &[f64], level: f64) -> Result<f64, MeasureError> {
    let start = signal.first().copied().unwrap_or(0.0);
    let up = level >= start;
    for i in 1..signal.len() {
        let reached = if up {
            signal[i] >= level
        } else {
            signal[i] <= level
        };
        if reached {
            let s = (level - signal[i - 1]) / (signal[i] - signal[i - 1]);
            return Ok(time[i - 1] + s * (time[i] - time[i - 1]));
        }
    }
    Err(MeasureError::NeverReaches { level })
}

/// `y` in the row of the largest `|peak|` (the first of equal ones; [`Measure::ValueAtPeak`]).
fn value_at_peak(y: &[f64], peak: &[f64]) -> Result<f64, MeasureError> {
    let p = (0..peak.len().min(y.len()))
        .reduce(|a, b| if peak[b].abs() > peak[a].abs() { b } else { a })
        .ok_or(MeasureError::Empty)?;
    Ok(y[p])
}

#[cfg(test)]
mod tests {
    use super::{peak_over_neighbours, value_at_peak};

    #[test]
    fn the_value_at_a_peak_is_read_in_the_peaks_row() {
        // A load that peaks (in magnitude, negative) at the third row: the opening there.
        let load = [0.0, -2.0, -5.0, -3.0, 5.0];
        let opening = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(value_at_peak(&opening, &load).unwrap(), 2.0);
        assert!(value_at_peak(&[], &[]).is_err());
    }

    #[test]
    fn a_resolved_peak_stands_little_above_its_neighbours_and_a_spike_stands_far() {
        // A half sine over 40 rows: its five rows around the peak are within 1 - cos(2 pi / 40)
        // of it, so the ratio is below 1.01.
        let pulse: Vec<f64> = (0..=40)
            .map(|i| -(std::f64::consts::PI * f64::from(i) / 40.0).sin())
            .collect();
        let ratio = peak_over_neighbours(&pulse).unwrap();
        assert!((1.0..1.01).contains(&ratio), "{ratio}");
        // One row at three times a plateau: 3 / ((3 + 4) / 5).
        let mut spike = vec![1.0; 11];
        spike[5] = 3.0;
        let ratio = peak_over_neighbours(&spike).unwrap();
        assert!((ratio - 15.0 / 7.0).abs() < 1e-12, "{ratio}");
        // At the end of the history the window is cut: 2 / ((1 + 1 + 2) / 3).
        let ratio = peak_over_neighbours(&[0.0, 1.0, 1.0, 2.0]).unwrap();
        assert!((ratio - 1.5).abs() < 1e-12, "{ratio}");
        assert!(peak_over_neighbours(&[0.0; 4]).is_err());
    }
}
