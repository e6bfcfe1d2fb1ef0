//! The rate-effect experiment: the unit check of the rate law and the peaks over strain rates
//! against the fib MC2010 dynamic increase factors.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::experiments::{
    rate_scaling, uniaxial_compression, uniaxial_tension, QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{
    axial_points, compression_paths, established_peak, note_stop, value, MPA, PER_MILLE,
    STIFFNESS_PROBE, UNIT_CHECK_END, UNIT_CHECK_STEPS,
};
use crate::material_point::plots::{sampled, series, STRAIN_AXIS};
use crate::material_point::{
    close, MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, ReferenceCurve,
    Selector, Targets,
};
use crate::reference::concrete::{
    cebfip1990_dynamic_increase_factor, mc2010_dif_ratio, microplane_rate_factor,
};
use crate::report::format::num;

/// `sigma_11 / eps_11` for the elastic uniaxial-stress strain `[eps, -nu eps, -nu eps]` with
/// `eps` = [`STIFFNESS_PROBE`] reached at axial strain rate `rate` (all strains prescribed, so no
/// Newton tolerance enters): Young's modulus of the model at that rate.
fn initial_stiffness(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    nu: f64,
) -> Result<f64, MaterialPointError> {
    let mut point = MaterialPoint::new(model, h)?;
    let e = STIFFNESS_PROBE;
    let p = point.strain_step([e, -nu * e, -nu * e, 0.0, 0.0, 0.0], e / rate);
    Ok(p.stress[0] / e)
}

