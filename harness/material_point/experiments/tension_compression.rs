//! Tension under a held lateral compression (Kupfer, Hilsdorf & Rüsch 1969): the tensile peak
//! at each lateral stress of the case, over the same point's uniaxial tensile peak.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::tension_under_lateral_stress;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{axial_points, established_peak, note_stop, value, MPA};
use crate::material_point::plots::{series, STRAIN_AXIS};
use crate::material_point::{
    MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, Selector, Targets,
};
use crate::report::format::num;

/// Default axial strain added after the lateral preload: six times the thesis concrete's
/// tensile peak strain, past every peak of the envelope.
pub const TENSION_COMPRESSION_END: f64 = 8e-4;
/// Default number of increments of that path.
pub const TENSION_COMPRESSION_STEPS: usize = 400;

/// Runs every lateral stress of `mp` (and 0 if the case leaves it out: the ratios need it).
pub(super) fn tension_compression(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let end = mp.end.unwrap_or(TENSION_COMPRESSION_END);
    let steps = mp.steps.unwrap_or(TENSION_COMPRESSION_STEPS);
    out.setup.push(format!(
        "lateral stress sigma_22 applied first (sigma_11 = sigma_33 = 0), then held while \
         E_11 grows by {end:e} in {steps} increments (sigma_33 = 0, no shear), quasi-static"
    ));
    let mut lateral: Vec<f64> = std::iter::once(0.0)
        .chain(mp.lateral_stresses.iter().copied())
        .collect();
    lateral.sort_by(|a, b| b.total_cmp(a));
    lateral.dedup();

    let mut runs = Vec::new();
    for &s in &lateral {
        let curve = tension_under_lateral_stress(&model, h, s, end, steps)?;
        let what = format!("tension under sigma_22 = {} MPa", num(s / MPA));
        note_stop(&curve, &what, out);
        let (peak, strain) = established_peak(&curve, &what, out);
        runs.push((s, curve, peak, strain));
    }
    let uniaxial = runs[0].2;
    let mut envelope = Vec::new();
    let mut reference = Vec::new();
    let mut rows = Vec::new();
    for (s, _, peak, strain) in &runs {
        let at = Selector {
            lateral_stress: Some(*s),
            ..Selector::default()
        };
        let ratio = peak / uniaxial;
        out.values.extend([
            value(Quantity::LateralTensionPeak, &at, peak / MPA),
            value(Quantity::LateralTensionRatio, &at, ratio),
        ]);
        envelope.push((s / MPA, ratio));
        let target = targets.reference(Quantity::LateralTensionRatio, &at);
        if let Some(r) = target {
            reference.push((s / MPA, r));
        }
        rows.push(vec![
            num(s / MPA),
            num(peak / MPA),
            format!("{strain:.3e}"),
            num(ratio),
            target.map(num).unwrap_or_default(),
        ]);
    }
    let mut envelope_plot = MaterialPlot::new(
        "Tensile peak under a lateral compression, over the uniaxial tensile peak",
        "lateral stress sigma_22 [MPa]",
        "tensile peak / uniaxial tensile peak [-]",
    )
    .curve(series("model", &envelope));
    if !reference.is_empty() {
        envelope_plot = envelope_plot.reference_curve(series("reference (metrics)", &reference));
    }
    let mut curves = MaterialPlot::new(
        format!(
            "Tension under a held lateral stress, h = {} mm",
            num(h * 1e3)
        ),
        &format!("axial {STRAIN_AXIS}"),
        "stress sigma_11 [MPa]",
    );
    for (s, curve, _, _) in &runs {
        curves = curves.curve(series(
            format!("sigma_22 = {} MPa", num(s / MPA)),
            &axial_points(curve, 1.0),
        ));
    }
    out.plots.extend([envelope_plot, curves]);
    out.tables.push(RecordTable {
        title: "Tensile peaks".into(),
        head: [
            "sigma_22 [MPa]",
            "peak sigma_11 [MPa]",
            "E_11 at the peak",
            "over uniaxial",
            "reference",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        note: "A path that stops after its peak has lost the lateral stress (the point cannot \
               hold it once cracked); its peak still counts."
            .into(),
    });
    Ok(())
}
