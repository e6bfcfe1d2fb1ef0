//! The cyclic experiment: closed strain cycles with and without the deviatoric trace term,
//! and the unloading stiffness after the tensile peak.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::experiments::{
    closed_strain_cycle, uniaxial_tension, QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{axial_points, value, work, MPA, PER_MILLE, UNLOADING_PROBE};
use crate::material_point::plots::{sampled, series, series_keeping, STRAIN_AXIS};
use crate::material_point::{
    MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, Selector, Targets,
};
use crate::report::format::num;

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
pub(super) fn cyclic(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
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
            let (curve, _, healed) = closed_strain_cycle(&model, h, &corners, cycle.steps)?;
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
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let (monotonic, r) = uniaxial_tension(&model, h, QUASI_STATIC_RATE)?;
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
    let mut point = MaterialPoint::new(&model, h)?;
    let de = 2e-6;
    let n = (unload_at / de).ceil() as usize;
    let ramp: Vec<f64> = (1..=n).map(|i| unload_at * i as f64 / n as f64).collect();
    let mut path = point.uniaxial_stress(&ramp, QUASI_STATIC_RATE)?;
    let top = *path.last().expect("a ramp has points");
    let peak_before = path.iter().map(|p| p.stress[0]).fold(0.0, f64::max);
    if top.stress[0] >= peak_before {
        out.notes.push(format!(
            "unloading starts at {unload_at:.3e}, not past the tensile peak of this path"
        ));
    }
    let probe = point.uniaxial_stress(&[unload_at - UNLOADING_PROBE], QUASI_STATIC_RATE)?;
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