/// Rate effect: the unit check of the rate law, and tensile and compressive peaks over rates
/// against the fib MC2010 dynamic increase factors.
pub(super) fn rate_effect(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let relative_to = mp.relative_to.ok_or_else(|| MaterialPointError::Needs {
        experiment: "rate_effect".into(),
        option: "relative_to".into(),
    })?;
    let (end, steps) = compression_paths(mp, out);
    match params.rate_effect {
        Some(r) => out.setup.push(format!(
            "rate law F = 1 + c2 asinh(gamma_dot / c1), c1 = {:e} /s, c2 = {} (parameter file)",
            r.c1,
            num(r.c2)
        )),
        None => out
            .setup
            .push("the parameter file switches the rate effect off (F = 1)".into()),
    }
    let law = |gamma: f64| match params.rate_effect {
        Some(r) => microplane_rate_factor(gamma, r.c1, r.c2),
        None => 1.0,
    };
    // (a) The unit check on uniaxial strain: gamma_dot = rate / sqrt 2.
    let mut unit_rows = Vec::new();
    for &rate in &mp.unit_check_rates {
        let (solver_ratio, peak_ratio, misfit) =
            rate_scaling(&model, h, rate, UNIT_CHECK_END, UNIT_CHECK_STEPS)?;
        let g = |r: f64| r / std::f64::consts::SQRT_2;
        let ratio = law(g(rate)) / law(g(QUASI_STATIC_RATE));
        let error = (peak_ratio / ratio - 1.0).abs();
        let at = Selector {
            rate: Some(rate),
            ..Selector::default()
        };
        out.values.extend([
            value(Quantity::RateScalingError, &at, error),
            value(Quantity::RateScalingMisfit, &at, misfit),
        ]);
        unit_rows.push(vec![
            format!("{rate:e}"),
            format!("{ratio:.9}"),
            format!("{solver_ratio:.9}"),
            format!("{peak_ratio:.9}"),
            format!("{error:.2e}"),
            format!("{misfit:.2e}"),
        ]);
    }
    out.tables.push(RecordTable {
        title: "Unit check of the rate law (uniaxial strain)".into(),
        head: [
            "rate [/s]",
            "F(rate)/F(static), harness",
            "the same, solver",
            "peak ratio",
            "|peak ratio / F ratio - 1|",
            "largest misfit along the path",
        ]
        .map(String::from)
        .to_vec(),
        rows: unit_rows,
        note: format!(
            "Uniaxial strain at the rate against the quasi-static path ({QUASI_STATIC_RATE:e} /s) \
             on a strain grid scaled by the factor ratio: the stresses must scale by the same \
             ratio. F is computed here from the parameter file's c1, c2 with gamma_dot = \
             rate / sqrt 2."
        ),
    });
    // (b) Peaks over rates.
    let mut tension = Vec::new();
    let mut compression = Vec::new();
    let mut compression_passed = Vec::new();
    let mut tension_curves = Vec::new();
    for &rate in &mp.rates {
        let (curve, r) = uniaxial_tension(&model, h, rate)?;
        let what = format!("tension at {rate:e} /s");
        note_stop(&curve, &what, out);
        let (peak, _) = established_peak(&curve, &what, out);
        let stiffness = initial_stiffness(&model, h, rate, params.poisson_ratio)?;
        tension.push((rate, peak, stiffness, r.initial_slope));
        tension_curves.push((rate, curve));
        let (c, _) = uniaxial_compression(&model, h, rate, end, steps)?;
        note_stop(&c, &format!("compression at {rate:e} /s"), out);
        // Compression is reported, not judged: a path that did not pass its peak still shows its
        // largest stress, marked as a lower bound.
        let passed = c.peak_passed();
        if !passed {
            out.notes.push(format!(
                "compression at {rate:e} /s: the stress still rose where the path ended or \
                 stopped; its largest stress is only a lower bound of the peak"
            ));
        }
        compression.push((rate, -c.peak().stress[0]));
        compression_passed.push(passed);
    }
    let base = |list: &[(f64, f64)]| {
        list.iter()
            .find(|(r, _)| close(*r, relative_to))
            .map_or(f64::NAN, |x| x.1)
    };
    let t_pairs: Vec<(f64, f64)> = tension.iter().map(|t| (t.0, t.1)).collect();
    let (t0, c0) = (base(&t_pairs), base(&compression));
    let cebfip = mp.reference_curves.iter().find_map(|c| match c {
        ReferenceCurve::CebFip1990Dif { f_cm } => Some(*f_cm),
        _ => None,
    });
    let mut rows = Vec::new();
    let base_passed = mp
        .rates
        .iter()
        .zip(&compression_passed)
        .find(|(r, _)| close(**r, relative_to))
        .is_some_and(|(_, p)| *p);
    for ((&(rate, peak, stiffness, _), &(_, cpeak)), &passed) in
        tension.iter().zip(&compression).zip(&compression_passed)
    {
        let at = Selector {
            rate: Some(rate),
            ..Selector::default()
        };
        let (tr, cr) = (peak / t0, cpeak / c0);
        out.values.extend([
            value(Quantity::InitialSlope, &at, stiffness / MPA),
            value(Quantity::TensionPeakStress, &at, peak / MPA),
            value(Quantity::TensionPeakRatio, &at, tr),
            value(Quantity::CompressionPeakStress, &at, cpeak / MPA),
            value(Quantity::CompressionPeakRatio, &at, cr),
        ]);
        let (mt, mc) = (
            mc2010_dif_ratio(rate, relative_to, true),
            mc2010_dif_ratio(rate, relative_to, false),
        );
        let judged = |q: Quantity| {
            if targets.band(q, &at).is_some() {
                " (judged)"
            } else {
                ""
            }
        };
        rows.push(vec![
            format!("{rate:e}"),
            num(peak / MPA),
            format!("{tr:.4}"),
            format!("{mt:.4}"),
            format!(
                "{:+.2} %{}",
                100.0 * (tr / mt - 1.0),
                judged(Quantity::TensionPeakRatio)
            ),
            cebfip.map_or("—".into(), |f| {
                format!(
                    "{:.4}",
                    cebfip1990_dynamic_increase_factor(rate, true, f)
                        / cebfip1990_dynamic_increase_factor(relative_to, true, f)
                )
            }),
            if passed {
                num(cpeak / MPA)
            } else {
                format!(">= {} (peak not passed)", num(cpeak / MPA))
            },
            if passed && base_passed {
                format!("{cr:.4}")
            } else {
                format!("{cr:.4} (from lower bounds)")
            },
            format!("{mc:.4}"),
            format!(
                "{:+.2} %{}",
                100.0 * (cr / mc - 1.0),
                judged(Quantity::CompressionPeakRatio)
            ),
        ]);
    }
    let spread_of = |slopes: Vec<f64>| {
        let mean = slopes.iter().sum::<f64>() / slopes.len() as f64;
        (slopes.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - slopes.iter().copied().fold(f64::INFINITY, f64::min))
            / mean
    };
    let spread = spread_of(tension.iter().map(|t| t.2).collect());
    let first_increment_spread = spread_of(tension.iter().map(|t| t.3).collect());
    out.values.push(value(
        Quantity::InitialSlopeSpread,
        &Selector::default(),
        spread,
    ));
    out.tables.push(RecordTable {
        title: format!("Peaks over strain rates, ratios to the peak at {relative_to:e} /s"),
        head: [
            "rate [/s]",
            "tension peak [MPa]",
            "tension ratio",
            "MC2010 tension",
            "deviation",
            "CEB-FIP 1990 tension",
            "compression peak [MPa]",
            "compression ratio",
            "MC2010 compression",
            "deviation",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        note: format!(
            "Homogeneous material point: no inertia, so the steep code branch above 10 /s \
             (tension) or 30 /s (compression) is not expected here; it must come from the \
             structure's inertia. Initial stiffness (elastic uniaxial stress at a strain of \
             {STIFFNESS_PROBE:e}) over all rates: (max - min) / mean = {spread:.2e}; the slope of \
             the tension path's first increment (1e-8, where the laws are already nonlinear by \
             about 1e-8 / e1) varies by {first_increment_spread:.2e}."
        ),
    });
    // Plots: peak ratios against MC2010 in tension and compression, and tension curves at a few
    // rates.
    let (lo, hi) = mp
        .rates
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| {
            (a.min(r), b.max(r))
        });
    let sides = [
        (
            "tension",
            true,
            t_pairs
                .iter()
                .map(|&(r, p)| (r, p / t0))
                .collect::<Vec<_>>(),
        ),
        (
            "compression",
            false,
            compression.iter().map(|&(r, p)| (r, p / c0)).collect(),
        ),
    ];
    for (what, tension_side, model_points) in sides {
        let mut plot = MaterialPlot::new(
            format!("Rate effect in {what}: peak / peak at {relative_to:e} /s"),
            "strain rate [/s]",
            "strength ratio [-]",
        )
        .log_x()
        .curve(series("model", &model_points))
        .reference_curve(sampled("fib MC2010", lo, hi, 200, true, |r| {
            mc2010_dif_ratio(r, relative_to, tension_side)
        }));
        let quantity = if tension_side {
            Quantity::TensionPeakRatio
        } else {
            Quantity::CompressionPeakRatio
        };
        // The judged band: +- the tolerance around MC2010 over the judged rates.
        let judged: Vec<(f64, f64)> = mp
            .rates
            .iter()
            .filter_map(|&r| {
                let at = Selector {
                    rate: Some(r),
                    ..Selector::default()
                };
                let b = targets.band(quantity, &at)?;
                let reference = targets.reference(quantity, &at)?;
                Some((r, (b[1] - reference) / reference))
            })
            .collect();
        if let (Some(first), Some(last)) = (judged.first(), judged.last()) {
            let tol = first.1;
            let pct = num(100.0 * tol);
            let (a, b) = (first.0, last.0);
            plot = plot
                .reference_curve(sampled(
                    format!("MC2010 +{pct} % (judged)"),
                    a,
                    b,
                    60,
                    true,
                    |r| (1.0 + tol) * mc2010_dif_ratio(r, relative_to, tension_side),
                ))
                .reference_curve(sampled(format!("MC2010 -{pct} %"), a, b, 60, true, |r| {
                    (1.0 - tol) * mc2010_dif_ratio(r, relative_to, tension_side)
                }));
        }
        if let Some(f_cm) = cebfip {
            plot = plot.reference_curve(sampled(
                format!("CEB-FIP 1990 (f_cm {f_cm} MPa)"),
                lo,
                hi,
                200,
                true,
                |r| {
                    cebfip1990_dynamic_increase_factor(r, tension_side, f_cm)
                        / cebfip1990_dynamic_increase_factor(relative_to, tension_side, f_cm)
                },
            ));
        }
        out.plots.push(plot);
    }
    let mut curves_plot = MaterialPlot::new(
        format!("Uniaxial tension at several rates, h = {} mm", num(h * 1e3)),
        STRAIN_AXIS,
        "stress [MPa]",
    );
    let n = tension_curves.len();
    for (i, (rate, curve)) in tension_curves.iter().enumerate() {
        if n > 4 && !(i == 0 || i == n - 1 || i == n / 2 || close(*rate, relative_to)) {
            continue;
        }
        let peak_strain = curve.peak().strain[0];
        let pts: Vec<(f64, f64)> = axial_points(curve, 1.0)
            .into_iter()
            .filter(|p| p.0 <= 4.0 * peak_strain * PER_MILLE)
            .collect();
        curves_plot = curves_plot.curve(series(format!("{rate:e} /s"), &pts));
    }
    out.plots.push(curves_plot);
    Ok(())
}
