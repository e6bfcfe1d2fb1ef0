//! The experiments of `material_point` cases: each drives the solver's virtual experiments
//! (`impact_solver::material::microplane::experiments`), measures its quantities in report units
//! and draws its plots with the targets of the case's metrics.

mod compression;
mod crack_band;
mod cyclic;
mod hydrostatic;
mod isotropy;
mod rate_effect;
mod tension;
mod tension_compression;

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::driver::PathPoint;
use impact_solver::material::microplane::experiments::{Curve, QUASI_STATIC_RATE};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{Experiment, MaterialPointSpec, Outcome, Quantity, Selector, Targets, Value};
use crate::report::format::num;
use compression::{biaxial, compression};
use crack_band::crack_band;
use cyclic::cyclic;
use hydrostatic::hydrostatic;
use isotropy::isotropy;
use rate_effect::rate_effect;
use tension::{tension_plots, tension_run};
use tension_compression::tension_compression;

/// Strain magnitude of the isotropy check: far inside the elastic range, so that the nonlinear
/// terms (of relative size `(eps / e1)^m`) stay below 1e-15 for exponents `m` of 1 or more.
pub const ISOTROPY_STRAIN: f64 = 1e-20;
/// Default sample count of the isotropy check.
pub const ISOTROPY_SAMPLES: usize = 200;
/// Defaults of the compressive paths: to 6e-3 in increments of 1e-5.
pub const COMPRESSION_END: f64 = 6e-3;
/// Default number of increments of the compressive paths.
pub const COMPRESSION_STEPS: usize = 600;
/// Defaults of the hydrostatic path: all normal strains to -0.05 and back.
pub const HYDROSTATIC_END: f64 = 0.05;
/// Default number of increments of the hydrostatic path (each way).
pub const HYDROSTATIC_STEPS: usize = 500;
/// The unit check of the rate law: uniaxial strain to 4e-4 in 200 increments (past the peak).
pub const UNIT_CHECK_END: f64 = 4e-4;
/// Number of increments of the rate law's unit check.
pub const UNIT_CHECK_STEPS: usize = 200;
/// Strain of the initial-stiffness probe: the laws' nonlinearity there, about `eps / e1`, is
/// 1e-7 of the stress or less.
pub const STIFFNESS_PROBE: f64 = 1e-12;
/// First unloading increment of the unloading-stiffness check.
pub const UNLOADING_PROBE: f64 = 1e-7;

const MPA: f64 = 1e6;
const PER_MILLE: f64 = 1e3;

/// Runs the experiment of `mp` on `params`.
pub fn run(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    targets: &Targets,
) -> Result<Outcome, MaterialPointError> {
    let mut out = Outcome::default();
    let h = match mp.element_size {
        Some(h) => {
            out.setup.push(format!(
                "element size h = {} mm (the case's element_size)",
                num(h * 1e3)
            ));
            h
        }
        None => {
            if !matches!(mp.experiment, Experiment::Isotropy | Experiment::CrackBand) {
                out.setup.push(format!(
                    "element size h = {} mm (the parameter file's h_ref)",
                    num(params.h_ref * 1e3)
                ));
            }
            params.h_ref
        }
    };
    match mp.experiment {
        Experiment::Isotropy => isotropy(mp, params, targets, &mut out)?,
        Experiment::UniaxialTension => {
            let model = MicroplaneConcrete::new(*params)?;
            let rate = rate_of(mp, &mut out);
            let (curve, values) = tension_run(
                &model,
                h,
                rate,
                mp.fracture_path_for(params),
                Selector::default(),
                &mut out,
            )?;
            out.values.extend(values);
            out.plots.extend(tension_plots(
                &curve,
                h,
                params,
                targets,
                &Selector::default(),
            ));
        }
        Experiment::CrackBand => crack_band(mp, params, targets, &mut out)?,
        Experiment::UniaxialCompression => compression(mp, params, h, targets, &mut out)?,
        Experiment::EqualBiaxial => biaxial(mp, params, h, targets, &mut out)?,
        Experiment::Hydrostatic => hydrostatic(mp, params, h, &mut out)?,
        Experiment::Cyclic => cyclic(mp, params, h, targets, &mut out)?,
        Experiment::RateEffect => rate_effect(mp, params, h, targets, &mut out)?,
        Experiment::TensionCompression => tension_compression(mp, params, h, targets, &mut out)?,
    }
    Ok(out)
}

fn rate_of(mp: &MaterialPointSpec, out: &mut Outcome) -> f64 {
    match mp.rate {
        Some(r) => {
            out.setup.push(format!("strain rate {r:e} /s"));
            r
        }
        None => {
            out.setup.push(format!(
                "strain rate {QUASI_STATIC_RATE:e} /s (quasi-static)"
            ));
            QUASI_STATIC_RATE
        }
    }
}

fn value(quantity: Quantity, at: &Selector, value: f64) -> Value {
    Value {
        quantity,
        at: at.clone(),
        value,
    }
}

