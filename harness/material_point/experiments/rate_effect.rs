//! The rate-effect experiment: the unit check of the rate law and the peaks over strain rates
//! against the fib MC2010 dynamic increase factors.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::experiments::{
    rate_scaling, uniaxial_compression, uniaxial_tension, Curve, QUASI_STATIC_RATE,
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
    describe_rate_law(params, out);
    unit_check(&model, params, h, mp, out)?;
    let peaks = peaks_over_rates(&model, params, h, mp, (end, steps), out)?;
    let bases = Bases::at(&peaks, relative_to);
    let cebfip = mp.reference_curves.iter().find_map(|c| match c {
        ReferenceCurve::CebFip1990Dif { f_cm } => Some(*f_cm),
        _ => None,
    });
    peaks_table(&peaks, &bases, cebfip, targets, out);
    // Plots: peak ratios against MC2010 in tension and compression, and tension curves at a few
    // rates.
    for tension_side in [true, false] {
        let plot = dif_plot(mp, &peaks, &bases, tension_side, cebfip, targets);
        out.plots.push(plot);
    }
    out.plots.push(tension_curves_plot(&peaks, h, relative_to));
    Ok(())
}

/// The rate factor `F(gamma_dot)` of the parameter file's rate law, 1 when the law is off.
fn rate_law(params: &MicroplaneParameters, gamma: f64) -> f64 {
    match params.rate_effect {
        Some(r) => microplane_rate_factor(gamma, r.c1, r.c2),
        None => 1.0,
    }
}

/// Says in the setup which rate law the parameter file sets (or that it sets none).
fn describe_rate_law(params: &MicroplaneParameters, out: &mut Outcome) {
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
}

