//! The measures of a structure's response, most of them the beam's: its failure mode, the
//! asymmetry of its support reactions, the kinetic share of the work, stiffnesses, the bending
//! moment at a section, peak ratios and lags, and the balance of the forces on a body.

use impact_solver::problem::Problem;

use super::columns::Histories;
use super::{Measure, MeasureError};
use crate::beam::history;
use impact_solver::analysis::Execution;

/// Evaluates `measure` when it is a structural measure; `None` for a measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, MeasureError> {
    Ok(Some(match measure {
        Measure::FailureMode(spec) => crate::beam::cracks::failure_mode_judged(problem, spec, run)?
            .0
            .code(),
        Measure::ReactionAsymmetry { left, right, body } => {
            let spec = crate::beam::BeamSpec {
                body: body.clone(),
                ..Default::default()
            };
            let first = crate::beam::cracks::first_crack_time(problem, &spec, run.snapshots())?
                .ok_or(MeasureError::NoCrackWindow)?;
            let (t, l, r) = (h.time()?, h.column(left)?, h.column(right)?);
            let upto = t.partition_point(|&t| t <= first);
            history::reaction_asymmetry(&l[..upto], &r[..upto])?
        }
        Measure::KineticOverInternalWork {
            kinetic,
            internal_work,
            above_fraction,
            until_peak_of,
            after_peak_down_to,
        } => {
            let (mut k, mut w) = (h.column(kinetic)?, h.column(internal_work)?);
            if let Some(c) = until_peak_of {
                let end = history::records_through_peak(&h.column(c)?, *after_peak_down_to)
                    .map_err(|source| MeasureError::OfColumn {
                        column: c.clone(),
                        source,
                    })?;
                k.truncate(end);
                w.truncate(end);
            }
            history::kinetic_over_internal_work(&k, &w, *above_fraction)?
        }
        Measure::SecantStiffness {
            force,
            displacement,
            up_to_fraction,
        } => {
            history::secant_stiffness(&h.column(force)?, &h.column(displacement)?, *up_to_fraction)?
        }
        Measure::RisingBranchSlope {
            load,
            load_scale,
            opening,
            opening_minus,
            opening_scale,
            from,
            to,
        } => {
            let f: Vec<f64> = h.column(load)?.iter().map(|f| load_scale * f).collect();
            let mut w = h.column(opening)?;
            if let Some(minus) = opening_minus {
                for (w, m) in w.iter_mut().zip(h.column(minus)?) {
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
        } => peak_bending_moment(problem, h, *section_x, conditions, until_peak_of.as_deref())?,
        Measure::PeakRatio {
            numerator,
            denominator,
        } => history::peak_ratio(&h.column(numerator)?, &h.column(denominator)?)?,
        Measure::PeakTimeLag { column: c, after } => {
            history::peak_time_lag(&h.time()?, &h.column(c)?, &h.column(after)?)?
        }
        Measure::ForceEquilibriumError {
            body,
            contact,
            reactions,
            other_contacts,
            momentum,
        } => {
            let forces = BodyForces {
                body,
                contact,
                reactions,
                other_contacts,
                momentum,
            };
            force_equilibrium_error(problem, h, &forces)?
        }
        _ => return Ok(None),
    }))
}

/// The largest bending moment at `section_x` from the force lines of `conditions` (up to the
/// peak of `until_peak_of` where given).
fn peak_bending_moment(
    problem: &Problem,
    h: &Histories,
    section_x: f64,
    conditions: &[String],
    until_peak_of: Option<&str>,
) -> Result<f64, MeasureError> {
    let end = match until_peak_of {
        Some(c) => history::records_through_peak(&h.column(c)?, None)?,
        None => usize::MAX,
    };
    let mut forces = Vec::with_capacity(conditions.len());
    for name in conditions {
        let (c, x) = history::force_line(problem, name)?;
        let mut f = h.column(&c)?;
        f.truncate(end);
        forces.push((f, x));
    }
    Ok(history::peak_bending_moment(section_x, &forces)?)
}

/// The history columns of the forces on one body, as [`Measure::ForceEquilibriumError`] names
/// them.
struct BodyForces<'a> {
    body: &'a str,
    contact: &'a str,
    reactions: &'a [String],
    other_contacts: &'a [String],
    momentum: &'a str,
}

/// The error of the force balance (6.48) of a body along y
/// (`crate::beam::history::force_equilibrium_error`), its weight `m g_y` from its mass and the
/// scene's gravity.
fn force_equilibrium_error(
    problem: &Problem,
    h: &Histories,
    forces: &BodyForces,
) -> Result<f64, MeasureError> {
    let b = problem
        .model
        .body_index(forces.body)
        .ok_or_else(|| MeasureError::NoBody {
            body: forces.body.to_string(),
        })?;
    let mass: f64 = problem.model.bodies[b]
        .nodes
        .clone()
        .map(|n| problem.model.mass[n])
        .sum();
    let g = problem.gravity.map_or(0.0, |g| g.y);
    let mut reactions = forces
        .reactions
        .iter()
        .map(|r| h.column(r))
        .collect::<Result<Vec<_>, _>>()?;
    // A force the body exerts on another body acts on it with the opposite sign.
    for c in forces.other_contacts {
        reactions.push(h.column(c)?.into_iter().map(|f| -f).collect());
    }
    Ok(history::force_equilibrium_error(
        &h.time()?,
        &h.column(forces.contact)?,
        &reactions,
        &h.column(forces.momentum)?,
        mass * g,
    )?)
}
