//! Uniaxial tension on one fracture path: its measured values and its plots, shared by the
//! tension and crack-band experiments.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::{Curve, FracturePath};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{
    axial_points, established_peak, note_stop, peak_box, post_peak_rise, value, MPA, PER_MILLE,
};
use crate::material_point::plots::{sampled, series, STRAIN_AXIS};
use crate::material_point::{MaterialPlot, Outcome, Quantity, Selector, Targets, Value};
use crate::report::format::num;

/// One tension run on `path` (uniaxial stress, or lateral strains held after the peak) and its
/// values at `at`.
pub(super) fn tension_run(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    path: FracturePath,
    at: Selector,
    out: &mut Outcome,
) -> Result<(Curve, Vec<Value>), MaterialPointError> {
    let (curve, r) = path.tension(model, h, rate)?;
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

/// Tension plots: up to the peak with the target window and the initial slope, and the whole
/// softening branch.
pub(super) fn tension_plots(
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