/// Largest rise of `stress` above its running minimum after the peak, over the peak.
pub fn post_peak_rise(stress: &[f64]) -> f64 {
    let Some((peak_index, peak)) = stress
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return f64::NAN;
    };
    let mut low = peak;
    let mut rise: f64 = 0.0;
    for &s in &stress[peak_index..] {
        low = low.min(s);
        rise = rise.max(s - low);
    }
    rise / peak
}

/// The peak stress and strain (magnitudes, Pa) if the curve passed its peak, else NaN with a
/// note.
fn established_peak(curve: &Curve, what: &str, out: &mut Outcome) -> (f64, f64) {
    let p = curve.peak();
    if curve.peak_passed() {
        (p.stress[0].abs(), p.strain[0].abs())
    } else {
        out.notes.push(format!(
            "{what}: the stress still rose where the path {} (largest |sigma_11| {} MPa at \
             strain {:.3e}): the peak was not reached, so it is not measured",
            if curve.error.is_some() {
                "stopped"
            } else {
                "ended"
            },
            num(p.stress[0].abs() / MPA),
            p.strain[0].abs()
        ));
        (f64::NAN, f64::NAN)
    }
}

fn note_stop(curve: &Curve, what: &str, out: &mut Outcome) {
    if let Some(e) = &curve.error {
        out.notes.push(format!(
            "{what}: the path stopped early at axial strain {:.3e}: {e}",
            curve.points.last().map_or(0.0, |p| p.strain[0])
        ));
    }
}

/// Stress-strain points in report units.
fn axial_points(curve: &Curve, sign: f64) -> Vec<(f64, f64)> {
    curve
        .points
        .iter()
        .map(|p| (sign * p.strain[0] * PER_MILLE, sign * p.stress[0] / MPA))
        .collect()
}

/// The peak window of the targets at `at` (strain in 1e-3, stress in MPa), when both are set.
fn peak_box(targets: &Targets, at: &Selector) -> Option<([f64; 2], [f64; 2])> {
    let s = targets.band(Quantity::PeakStress, at)?;
    let e = targets.band(Quantity::PeakStrain, at)?;
    Some(([e[0] * PER_MILLE, e[1] * PER_MILLE], s))
}

fn compression_paths(mp: &MaterialPointSpec, out: &mut Outcome) -> (f64, usize) {
    let end = mp.end.unwrap_or(COMPRESSION_END);
    let steps = mp.steps.unwrap_or(COMPRESSION_STEPS);
    out.setup.push(format!(
        "compressive path to an axial strain of {end:e} in {steps} increments"
    ));
    (end, steps)
}

/// Work `int sigma : d eps` between consecutive points (trapezoidal, shears twice) and the sum of
/// its absolute increments.
fn work(points: &[PathPoint]) -> (f64, f64) {
    points.windows(2).fold((0.0, 0.0), |(w, a), pair| {
        let (p, q) = (&pair[0], &pair[1]);
        let dw: f64 = (0..6)
            .map(|i| {
                let f = if i < 3 { 1.0 } else { 2.0 };
                f * 0.5 * (p.stress[i] + q.stress[i]) * (q.strain[i] - p.strain[i])
            })
            .sum();
        (w + dw, a + dw.abs())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn post_peak_rise_is_zero_for_monotone_softening_and_finds_a_bump() {
        assert_eq!(post_peak_rise(&[0.0, 1.0, 2.0, 1.5, 1.0, 0.5]), 0.0);
        let r = post_peak_rise(&[0.0, 2.0, 1.0, 1.2, 0.5]);
        assert!((r - 0.1).abs() < 1e-15, "{r}");
    }

    fn point(e: f64, s: f64) -> PathPoint {
        PathPoint {
            time: 0.0,
            strain: [e, 0.0, 0.0, 0.0, 0.0, 0.0],
            stress: [s, 0.0, 0.0, 0.0, 0.0, 0.0],
            rate_factor: 1.0,
        }
    }

    #[test]
    fn work_of_an_elastic_closed_path_vanishes() {
        let path = [
            point(0.0, 0.0),
            point(1.0, 2.0),
            point(-1.0, -2.0),
            point(0.0, 0.0),
        ];
        assert_eq!(work(&path).0, 0.0);
        // A loop that returns on a lower branch dissipates.
        let lossy = [
            point(0.0, 0.0),
            point(1.0, 2.0),
            point(0.5, 0.0),
            point(0.0, 0.0),
        ];
        assert!(work(&lossy).0 > 0.0);
    }

    #[test]
    fn a_peak_counts_only_once_the_stress_has_fallen() {
        let curve = |s: &[f64]| Curve {
            points: s
                .iter()
                .enumerate()
                .map(|(i, &s)| point(i as f64, s))
                .collect(),
            error: None,
        };
        assert!(curve(&[0.0, 2.0, 1.0]).peak_passed());
        assert!(!curve(&[0.0, 1.0, 2.0]).peak_passed());
        // A plateau within 1e-3 of the top is not a passed peak.
        assert!(!curve(&[0.0, 2.0, 1.9995]).peak_passed());
        assert!(curve(&[0.0, -2.0, -1.0]).peak_passed());
    }
}
