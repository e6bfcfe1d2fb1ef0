//! The measures of a structure's response, most of them the beam's: its failure mode, the
//! asymmetry of its support reactions, the kinetic share of the work, stiffnesses, the bending
//! moment at a section, peak ratios and lags, and the balance of the forces on a body.

use impact_solver::problem::Problem;

use super::columns::Histories;
use super::Measure;
use crate::beam::cracks::CrackError;
use crate::beam::history::{self, HistoryError};
use crate::curve::CurveError;
use impact_solver::analysis::Execution;

/// Why a structural measure has no value.
#[derive(Debug, thiserror::Error)]
pub enum StructureError {
    /// The run kept no history, or the history lacks a column (the message lists those it
    /// has), or a curve cannot be fitted.
    #[error(transparent)]
    Column(#[from] CurveError),
    /// A history check has no value.
    #[error(transparent)]
    History(#[from] HistoryError),
    /// A history check of a named column has no value.
    #[error("`{column}`: {source}")]
    OfColumn {
        /// The column.
        column: String,
        /// Why.
        source: HistoryError,
    },
    /// The beam's cracks cannot be read.
    #[error(transparent)]
    Crack(#[from] CrackError),
    /// No crack in the snapshots: no window for the reaction asymmetry.
    #[error(
        "no element of body `{body}` cracks in the snapshots: no window for the reaction \
         asymmetry (the run needs a snapshot_interval and a crack)"
    )]
    NoCrackWindow {
        /// The beam body.
        body: String,
    },
    /// No body of that name: the message lists the scene's bodies.
    #[error("no body named `{body}`; the scene has {bodies:?}")]
    NoBody {
        /// The body asked for.
        body: String,
        /// The bodies of the scene.
        bodies: Vec<String>,
    },
}

/// Evaluates `measure` when it is a structural measure; `None` for a measure of another family.
pub(super) fn evaluate(
    measure: &Measure,
    problem: &Problem,
    run: &Execution,
    h: &Histories,
) -> Result<Option<f64>, StructureError> {
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
                .ok_or_else(|| StructureError::NoCrackWindow { body: body.clone() })?;
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
                    .map_err(|source| StructureError::OfColumn {
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
) -> Result<f64, StructureError> {
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
) -> Result<f64, StructureError> {
    let b = problem
        .model
        .body_index(forces.body)
        .ok_or_else(|| StructureError::NoBody {
            body: forces.body.to_string(),
            bodies: problem
                .model
                .bodies
                .iter()
                .map(|b| b.name.clone())
                .collect(),
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

#[cfg(test)]
mod tests {
    use super::super::synthetic::{bar, history, rest, run, value, DENSITY, VOLUME};
    use super::super::{Measure, MeasureError};
    use super::StructureError;
    use crate::beam::cracks::CrackError;
    use crate::beam::history::HistoryError;
    use impact_solver::analysis::Execution;

    fn error(measure: Measure, run: &Execution) -> StructureError {
        match measure.evaluate(&bar(), run) {
            Err(MeasureError::Structure(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    fn s(name: &str) -> String {
        name.to_string()
    }

    /// Four records one second apart of a load, an opening, energies and the bar's forces.
    fn records() -> Execution {
        run(
            &bar(),
            rest,
            Some(history(&[
                ("time", &[0.0, 1.0, 2.0, 3.0, 4.0]),
                ("load", &[0.0, -10.0, -20.0, -30.0, -10.0]),
                ("opening", &[0.0, 1.0, 2.0, 3.0, 4.0]),
                ("left_mouth", &[0.0, 0.5, 1.0, 1.5, 2.0]),
                ("kinetic", &[0.0, 0.0, 0.01, 0.02, 0.5]),
                ("internal_work", &[0.0, 1.0, 2.0, 4.0, 5.0]),
                ("end_reaction_y", &[0.0, 5.0, -8.0, 3.0, 1.0]),
                ("tip_y", &[0.0, 1.0, 2.0, -4.0, 0.0]),
            ])),
        )
    }

    #[test]
    fn ratios_lags_and_stiffnesses_of_known_curves() {
        let r = records();
        // max |load| = 30 over max |opening| = 4.
        let ratio = Measure::PeakRatio {
            numerator: s("load"),
            denominator: s("opening"),
        };
        assert_eq!(value(ratio, &r), 7.5);
        // The opening peaks at t = 4 s, the load at t = 3 s.
        let lag = Measure::PeakTimeLag {
            column: s("opening"),
            after: s("load"),
        };
        assert_eq!(value(lag, &r), 1.0);
        // -10 N per unit opening, all the way up to the peak.
        let secant = Measure::SecantStiffness {
            force: s("load"),
            displacement: s("opening"),
            up_to_fraction: 0.9,
        };
        assert_eq!(value(secant, &r), -10.0);
        // F = -load, w = 2 (opening - left_mouth) = opening: F in [5, 30] at w = 1, 2, 3 on the
        // rising branch, slope 10 N per unit.
        let rising = Measure::RisingBranchSlope {
            load: s("load"),
            load_scale: -1.0,
            opening: s("opening"),
            opening_minus: Some(s("left_mouth")),
            opening_scale: 2.0,
            from: 5.0,
            to: 30.0,
        };
        let k = value(rising, &r);
        assert!((k - 10.0).abs() < 1e-12, "{k}");
    }

    /// `K / W` over the records where `W` exceeds 5 % of its largest value: 0.5 / 5 at the end;
    /// up to the load's peak (t = 3 s) the largest `W` is 4 and the ratios 0, 0.005, 0.005.
    #[test]
    fn kinetic_share_of_the_work_over_the_run_and_up_to_the_peak() {
        let r = records();
        let share = |until_peak_of: Option<String>| Measure::KineticOverInternalWork {
            kinetic: s("kinetic"),
            internal_work: s("internal_work"),
            above_fraction: 0.05,
            until_peak_of,
            after_peak_down_to: None,
        };
        assert_eq!(value(share(None), &r), 0.1);
        assert_eq!(value(share(Some(s("load"))), &r), 0.005);
    }

    /// The moment at a section of the reactions on one side: `M = R (x_s - x_c)`. The fixed
    /// end lies at x = 0, the tip probe at x = 2.
    #[test]
    fn bending_moment_at_a_section_from_the_reactions_of_one_side() {
        let r = records();
        let moment = |section_x, conditions: &[&str], until_peak_of: Option<&str>| {
            Measure::PeakBendingMoment {
                section_x,
                conditions: conditions.iter().map(|c| s(c)).collect(),
                until_peak_of: until_peak_of.map(s),
            }
        };
        // Largest |R_end| = 8 N, at 1 m.
        assert_eq!(value(moment(1.0, &["end"], None), &r), 8.0);
        // Largest |R_tip| = 4 N, at -0.5 m.
        assert_eq!(value(moment(1.5, &["tip"], None), &r), 2.0);
        // Up to the peak of `end_reaction_y` (t = 2 s) the tip carries 2 N at most.
        let until = moment(1.5, &["tip"], Some("end_reaction_y"));
        assert_eq!(value(until, &r), 1.0);
        let e = error(moment(1.0, &["end", "tip"], None), &r);
        assert!(
            matches!(
                e,
                StructureError::History(HistoryError::ForcesOnBothSides { .. })
            ),
            "{e}"
        );
        let e = error(moment(1.0, &["nothing"], None), &r);
        assert!(
            matches!(&e, StructureError::History(HistoryError::NoForceNamed { name }) if name == "nothing"),
            "{e}"
        );
    }

    /// The bar weighs `rho V g = 2000 * 2 * 10 = 40 kN` down, held by its end; it pushes
    /// another body with 0, 100, 100, 100 N (which pushes back) and a third with 10 N, which the
    /// end's 40 010 N makes up for. Its momentum -50, -150 over the first two seconds follows
    /// the mean push back; a last record of -150 misses the 100 N push over the second and
    /// third seconds by 50 N, half the largest contact force.
    #[test]
    fn force_balance_of_a_body_with_its_weight() {
        let momentum = |last: f64| {
            run(
                &bar(),
                rest,
                Some(history(&[
                    ("time", &[0.0, 1.0, 2.0, 3.0]),
                    ("contact", &[0.0, 100.0, 100.0, 100.0]),
                    ("other", &[10.0; 4]),
                    ("end_reaction_y", &[DENSITY * VOLUME * 10.0 + 10.0; 4]),
                    ("p", &[0.0, -50.0, -150.0, last]),
                ])),
            )
        };
        let balance = |body: &str| Measure::ForceEquilibriumError {
            body: s(body),
            contact: s("contact"),
            reactions: vec![s("end_reaction_y")],
            other_contacts: vec![s("other")],
            momentum: s("p"),
        };
        let e = value(balance("bar"), &momentum(-250.0));
        assert!(e < 1e-9, "{e}");
        let e = value(balance("bar"), &momentum(-150.0));
        assert!((e - 0.5).abs() < 1e-9, "{e}");
        let e = error(balance("beam"), &momentum(-250.0));
        assert!(
            matches!(&e, StructureError::NoBody { body, bodies } if body == "beam" && bodies == &["bar"]),
            "{e}"
        );
    }

    #[test]
    fn each_error_names_the_column_body_or_window_it_lacks() {
        let r = records();
        let share = Measure::KineticOverInternalWork {
            kinetic: s("kinetic"),
            internal_work: s("internal_work"),
            above_fraction: 0.05,
            until_peak_of: Some(s("load")),
            after_peak_down_to: Some(0.1),
        };
        let e = error(share, &r);
        assert!(
            matches!(&e, StructureError::OfColumn { column, source: HistoryError::LoadNeverFalls { .. } }
                if column == "load"),
            "{e}"
        );
        let asymmetry = |body: &str| Measure::ReactionAsymmetry {
            left: s("end_reaction_y"),
            right: s("tip_y"),
            body: s(body),
        };
        // No snapshot, so no crack: no window.
        let e = error(asymmetry("bar"), &r);
        assert!(
            matches!(&e, StructureError::NoCrackWindow { body } if body == "bar"),
            "{e}"
        );
        let e = error(asymmetry("beam"), &r);
        assert!(
            matches!(&e, StructureError::Crack(CrackError::NoBody { body }) if body == "beam"),
            "{e}"
        );
        let ratio = Measure::PeakRatio {
            numerator: s("load"),
            denominator: s("missing"),
        };
        let e = error(ratio, &r);
        assert!(e.to_string().contains("`missing`"), "{e}");
        let flat = Measure::SecantStiffness {
            force: s("tip_y"),
            displacement: s("opening"),
            up_to_fraction: 0.9,
        };
        let zero = run(
            &bar(),
            rest,
            Some(history(&[
                ("tip_y", &[0.0; 3]),
                ("opening", &[0.0, 1.0, 2.0]),
            ])),
        );
        let e = error(flat, &zero);
        assert!(
            matches!(e, StructureError::History(HistoryError::ForceZero)),
            "{e}"
        );
    }
}
