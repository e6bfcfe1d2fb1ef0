//! The experiments of `material_point` cases: each drives the solver's virtual experiments
//! (`impact_solver::material::microplane::experiments`), measures its quantities in report units
//! and draws its plots with the targets of the case's metrics.

use impact_solver::material::microplane::driver::{MaterialPoint, PathPoint};
use impact_solver::material::microplane::experiments::FracturePath;
use impact_solver::material::microplane::experiments::{
    closed_strain_cycle, equal_biaxial_compression, hydrostatic_compression, isotropy_error,
    rate_scaling, softening_shape, uniaxial_compression, uniaxial_tension, Curve,
    QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters, SphereRule};
use impact_solver::rng::SplitMix64;

use super::plots::{sampled, series, series_keeping, STRAIN_AXIS};
use super::{
    rule_name, Experiment, MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable,
    ReferenceCurve, Selector, Targets, Value,
};
use crate::reference::concrete::{
    cebfip1990_dynamic_increase_factor, hordijk_softening, mc2010_bilinear_softening,
    mc2010_compression_stress, mc2010_dif_ratio, microplane_hydrostatic_returned_fraction,
    microplane_rate_factor,
};
use crate::report::format::num;

/// Strain magnitude of the isotropy check: far inside the elastic range, so that the nonlinear
/// terms (of relative size `(eps / e1)^m`) stay below 1e-15 for exponents `m` of 1 or more.
pub const ISOTROPY_STRAIN: f64 = 1e-20;
/// Default sample count of the isotropy check.
pub const ISOTROPY_SAMPLES: usize = 200;
/// Defaults of the compressive paths: to 6e-3 in increments of 1e-5.
pub const COMPRESSION_END: f64 = 6e-3;
pub const COMPRESSION_STEPS: usize = 600;
/// Defaults of the hydrostatic path: all normal strains to -0.05 and back.
pub const HYDROSTATIC_END: f64 = 0.05;
pub const HYDROSTATIC_STEPS: usize = 500;
/// The unit check of the rate law: uniaxial strain to 4e-4 in 200 increments (past the peak).
pub const UNIT_CHECK_END: f64 = 4e-4;
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
) -> Result<Outcome, String> {
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

/// Norm of a symmetric tensor stored `[11, 22, 33, 23, 13, 12]`, shears counted twice.
fn tensor_norm(s: &[f64; 6]) -> f64 {
    (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// Hooke's law `sigma = E / (1 + nu) (eps + nu / (1 - 2 nu) tr(eps) I)` (tensor shears).
fn hooke(e: f64, nu: f64, eps: &[f64; 6]) -> [f64; 6] {
    let g2 = e / (1.0 + nu);
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let tr = eps[0] + eps[1] + eps[2];
    std::array::from_fn(|i| g2 * eps[i] + if i < 3 { lambda * tr } else { 0.0 })
}

fn relative_difference(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    let d: [f64; 6] = std::array::from_fn(|i| a[i] - b[i]);
    tensor_norm(&d) / tensor_norm(b)
}

/// Isotropy: for each rule, the model's update at a tiny strain in random directions, and its
/// homogenised elastic stiffness, against Hooke's law with the file's E and nu (computed here);
/// the solver's own check beside them.
fn isotropy(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let samples = mp.samples.unwrap_or(ISOTROPY_SAMPLES);
    let rules = if mp.rules.is_empty() {
        vec![SphereRule::BazantOh21, SphereRule::Bazant37]
    } else {
        mp.rules.clone()
    };
    let (e, nu) = (params.youngs_modulus, params.poisson_ratio);
    out.setup.push(format!(
        "{samples} random strain directions (seeded), magnitude {ISOTROPY_STRAIN:e}; Hooke's law \
         with E = {} MPa, nu = {} from the parameter file",
        num(e / MPA),
        num(nu)
    ));
    let mut plot = MaterialPlot::new(
        "Isotropy: deviation from Hooke's law per direction",
        "direction",
        "relative deviation [-]",
    )
    .log_y();
    let mut rows = Vec::new();
    for rule in rules {
        let model = MicroplaneConcrete::new(MicroplaneParameters { rule, ..*params })?;
        let band = model.crack_band(params.h_ref)?;
        let c = model.elastic_stiffness();
        // A seed of our own, so that the directions differ from the solver's check.
        let mut rng = SplitMix64::new(0x5EED_0150);
        let mut update_errors = Vec::with_capacity(samples);
        let mut stiffness_worst: f64 = 0.0;
        for _ in 0..samples {
            let raw: [f64; 6] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
            let norm = tensor_norm(&raw);
            let dir: [f64; 6] = std::array::from_fn(|i| raw[i] / norm);
            let eps: [f64; 6] = std::array::from_fn(|i| ISOTROPY_STRAIN * dir[i]);
            let mut state = model.initial_state();
            let (stress, _) = model.update(&mut state.values, &eps, 0.0, &band);
            update_errors.push(relative_difference(&stress, &hooke(e, nu, &eps)));
            // The stiffness acts on engineering shears.
            let voigt = [
                dir[0],
                dir[1],
                dir[2],
                2.0 * dir[3],
                2.0 * dir[4],
                2.0 * dir[5],
            ];
            let s: [f64; 6] = std::array::from_fn(|i| (0..6).map(|j| c[i][j] * voigt[j]).sum());
            stiffness_worst = stiffness_worst.max(relative_difference(&s, &hooke(e, nu, &dir)));
        }
        let worst = update_errors.iter().copied().fold(0.0, f64::max);
        let solver = isotropy_error(&model, samples);
        let at = Selector {
            rule: Some(rule),
            ..Selector::default()
        };
        out.values.push(value(Quantity::IsotropyError, &at, worst));
        out.values.push(value(
            Quantity::StiffnessIsotropyError,
            &at,
            stiffness_worst,
        ));
        out.values
            .push(value(Quantity::SolverIsotropyError, &at, solver));
        rows.push(vec![
            rule_name(rule).to_string(),
            model.planes().len().to_string(),
            format!("{worst:.2e}"),
            format!("{stiffness_worst:.2e}"),
            format!("{solver:.2e}"),
        ]);
        let zeros = update_errors.iter().filter(|&&x| x == 0.0).count();
        if zeros > 0 {
            out.notes.push(format!(
                "{}: {zeros} of {samples} directions agree with Hooke's law to the last bit \
                 (not drawn on the log axis)",
                rule_name(rule)
            ));
        }
        let points: Vec<(f64, f64)> = update_errors
            .iter()
            .enumerate()
            .map(|(i, &x)| ((i + 1) as f64, x))
            .collect();
        plot = plot.curve(series(rule_name(rule), &points));
        if let Some(b) = targets.band(Quantity::IsotropyError, &at) {
            if plot.plot.reference_lines.is_empty() && b[1].is_finite() {
                plot = plot.line("acceptance", b[1], None);
            }
        }
    }
    out.tables.push(RecordTable {
        title: "Largest relative deviation from Hooke's law".into(),
        head: [
            "rule",
            "directions",
            "model update",
            "elastic stiffness",
            "solver's own check",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        note: "Model update: the stress of one update at the tiny strain; elastic stiffness: the \
               homogenised elastic split (5.37) applied to a unit strain; the solver's check uses \
               its own directions and its own Hooke constants."
            .into(),
    });
    out.plots.push(plot);
    Ok(())
}

/// One tension run on `path` (uniaxial stress, or lateral strains held after the peak) and its
/// values at `at`.
fn tension_run(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    path: FracturePath,
    at: Selector,
    out: &mut Outcome,
) -> Result<(Curve, Vec<Value>), String> {
    let (curve, r) = path.tension(model, h, rate).map_err(|e| e.to_string())?;
    let what = format!("tension{}", label_suffix(&at));
    note_stop(&curve, &what, out);
    let (peak, peak_strain) = established_peak(&curve, &what, out);
    let values = vec![
        value(Quantity::PeakStress, &at, peak / MPA),
        value(Quantity::PeakStrain, &at, peak_strain),
        value(Quantity::InitialSlope, &at, r.initial_slope / MPA),
        value(Quantity::FractureEnergy, &at, r.fracture_energy / 1e3),
        value(Quantity::FinalStressRatio, &at, r.final_stress_ratio),
        value(
            Quantity::PostPeakRise,
            &at,
            post_peak_rise(&curve.axial_stress()),
        ),
    ];
    Ok((curve, values))
}

fn label_suffix(at: &Selector) -> String {
    let l = at.label();
    if l.is_empty() {
        l
    } else {
        format!(" ({l})")
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

/// Whether the curve passed its peak: the stress fell below its largest |sigma_11| by 1e-3 of it
/// afterwards. Otherwise the largest stress computed is only a lower bound of the peak (the path
/// ended or stopped while the stress still rose).
pub fn peak_passed(curve: &Curve) -> bool {
    let s: Vec<f64> = curve.points.iter().map(|p| p.stress[0].abs()).collect();
    let Some((i, &top)) = s.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return false;
    };
    s[i..].iter().any(|&x| x < (1.0 - 1e-3) * top)
}

/// The peak stress and strain (magnitudes, Pa) if the curve passed its peak, else NaN with a
/// note.
fn established_peak(curve: &Curve, what: &str, out: &mut Outcome) -> (f64, f64) {
    let p = curve.peak();
    if peak_passed(curve) {
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

/// Tension plots: up to the peak with the target window and the initial slope, and the whole
/// softening branch.
fn tension_plots(
    curve: &Curve,
    h: f64,
    params: &MicroplaneParameters,
    targets: &Targets,
    at: &Selector,
) -> Vec<MaterialPlot> {
    let points = axial_points(curve, 1.0);
    let peak = curve.peak();
    let strain_top = targets
        .band(Quantity::PeakStrain, at)
        .map_or(0.0, |b| b[1] * PER_MILLE);
    let zoom_end = (3.0 * peak.strain[0] * PER_MILLE).max(2.0 * strain_top);
    let pre: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0 <= zoom_end).collect();
    let modulus = targets
        .reference(Quantity::InitialSlope, at)
        .unwrap_or(params.youngs_modulus / MPA);
    let stress_top = targets
        .band(Quantity::PeakStress, at)
        .map_or(peak.stress[0] / MPA, |b| b[1]);
    let slope_end = (1.1 * stress_top / modulus * PER_MILLE).min(zoom_end);
    let mut first = MaterialPlot::new(
        format!("Uniaxial tension to the peak, h = {} mm", num(h * 1e3)),
        STRAIN_AXIS,
        "stress [MPa]",
    )
    .curve(series("model", &pre))
    .reference_curve(sampled(
        format!("E eps, E = {} MPa", num(modulus)),
        0.0,
        slope_end,
        2,
        false,
        |x| modulus * x / PER_MILLE,
    ));
    if let Some((x, y)) = peak_box(targets, at) {
        first = first.target("target: peak stress x peak strain", x, y);
    } else if let Some(b) = targets.band(Quantity::PeakStress, at) {
        first = first.line("target peak stress", 0.5 * (b[0] + b[1]), Some(b));
    }
    let second = MaterialPlot::new(
        format!("Uniaxial tension: softening, h = {} mm", num(h * 1e3)),
        STRAIN_AXIS,
        "stress [MPa]",
    )
    .curve(series("model", &points));
    vec![first, second]
}

/// Uniaxial tension at each element size: `h int sigma d eps` against GF, curves against strain
/// and against the crack opening `w = h (eps - sigma / E)`.
fn crack_band(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let rate = rate_of(mp, out);
    out.setup.push(format!(
        "element sizes {} mm; the parameters were calibrated at h_ref = {} mm",
        mp.element_sizes
            .iter()
            .map(|h| num(h * 1e3))
            .collect::<Vec<_>>()
            .join(", "),
        num(params.h_ref * 1e3)
    ));
    let e = params.youngs_modulus;
    let mut strain_plot = MaterialPlot::new(
        "Crack band: stress-strain (to 1 % of the peak)",
        STRAIN_AXIS,
        "stress [MPa]",
    );
    let mut opening_plot = MaterialPlot::new(
        "Crack band: stress against crack opening",
        "crack opening w = h (eps - sigma/E) [mm]",
        "stress [MPa]",
    );
    // w1 = GF / ft of the case's softening reference (mm), where MC2010 and Hordijk are compared.
    let reference = mp.reference_curves.iter().find_map(|c| match *c {
        ReferenceCurve::Mc2010Softening { f_t, g_f }
        | ReferenceCurve::Hordijk1991Softening { f_t, g_f } => Some((f_t, g_f)),
        _ => None,
    });
    let mut shape_rows = Vec::new();
    let mut energies = Vec::new();
    let mut rows = Vec::new();
    for &h in &mp.element_sizes {
        let at = Selector {
            element_size: Some(h),
            ..Selector::default()
        };
        let (curve, values) = tension_run(
            &model,
            h,
            rate,
            mp.fracture_path_for(params),
            at.clone(),
            out,
        )?;
        let get = |q: Quantity| {
            values
                .iter()
                .find(|v| v.quantity == q)
                .map_or(f64::NAN, |v| v.value)
        };
        let gf = get(Quantity::FractureEnergy);
        energies.push((h * 1e3, gf));
        let target = targets.reference(Quantity::FractureEnergy, &at);
        rows.push(vec![
            num(h * 1e3),
            num(get(Quantity::PeakStress)),
            format!("{:.3e}", get(Quantity::PeakStrain)),
            num(gf),
            target.map_or("—".into(), num),
            target.map_or("—".into(), |t| {
                format!("{:+.1} %", 100.0 * (gf / t - 1.0))
            }),
            format!("{:.1e}", get(Quantity::FinalStressRatio)),
        ]);
        out.values.extend(values);
        if let Some((f_t, g_f)) = reference {
            let w1 = g_f / f_t;
            let shape = softening_shape(&curve, h, e, w1 * 1e-3);
            out.values.extend([
                value(
                    Quantity::SofteningStressRatioAtW1,
                    &at,
                    shape.stress_ratio_at_w1,
                ),
                value(
                    Quantity::SofteningEndOpening,
                    &at,
                    shape.opening_at_one_percent * 1e3,
                ),
            ]);
            shape_rows.push(vec![
                num(h * 1e3),
                format!("{:.4}", shape.stress_ratio_at_w1),
                format!("{:.4}", shape.opening_at_one_percent * 1e3),
            ]);
        }
        let name = format!("h = {} mm", num(h * 1e3));
        // The tail below 1 % of the peak would squeeze the curves into the left edge.
        let top = curve.peak().stress[0];
        let shown: Vec<_> = curve
            .points
            .iter()
            .enumerate()
            .take_while(|(i, p)| p.stress[0] >= 0.01 * top || *i <= 1)
            .map(|(_, p)| *p)
            .collect();
        let shown = Curve {
            points: shown,
            error: None,
        };
        strain_plot = strain_plot.curve(series(name.clone(), &axial_points(&shown, 1.0)));
        let opening: Vec<(f64, f64)> = shown
            .points
            .iter()
            .map(|p| (h * 1e3 * (p.strain[0] - p.stress[0] / e), p.stress[0] / MPA))
            .collect();
        opening_plot = opening_plot.curve(series(name, &opening));
    }
    for c in &mp.reference_curves {
        let (label, f_t, g_f, hordijk) = match *c {
            ReferenceCurve::Mc2010Softening { f_t, g_f } => ("MC2010 bilinear", f_t, g_f, false),
            ReferenceCurve::Hordijk1991Softening { f_t, g_f } => ("Hordijk 1991", f_t, g_f, true),
            _ => continue,
        };
        opening_plot = opening_plot.reference_curve(sampled(
            format!("{label} (ft {f_t} MPa, GF {g_f} N/mm)"),
            0.0,
            5.5 * g_f / f_t,
            200,
            false,
            |w| {
                if hordijk {
                    hordijk_softening(w, f_t, g_f)
                } else {
                    mc2010_bilinear_softening(w, f_t, g_f)
                }
            },
        ));
    }
    if let Some((f_t, g_f)) = reference {
        let w1 = g_f / f_t;
        out.tables.push(RecordTable {
            title: "Crack band: softening shape against MC2010 and Hordijk".into(),
            head: vec![
                "h [mm]".into(),
                format!("sigma / ft at w1 = GF/ft = {w1:.4} mm"),
                "w at 1 % of ft [mm]".into(),
            ],
            rows: {
                // Where a decreasing curve on [0, end] falls to 1 % of ft (bisection).
                let one_percent = |f: &dyn Fn(f64) -> f64, end: f64| {
                    let (mut lo, mut hi) = (0.0, end);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if f(mid) > 0.01 {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    0.5 * (lo + hi)
                };
                shape_rows.push(vec![
                    "MC2010 bilinear".into(),
                    format!("{:.4}", mc2010_bilinear_softening(w1, f_t, g_f) / f_t),
                    format!(
                        "{:.4} (zero at 5 GF/ft = {:.4})",
                        one_percent(&|w| mc2010_bilinear_softening(w, f_t, g_f) / f_t, 6.0 * w1),
                        5.0 * w1
                    ),
                ]);
                shape_rows.push(vec![
                    "Hordijk 1991".into(),
                    format!("{:.4}", hordijk_softening(w1, f_t, g_f) / f_t),
                    format!(
                        "{:.4} (zero at 5.14 GF/ft = {:.4})",
                        one_percent(&|w| hordijk_softening(w, f_t, g_f) / f_t, 6.0 * w1),
                        5.14 * w1
                    ),
                ]);
                shape_rows
            },
            note:
                "Crack opening w = h (eps - sigma/E) after the peak; sigma / ft with the model's \
                   own peak as ft."
                    .into(),
        });
    }
    let mut energy_plot = MaterialPlot::new(
        "Crack band: h int sigma d eps per element size",
        "element size h [mm]",
        "h int sigma d eps [N/mm]",
    )
    .curve(series("model", &energies));
    if let Some(b) = mp.element_sizes.first().and_then(|&h| {
        targets.band(
            Quantity::FractureEnergy,
            &Selector {
                element_size: Some(h),
                ..Selector::default()
            },
        )
    }) {
        energy_plot = energy_plot.line("target GF", 0.5 * (b[0] + b[1]), Some(b));
    }
    out.tables.push(RecordTable {
        title: "Uniaxial tension per element size".into(),
        head: [
            "h [mm]",
            "peak [MPa]",
            "peak strain",
            "h int sigma d eps [N/mm]",
            "target GF [N/mm]",
            "deviation",
            "final stress / peak",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        note: "Each path runs until the stress has fallen below 1e-3 of its peak; the tail \
               beyond is left out of the energy."
            .into(),
    });
    out.plots.extend([strain_plot, opening_plot, energy_plot]);
    Ok(())
}

fn compression_paths(mp: &MaterialPointSpec, out: &mut Outcome) -> (f64, usize) {
    let end = mp.end.unwrap_or(COMPRESSION_END);
    let steps = mp.steps.unwrap_or(COMPRESSION_STEPS);
    out.setup.push(format!(
        "compressive path to an axial strain of {end:e} in {steps} increments"
    ));
    (end, steps)
}

/// Uniaxial compression: peak, Poisson ratios, dilatancy and the MC2010 curve.
fn compression(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let rate = rate_of(mp, out);
    let (end, steps) = compression_paths(mp, out);
    let (curve, r) =
        uniaxial_compression(&model, h, rate, end, steps).map_err(|e| e.to_string())?;
    let at = Selector::default();
    note_stop(&curve, "compression", out);
    let (peak, peak_strain) = established_peak(&curve, "compression", out);
    let first = curve.points.get(1);
    out.values.extend([
        value(Quantity::PeakStress, &at, peak / MPA),
        value(Quantity::PeakStrain, &at, peak_strain),
        value(
            Quantity::InitialSlope,
            &at,
            first.map_or(f64::NAN, |p| p.stress[0] / p.strain[0] / MPA),
        ),
        value(Quantity::InitialPoisson, &at, r.initial_poisson),
        value(Quantity::PoissonAtPeak, &at, r.poisson_at_peak),
        value(
            Quantity::LargestPoissonAfterPeak,
            &at,
            r.largest_poisson_after_peak,
        ),
        value(
            Quantity::DilatancyOnset,
            &at,
            r.dilatancy_onset.unwrap_or(f64::NAN),
        ),
    ]);
    let points = axial_points(&curve, -1.0);
    let mut stress_plot = MaterialPlot::new(
        format!("Uniaxial compression, h = {} mm", num(h * 1e3)),
        "axial strain (compression) [1e-3]",
        "axial stress (compression) [MPa]",
    )
    .curve(series("model", &points));
    let mut rows = Vec::new();
    for c in &mp.reference_curves {
        if let ReferenceCurve::Mc2010Compression { f_cm, e_ci, eps_c1 } = *c {
            let reference = |eps: f64| mc2010_compression_stress(eps, f_cm, e_ci, eps_c1);
            // RMS over the model's points on the reference's pre-peak branch.
            let residuals: Vec<f64> = points
                .iter()
                .filter(|p| p.0 / PER_MILLE <= eps_c1)
                .map(|p| p.1 - reference(p.0 / PER_MILLE))
                .collect();
            let rms = if residuals.is_empty() {
                f64::NAN
            } else {
                (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt()
            };
            out.values
                .push(value(Quantity::Mc2010CurveMisfit, &at, rms));
            rows.push(vec![
                "RMS(model - MC2010) on 0 <= eps <= eps_c1".into(),
                format!("{} MPa ({} % of f_cm)", num(rms), num(100.0 * rms / f_cm)),
            ]);
            let lim = 3.5e-3_f64.min(end);
            stress_plot = stress_plot.reference_curve(sampled(
                format!("MC2010 (f_cm {f_cm} MPa, eps_c1 {eps_c1:e})"),
                0.0,
                lim * PER_MILLE,
                100,
                false,
                |x| reference(x / PER_MILLE),
            ));
        }
    }
    if let Some((x, y)) = peak_box(targets, &at) {
        stress_plot = stress_plot.target("target: peak stress x peak strain", x, y);
    }
    rows.splice(
        0..0,
        [
            vec![
                "initial apparent Poisson ratio".to_string(),
                format!(
                    "{} (file's nu {})",
                    num(r.initial_poisson),
                    num(params.poisson_ratio)
                ),
            ],
            vec![
                "apparent Poisson ratio at the largest stress".into(),
                num(r.poisson_at_peak),
            ],
            vec![
                "largest apparent Poisson ratio after it".into(),
                num(r.largest_poisson_after_peak),
            ],
            vec![
                "onset of dilatancy (axial strain of the smallest volume)".into(),
                r.dilatancy_onset
                    .map_or("volume still falling at the end".into(), |d| {
                        format!(
                            "{d:.3e} ({} % of the strain at the largest stress)",
                            num(100.0 * d / r.peak_strain)
                        )
                    }),
            ],
        ],
    );
    out.tables.push(RecordTable {
        title: "Uniaxial compression: reported, not judged".into(),
        head: vec!["quantity".into(), "value".into()],
        rows,
        note: String::new(),
    });
    let lateral: Vec<(f64, f64)> = curve
        .points
        .iter()
        .map(|p| (-p.strain[0] * PER_MILLE, p.strain[1] * PER_MILLE))
        .collect();
    let volumetric: Vec<(f64, f64)> = curve
        .points
        .iter()
        .map(|p| {
            (
                -p.strain[0] * PER_MILLE,
                (p.strain[0] + p.strain[1] + p.strain[2]) * PER_MILLE,
            )
        })
        .collect();
    let strain_plot = MaterialPlot::new(
        "Uniaxial compression: lateral and volumetric strain",
        "axial strain (compression) [1e-3]",
        "strain [1e-3]",
    )
    .curve(series("lateral strain eps_22", &lateral))
    .curve(series("volumetric strain eps_kk", &volumetric));
    let shown = 2.0;
    let poisson: Vec<(f64, f64)> = curve
        .points
        .iter()
        .skip(1)
        .map(|p| (-p.strain[0] * PER_MILLE, -p.strain[1] / p.strain[0]))
        .filter(|p| p.1.abs() <= shown)
        .collect();
    let mut poisson_plot = MaterialPlot::new(
        format!("Apparent Poisson ratio -eps_22/eps_11 (shown up to {shown})"),
        "axial strain (compression) [1e-3]",
        "apparent Poisson ratio [-]",
    )
    .curve(series("model", &poisson))
    .line(
        format!("file's nu = {}", num(params.poisson_ratio)),
        params.poisson_ratio,
        None,
    );
    if let Some(b) = targets.band(Quantity::LargestPoissonAfterPeak, &at) {
        if b[0].is_finite() {
            poisson_plot = poisson_plot.line("target: passes 0.5 after the peak", b[0], None);
        }
    }
    out.plots.extend([stress_plot, strain_plot, poisson_plot]);
    Ok(())
}

/// Equal biaxial compression beside uniaxial compression on the same grid.
fn biaxial(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let (end, steps) = compression_paths(mp, out);
    let (bi, peak_bi) =
        equal_biaxial_compression(&model, h, end, steps).map_err(|e| e.to_string())?;
    let (uni, r) = uniaxial_compression(&model, h, QUASI_STATIC_RATE, end, steps)
        .map_err(|e| e.to_string())?;
    note_stop(&bi, "equal biaxial compression", out);
    note_stop(&uni, "uniaxial compression", out);
    let (bi_peak, _) = established_peak(&bi, "equal biaxial compression", out);
    let (uni_peak, _) = established_peak(&uni, "uniaxial compression", out);
    let at = Selector::default();
    let ratio = bi_peak / uni_peak;
    out.values.extend([
        value(Quantity::BiaxialPeakStress, &at, bi_peak / MPA),
        value(Quantity::PeakStress, &at, uni_peak / MPA),
        value(Quantity::BiaxialRatio, &at, ratio),
    ]);
    let mut plot = MaterialPlot::new(
        format!(
            "Equal biaxial and uniaxial compression, h = {} mm",
            num(h * 1e3)
        ),
        "axial strain eps_11 (compression) [1e-3]",
        "stress -sigma_11 [MPa]",
    )
    .curve(series("equal biaxial", &axial_points(&bi, -1.0)))
    .curve(series("uniaxial", &axial_points(&uni, -1.0)));
    if let Some(b) = targets.band(Quantity::BiaxialRatio, &at) {
        let uni_top = r.peak_stress / MPA;
        plot = plot.line(
            format!("target: {} to {} x uniaxial peak", num(b[0]), num(b[1])),
            0.5 * (b[0] + b[1]) * uni_top,
            Some([b[0] * uni_top, b[1] * uni_top]),
        );
    }
    out.tables.push(RecordTable {
        title: "Peaks".into(),
        head: [
            "path",
            "largest -sigma_11 [MPa]",
            "at strain",
            "peak passed",
        ]
        .map(String::from)
        .to_vec(),
        rows: vec![
            vec![
                "equal biaxial".into(),
                num(peak_bi / MPA),
                format!("{:.3e}", -bi.peak().strain[0]),
                peak_passed(&bi).to_string(),
            ],
            vec![
                "uniaxial".into(),
                num(r.peak_stress / MPA),
                format!("{:.3e}", r.peak_strain),
                peak_passed(&uni).to_string(),
            ],
            vec!["ratio".into(), num(ratio), String::new(), String::new()],
        ],
        note: "Largest -sigma_11 computed on each path; a peak counts only when the stress fell \
               after it (by 1e-3 of it), otherwise the ratio is not measured."
            .into(),
    });
    out.plots.push(plot);
    Ok(())
}

/// Hydrostatic compression and unloading: damage, and compaction then stiffening of the
/// secant bulk modulus.
fn hydrostatic(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let end = mp.end.unwrap_or(HYDROSTATIC_END);
    let steps = mp.steps.unwrap_or(HYDROSTATIC_STEPS);
    out.setup.push(format!(
        "all normal strains to -{} (volumetric strain -{}) in {steps} increments and back",
        num(end),
        num(3.0 * end)
    ));
    let (curve, damaged) =
        hydrostatic_compression(&model, h, end, steps).map_err(|e| e.to_string())?;
    note_stop(&curve, "hydrostatic compression", out);
    let pv: Vec<(f64, f64)> = curve
        .points
        .iter()
        .map(|p| {
            (
                -(p.strain[0] + p.strain[1] + p.strain[2]),
                -(p.stress[0] + p.stress[1] + p.stress[2]) / 3.0,
            )
        })
        .collect();
    let turn = steps.min(pv.len() - 1);
    let (loading, unloading) = (&pv[..=turn], &pv[turn..]);
    let secant: Vec<(f64, f64)> = loading.iter().skip(1).map(|&(v, p)| (v, p / v)).collect();
    let k0 = secant.first().map_or(f64::NAN, |s| s.1);
    let ratios: Vec<(f64, f64)> = secant.iter().map(|&(v, k)| (v, k / k0)).collect();
    let first_soft = ratios.iter().position(|r| r.1 < 1.0 - 1e-3);
    let then_stiff = first_soft.is_some_and(|i| ratios[i..].iter().any(|r| r.1 > 1.0 + 1e-3));
    let smallest = ratios.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    let largest = ratios.iter().map(|r| r.1).fold(f64::NEG_INFINITY, f64::max);
    let peak_p = loading.iter().map(|x| x.1).fold(0.0, f64::max);
    let residual = unloading
        .iter()
        .find(|x| x.1 <= 1e-9 * peak_p)
        .map_or(0.0, |x| x.0);
    let at = Selector::default();
    let hooke_k = params.youngs_modulus / (3.0 * (1.0 - 2.0 * params.poisson_ratio));
    let (cycle_work, cycle_abs) = work(&curve.points);
    let loading_work = work(&curve.points[..=turn]).0;
    let returned = -work(&curve.points[turn..]).0;
    let fraction = returned / loading_work;
    let closed_form = microplane_hydrostatic_returned_fraction(
        params.youngs_modulus / (1.0 - 2.0 * params.poisson_ratio),
        [params.a, params.b, params.p, params.q],
        end,
    );
    if cycle_work < -1e-6 * cycle_abs {
        out.notes.push(format!(
            "the load-unload cycle gives back {} J/m^3 more than it took ({} % of its work): \
             unloading runs above the loading curve",
            num(-cycle_work),
            num(-100.0 * cycle_work / (0.5 * cycle_abs))
        ));
    }
    out.values.extend([
        value(Quantity::Damaged, &at, damaged as u8 as f64),
        value(
            Quantity::CompactionThenStiffening,
            &at,
            then_stiff as u8 as f64,
        ),
        value(Quantity::SmallestSecantRatio, &at, smallest),
        value(Quantity::LargestSecantRatio, &at, largest),
        value(Quantity::InitialBulkModulus, &at, k0 / MPA),
        value(Quantity::ResidualVolumetricStrain, &at, residual),
        value(Quantity::CycleDissipation, &at, cycle_work),
        value(Quantity::ReturnedWorkFraction, &at, fraction),
        value(Quantity::ReturnedWorkFractionClosedForm, &at, closed_form),
        value(
            Quantity::ReturnedWorkFractionError,
            &at,
            (fraction / closed_form - 1.0).abs(),
        ),
    ]);
    out.tables.push(RecordTable {
        title: "Hydrostatic compression".into(),
        head: vec!["quantity".into(), "value".into()],
        rows: vec![
            vec!["damage on loading or unloading".into(), damaged.to_string()],
            vec![
                "initial bulk modulus [MPa]".into(),
                format!(
                    "{} (Hooke: E / (3 (1 - 2 nu)) = {})",
                    num(k0 / MPA),
                    num(hooke_k / MPA)
                ),
            ],
            vec![
                "smallest secant / initial (compaction)".into(),
                format!(
                    "{} at volumetric strain {}",
                    num(smallest),
                    ratios
                        .iter()
                        .find(|r| r.1 == smallest)
                        .map_or("—".into(), |r| format!("{:.3e}", r.0))
                ),
            ],
            vec!["largest secant / initial (stiffening)".into(), num(largest)],
            vec!["compaction, then stiffening".into(), then_stiff.to_string()],
            vec![
                "volumetric strain where the pressure returns to zero on unloading".into(),
                format!("{residual:.3e}"),
            ],
            vec![
                "work given back on unloading / work of loading".into(),
                format!(
                    "{} (closed form from the law: {})",
                    num(fraction),
                    num(closed_form)
                ),
            ],
            vec![
                "work over the load-unload cycle, oint sigma : d eps [J/m^3]".into(),
                format!("{} (negative: energy given back)", num(cycle_work)),
            ],
        ],
        note: "Secant bulk modulus K = p / (-eps_kk) on loading; compaction: below its initial \
               value by more than 1e-3 of it, stiffening: above it by as much."
            .into(),
    });
    let scale = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        pts.iter().map(|&(v, p)| (v * PER_MILLE, p / MPA)).collect()
    };
    out.plots.push(
        MaterialPlot::new(
            "Hydrostatic compression: pressure against volume",
            "volumetric strain -eps_kk [1e-3]",
            "pressure p = -sigma_kk/3 [MPa]",
        )
        .curve(series("loading", &scale(loading)))
        .curve(series("unloading", &scale(unloading))),
    );
    let ratio_points: Vec<(f64, f64)> = ratios.iter().map(|&(v, r)| (v * PER_MILLE, r)).collect();
    out.plots.push(
        MaterialPlot::new(
            "Hydrostatic compression: secant bulk modulus",
            "volumetric strain -eps_kk [1e-3]",
            "secant K / initial K [-]",
        )
        .curve(series("model", &ratio_points))
        .line("initial value", 1.0, None),
    );
    Ok(())
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

/// The shear component with the largest excursion among the corners, if any.
fn shear_component(corners: &[[f64; 6]]) -> Option<usize> {
    (3..6)
        .map(|i| (i, corners.iter().map(|c| c[i].abs()).fold(0.0, f64::max)))
        .filter(|(_, m)| *m > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

const COMPONENT: [&str; 6] = ["11", "22", "33", "23", "13", "12"];

/// Closed strain cycles with and without the deviatoric trace term, and the unloading stiffness
/// after the tensile peak.
fn cyclic(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    out.setup.push(
        "each cycle runs with the deviatoric trace term on (the default, judged) and off \
         (reported), whatever the parameter file says"
            .into(),
    );
    let mut rows = Vec::new();
    let mut dissipation_plot = MaterialPlot::new(
        "Dissipation per repetition of each closed cycle",
        "repetition",
        "oint sigma : d eps [J/m^3]",
    )
    .line("zero", 0.0, None);
    for cycle in &mp.cycles {
        let n = cycle.corners.len();
        let corners: Vec<[f64; 6]> = (0..cycle.repeat)
            .flat_map(|_| cycle.corners.iter().copied())
            .collect();
        let shear = shear_component(&cycle.corners);
        let mut normal_plot = MaterialPlot::new(
            format!("Cycle {}: sigma_11 against eps_11", cycle.name),
            "strain eps_11 [1e-3]",
            "stress sigma_11 [MPa]",
        );
        let mut shear_plot = shear.map(|i| {
            MaterialPlot::new(
                format!(
                    "Cycle {}: sigma_{c} against eps_{c} (tensor shear)",
                    cycle.name,
                    c = COMPONENT[i]
                ),
                &format!("strain eps_{} [1e-3]", COMPONENT[i]),
                &format!("stress sigma_{} [MPa]", COMPONENT[i]),
            )
        });
        for trace in [false, true] {
            let model = MicroplaneConcrete::new(MicroplaneParameters {
                deviatoric_trace_term: trace,
                ..*params
            })?;
            let (curve, _, healed) =
                closed_strain_cycle(&model, h, &corners, cycle.steps).map_err(|e| e.to_string())?;
            let per = n * cycle.steps;
            let last = curve.points.len() - 1;
            let reps: Vec<(f64, f64)> = (0..cycle.repeat)
                .map(|j| work(&curve.points[(j * per).min(last)..=((j + 1) * per).min(last)]))
                .collect();
            let setting = if trace {
                "trace term (default)"
            } else {
                "no trace term"
            };
            for (j, (w, _)) in reps.iter().enumerate() {
                out.values.push(value(
                    Quantity::CycleDissipation,
                    &Selector {
                        cycle: Some(format!("{}#{}", cycle.name, j + 1)),
                        deviatoric_trace_term: Some(trace),
                        ..Selector::default()
                    },
                    *w,
                ));
            }
            let at = Selector {
                cycle: Some(cycle.name.clone()),
                deviatoric_trace_term: Some(trace),
                ..Selector::default()
            };
            let smallest = reps.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
            let relative = reps.iter().map(|r| r.0 / r.1).fold(f64::INFINITY, f64::min);
            out.values.extend([
                value(Quantity::SmallestDissipation, &at, smallest),
                value(Quantity::SmallestRelativeDissipation, &at, relative),
                value(Quantity::ReturnedEnergyFraction, &at, -relative),
                value(Quantity::Healed, &at, healed as u8 as f64),
            ]);
            rows.push(vec![
                cycle.name.clone(),
                setting.to_string(),
                reps.iter()
                    .map(|r| format!("{:.4e}", r.0))
                    .collect::<Vec<_>>()
                    .join(", "),
                format!("{smallest:.4e}"),
                format!("{relative:.3e}"),
                healed.to_string(),
            ]);
            let name = format!("{} ({setting})", cycle.name);
            dissipation_plot = dissipation_plot.curve(series(
                name,
                &reps
                    .iter()
                    .enumerate()
                    .map(|(j, r)| ((j + 1) as f64, r.0))
                    .collect::<Vec<_>>(),
            ));
            let component = |i: usize| -> Vec<(f64, f64)> {
                curve
                    .points
                    .iter()
                    .map(|p| (p.strain[i] * PER_MILLE, p.stress[i] / MPA))
                    .collect()
            };
            let corners: Vec<usize> = (0..curve.points.len()).step_by(cycle.steps).collect();
            normal_plot = normal_plot.curve(series_keeping(setting, &component(0), &corners));
            if let (Some(i), Some(plot)) = (shear, shear_plot.take()) {
                shear_plot = Some(plot.curve(series_keeping(setting, &component(i), &corners)));
            }
        }
        out.plots.push(normal_plot);
        out.plots.extend(shear_plot);
    }
    out.plots.push(dissipation_plot);
    out.tables.push(RecordTable {
        title: "Closed strain cycles".into(),
        head: [
            "cycle",
            "setting",
            "dissipation per repetition [J/m^3]",
            "smallest [J/m^3]",
            "smallest relative",
            "healed",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        note: "Dissipation: the work oint sigma : d eps over one repetition of the closed strain \
               path (trapezoidal rule, tensor shears counted twice); relative: over the sum of \
               |sigma : d eps| along it. A negative value means the cycle gives energy back."
            .into(),
    });
    unloading(mp, params, h, targets, out)
}

/// Uniaxial tension to `unload_at` (default 2.5 times the peak strain), one small unloading
/// increment (its slope against the secant and E), then unloading to zero stress and reloading.
fn unloading(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let (monotonic, r) =
        uniaxial_tension(&model, h, QUASI_STATIC_RATE).map_err(|e| e.to_string())?;
    let unload_at = mp.unload_at.unwrap_or(2.5 * r.peak_strain);
    out.setup.push(format!(
        "unloading stiffness: uniaxial tension to {unload_at:.3e} ({}), one unloading increment \
         of {UNLOADING_PROBE:e}",
        if mp.unload_at.is_some() {
            "the case's unload_at"
        } else {
            "2.5 times the peak strain"
        }
    ));
    let mut point = MaterialPoint::new(&model, h).map_err(|e| e.to_string())?;
    let de = 2e-6;
    let n = (unload_at / de).ceil() as usize;
    let ramp: Vec<f64> = (1..=n).map(|i| unload_at * i as f64 / n as f64).collect();
    let mut path = point
        .uniaxial_stress(&ramp, QUASI_STATIC_RATE)
        .map_err(|e| e.to_string())?;
    let top = *path.last().expect("a ramp has points");
    let peak_before = path.iter().map(|p| p.stress[0]).fold(0.0, f64::max);
    if top.stress[0] >= peak_before {
        out.notes.push(format!(
            "unloading starts at {unload_at:.3e}, not past the tensile peak of this path"
        ));
    }
    let probe = point
        .uniaxial_stress(&[unload_at - UNLOADING_PROBE], QUASI_STATIC_RATE)
        .map_err(|e| e.to_string())?;
    let slope = (top.stress[0] - probe[1].stress[0]) / UNLOADING_PROBE;
    let secant = top.stress[0] / top.strain[0];
    let e = params.youngs_modulus;
    let position = (slope - secant) / (e - secant);
    path.push(probe[1]);
    // Unload until the stress is no longer tensile, then reload past the unloading point.
    let mut strain = unload_at - UNLOADING_PROBE;
    while strain > 0.0 && point.stress[0] > 0.0 {
        strain -= de;
        match point.uniaxial_stress(&[strain], QUASI_STATIC_RATE) {
            Ok(p) => path.push(p[1]),
            Err(e) => {
                out.notes.push(format!("unloading stopped: {e}"));
                break;
            }
        }
    }
    while strain < 1.6 * unload_at {
        strain += de;
        match point.uniaxial_stress(&[strain], QUASI_STATIC_RATE) {
            Ok(p) => path.push(p[1]),
            Err(e) => {
                out.notes.push(format!("reloading stopped: {e}"));
                break;
            }
        }
    }
    let at = Selector::default();
    out.values.extend([
        value(Quantity::UnloadingSlope, &at, slope / MPA),
        value(Quantity::UnloadingSecant, &at, secant / MPA),
        value(Quantity::UnloadingPosition, &at, position),
    ]);
    let band = targets.band(Quantity::UnloadingPosition, &at);
    out.tables.push(RecordTable {
        title: "Unloading stiffness after the tensile peak (uniaxial tension, default setting)"
            .into(),
        head: [
            "unloading at strain",
            "stress [MPa]",
            "secant [MPa]",
            "unloading slope [MPa]",
            "E [MPa]",
            "(slope - secant) / (E - secant)",
        ]
        .map(String::from)
        .to_vec(),
        rows: vec![vec![
            format!("{unload_at:.3e}"),
            num(top.stress[0] / MPA),
            num(secant / MPA),
            num(slope / MPA),
            num(e / MPA),
            num(position),
        ]],
        note: format!(
            "(5.102): the microplanes unload between their secant (alpha -> 0) and the initial \
             modulus (alpha = 1), alpha = {} here; the macroscopic slope should lie between the \
             secant and E{}.",
            num(params.alpha),
            band.map_or(String::new(), |b| format!(
                " (judged: position in [{}, {}])",
                num(b[0]),
                num(b[1])
            ))
        ),
    });
    let points: Vec<(f64, f64)> = path
        .iter()
        .map(|p| (p.strain[0] * PER_MILLE, p.stress[0] / MPA))
        .collect();
    let end = 1.6 * unload_at * PER_MILLE;
    let mono: Vec<(f64, f64)> = axial_points(&monotonic, 1.0)
        .into_iter()
        .filter(|p| p.0 <= end)
        .collect();
    let (eu, su) = (top.strain[0] * PER_MILLE, top.stress[0] / MPA);
    let e_mpa = e / MPA;
    let down = (eu - su * PER_MILLE / e_mpa).max(0.0);
    out.plots.push(
        MaterialPlot::new(
            "Unloading and reloading after the tensile peak",
            STRAIN_AXIS,
            "stress [MPa]",
        )
        .curve(series("unloading and reloading", &points))
        .reference_curve(series("monotonic (same model)", &mono))
        .reference_curve(sampled("slope E", down, eu, 1, false, |x| {
            su - e_mpa * (eu - x) / PER_MILLE
        }))
        .reference_curve(sampled("secant", 0.0, eu, 1, false, |x| su * x / eu)),
    );
    Ok(())
}

/// `sigma_11 / eps_11` for the elastic uniaxial-stress strain `[eps, -nu eps, -nu eps]` with
/// `eps` = [`STIFFNESS_PROBE`] reached at axial strain rate `rate` (all strains prescribed, so no
/// Newton tolerance enters): Young's modulus of the model at that rate.
fn initial_stiffness(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    nu: f64,
) -> Result<f64, String> {
    let mut point = MaterialPoint::new(model, h).map_err(|e| e.to_string())?;
    let e = STIFFNESS_PROBE;
    let p = point.strain_step([e, -nu * e, -nu * e, 0.0, 0.0, 0.0], e / rate);
    Ok(p.stress[0] / e)
}

/// Rate effect: the unit check of the rate law, and tensile and compressive peaks over rates
/// against the fib MC2010 dynamic increase factors.
fn rate_effect(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), String> {
    let model = MicroplaneConcrete::new(*params)?;
    let relative_to = mp.relative_to.ok_or("rate_effect needs relative_to")?;
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
            rate_scaling(&model, h, rate, UNIT_CHECK_END, UNIT_CHECK_STEPS)
                .map_err(|e| e.to_string())?;
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
        let (curve, r) = uniaxial_tension(&model, h, rate).map_err(|e| e.to_string())?;
        let what = format!("tension at {rate:e} /s");
        note_stop(&curve, &what, out);
        let (peak, _) = established_peak(&curve, &what, out);
        let stiffness = initial_stiffness(&model, h, rate, params.poisson_ratio)?;
        tension.push((rate, peak, stiffness, r.initial_slope));
        tension_curves.push((rate, curve));
        let (c, _) =
            uniaxial_compression(&model, h, rate, end, steps).map_err(|e| e.to_string())?;
        note_stop(&c, &format!("compression at {rate:e} /s"), out);
        // Compression is reported, not judged: a path that did not pass its peak still shows its
        // largest stress, marked as a lower bound.
        let passed = peak_passed(&c);
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
            .find(|(r, _)| super::close(*r, relative_to))
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
        .find(|(r, _)| super::close(**r, relative_to))
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
        if n > 4 && !(i == 0 || i == n - 1 || i == n / 2 || super::close(*rate, relative_to)) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn post_peak_rise_is_zero_for_monotone_softening_and_finds_a_bump() {
        assert_eq!(post_peak_rise(&[0.0, 1.0, 2.0, 1.5, 1.0, 0.5]), 0.0);
        let r = post_peak_rise(&[0.0, 2.0, 1.0, 1.2, 0.5]);
        assert!((r - 0.1).abs() < 1e-15, "{r}");
    }

    #[test]
    fn hooke_gives_e_in_uniaxial_stress() {
        let (e, nu) = (30e9, 0.18);
        let s = hooke(e, nu, &[1e-4, -nu * 1e-4, -nu * 1e-4, 0.0, 0.0, 0.0]);
        assert!((s[0] - e * 1e-4).abs() < 1e-9 * e * 1e-4);
        assert!(s[1].abs() < 1e-9 * s[0]);
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
        assert!(peak_passed(&curve(&[0.0, 2.0, 1.0])));
        assert!(!peak_passed(&curve(&[0.0, 1.0, 2.0])));
        // A plateau within 1e-3 of the top is not a passed peak.
        assert!(!peak_passed(&curve(&[0.0, 2.0, 1.9995])));
        assert!(peak_passed(&curve(&[0.0, -2.0, -1.0])));
    }
}
