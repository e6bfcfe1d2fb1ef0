//! The compression experiments: uniaxial compression (peak, Poisson ratios, dilatancy, MC2010
//! curve) and equal biaxial compression beside it.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::{
    equal_biaxial_compression, uniaxial_compression, CompressionResult, QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{
    axial_points, compression_paths, established_peak, note_stop, peak_box, rate_of, value, MPA,
    PER_MILLE,
};
use crate::material_point::plots::{sampled, series};
use crate::material_point::{
    MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, ReferenceCurve, Selector,
    Targets,
};
use crate::reference::concrete::mc2010_compression_stress;
use crate::report::format::num;

/// Uniaxial compression: peak, Poisson ratios, dilatancy and the MC2010 curve.
pub(super) fn compression(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let rate = rate_of(mp, out);
    let (end, steps) = compression_paths(mp, out);
    let (curve, r) = uniaxial_compression(&model, h, rate, end, steps)?;
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
    rows.splice(0..0, reported_rows(&r, params));
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

/// The rows of the compression quantities that are reported, not judged: the apparent Poisson
/// ratios and the onset of dilatancy.
fn reported_rows(r: &CompressionResult, params: &MicroplaneParameters) -> [Vec<String>; 4] {
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
    ]
}

/// Equal biaxial compression beside uniaxial compression on the same grid.
pub(super) fn biaxial(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let (end, steps) = compression_paths(mp, out);
    let (bi, peak_bi) = equal_biaxial_compression(&model, h, end, steps)?;
    let (uni, r) = uniaxial_compression(&model, h, QUASI_STATIC_RATE, end, steps)?;
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
                bi.peak_passed().to_string(),
            ],
            vec![
                "uniaxial".into(),
                num(r.peak_stress / MPA),
                format!("{:.3e}", r.peak_strain),
                uni.peak_passed().to_string(),
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