/// (a) The unit check of the rate law on uniaxial strain (`gamma_dot = rate / sqrt 2`): the
/// stresses at a rate must be the quasi-static ones scaled by the ratio of the rate factors,
/// which the harness computes here independently of the solver from the parameter file.
fn unit_check(
    model: &MicroplaneConcrete,
    params: &MicroplaneParameters,
    h: f64,
    mp: &MaterialPointSpec,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let mut unit_rows = Vec::new();
    for &rate in &mp.unit_check_rates {
        let (solver_ratio, peak_ratio, misfit) =
            rate_scaling(model, h, rate, UNIT_CHECK_END, UNIT_CHECK_STEPS)?;
        let g = |r: f64| r / std::f64::consts::SQRT_2;
        let ratio = rate_law(params, g(rate)) / rate_law(params, g(QUASI_STATIC_RATE));
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
    Ok(())
}

/// The paths at one strain rate and what they reached.
struct RatePeak {
    /// Axial strain rate (1/s).
    rate: f64,
    /// Uniaxial tension path.
    tension_curve: Curve,
    /// Established tensile peak (Pa).
    tension: f64,
    /// Elastic uniaxial-stress stiffness at the rate (Pa; [`initial_stiffness`]).
    stiffness: f64,
    /// Slope of the tension path's first increment (Pa).
    first_slope: f64,
    /// Largest compressive stress (Pa, positive): the peak, or a lower bound of it.
    compression: f64,
    /// Whether the compressive path passed its peak.
    compression_passed: bool,
}

/// (b) Uniaxial tension and compression at each rate of the case, with notes on paths that
/// stopped early and on compressive paths that did not pass their peak.
fn peaks_over_rates(
    model: &MicroplaneConcrete,
    params: &MicroplaneParameters,
    h: f64,
    mp: &MaterialPointSpec,
    (end, steps): (f64, usize),
    out: &mut Outcome,
) -> Result<Vec<RatePeak>, MaterialPointError> {
    let mut peaks = Vec::with_capacity(mp.rates.len());
    for &rate in &mp.rates {
        let (curve, r) = uniaxial_tension(model, h, rate)?;
        let what = format!("tension at {rate:e} /s");
        note_stop(&curve, &what, out);
        let (peak, _) = established_peak(&curve, &what, out);
        let stiffness = initial_stiffness(model, h, rate, params.poisson_ratio)?;
        let (c, _) = uniaxial_compression(model, h, rate, end, steps)?;
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
        peaks.push(RatePeak {
            rate,
            tension_curve: curve,
            tension: peak,
            stiffness,
            first_slope: r.initial_slope,
            compression: -c.peak().stress[0],
            compression_passed: passed,
        });
    }
    Ok(peaks)
}

/// The peaks at the base rate `relative_to`, which the ratios divide by (NaN where the case's
/// rates miss it).
struct Bases {
    /// The base rate (1/s).
    relative_to: f64,
    /// Tensile peak at the base rate (Pa).
    tension: f64,
    /// Compressive peak at the base rate (Pa).
    compression: f64,
    /// Whether the compressive path at the base rate passed its peak.
    compression_passed: bool,
}

impl Bases {
    /// The bases of `peaks` at `relative_to`.
    fn at(peaks: &[RatePeak], relative_to: f64) -> Self {
        let base = peaks.iter().find(|p| close(p.rate, relative_to));
        Bases {
            relative_to,
            tension: base.map_or(f64::NAN, |p| p.tension),
            compression: base.map_or(f64::NAN, |p| p.compression),
            compression_passed: base.is_some_and(|p| p.compression_passed),
        }
    }
}

/// The values of the peaks and their ratios at each rate, the spread of the initial stiffness
/// over the rates (it must not depend on the rate), and the table of the ratios against MC2010
/// and CEB-FIP 1990 (`cebfip`: its `f_cm` in MPa where the case draws it).
fn peaks_table(
    peaks: &[RatePeak],
    bases: &Bases,
    cebfip: Option<f64>,
    targets: &Targets,
    out: &mut Outcome,
) {
    let relative_to = bases.relative_to;
    let rows = peaks
        .iter()
        .map(|p| peak_row(p, bases, cebfip, targets, out))
        .collect();
    let spread_of = |slopes: Vec<f64>| {
        let mean = slopes.iter().sum::<f64>() / slopes.len() as f64;
        (slopes.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - slopes.iter().copied().fold(f64::INFINITY, f64::min))
            / mean
    };
    let spread = spread_of(peaks.iter().map(|p| p.stiffness).collect());
    let first_increment_spread = spread_of(peaks.iter().map(|p| p.first_slope).collect());
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
}

/// The values measured at one rate (into `out`) and its row of the peaks table: the peaks, their
/// ratios to the base rate's, and the MC2010 and CEB-FIP 1990 ratios they are compared with.
fn peak_row(
    p: &RatePeak,
    bases: &Bases,
    cebfip: Option<f64>,
    targets: &Targets,
    out: &mut Outcome,
) -> Vec<String> {
    let (rate, peak, stiffness, cpeak) = (p.rate, p.tension, p.stiffness, p.compression);
    let relative_to = bases.relative_to;
    let at = Selector {
        rate: Some(rate),
        ..Selector::default()
    };
    let (tr, cr) = (peak / bases.tension, cpeak / bases.compression);
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
    vec![
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
        if p.compression_passed {
            num(cpeak / MPA)
        } else {
            format!(">= {} (peak not passed)", num(cpeak / MPA))
        },
        if p.compression_passed && bases.compression_passed {
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
    ]
}

/// The dynamic increase of the peak in tension (`tension_side`) or compression over the rates:
/// the model's ratios against fib MC2010, the judged band around it, and CEB-FIP 1990 where the
/// case draws it.
fn dif_plot(
    mp: &MaterialPointSpec,
    peaks: &[RatePeak],
    bases: &Bases,
    tension_side: bool,
    cebfip: Option<f64>,
    targets: &Targets,
) -> MaterialPlot {
    let relative_to = bases.relative_to;
    let (lo, hi) = mp
        .rates
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| {
            (a.min(r), b.max(r))
        });
    let (what, model_points, quantity): (_, Vec<(f64, f64)>, _) = if tension_side {
        (
            "tension",
            peaks
                .iter()
                .map(|p| (p.rate, p.tension / bases.tension))
                .collect(),
            Quantity::TensionPeakRatio,
        )
    } else {
        (
            "compression",
            peaks
                .iter()
                .map(|p| (p.rate, p.compression / bases.compression))
                .collect(),
            Quantity::CompressionPeakRatio,
        )
    };
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
    plot
}

/// The tension paths at a few rates (all of them up to four; otherwise the first, the middle,
/// the last and the base rate), each to four times its peak strain.
fn tension_curves_plot(peaks: &[RatePeak], h: f64, relative_to: f64) -> MaterialPlot {
    let mut curves_plot = MaterialPlot::new(
        format!("Uniaxial tension at several rates, h = {} mm", num(h * 1e3)),
        STRAIN_AXIS,
        "stress [MPa]",
    );
    let n = peaks.len();
    for (i, p) in peaks.iter().enumerate() {
        let (rate, curve) = (&p.rate, &p.tension_curve);
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
    curves_plot
}
