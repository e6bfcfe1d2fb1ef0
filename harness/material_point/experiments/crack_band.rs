//! The crack-band experiment: uniaxial tension at several element sizes, its energy and its
//! softening shape against MC2010 and Hordijk.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::{softening_shape, Curve};
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::tension::tension_run;
use super::{axial_points, rate_of, value, MPA};
use crate::material_point::plots::{sampled, series, STRAIN_AXIS};
use crate::material_point::{
    MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, ReferenceCurve, Selector,
    Targets,
};
use crate::reference::concrete::{hordijk_softening, mc2010_bilinear_softening};
use crate::report::format::num;

/// Uniaxial tension at each element size: `h int sigma d eps` against GF, curves against strain
/// and against the crack opening `w = h (eps - sigma / E)`.
pub(super) fn crack_band(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
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
