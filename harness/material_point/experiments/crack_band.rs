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
use crate::results::Series;

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
    // w1 = GF / ft of the case's softening reference (mm), where MC2010 and Hordijk are compared.
    let reference = mp.reference_curves.iter().find_map(|c| match *c {
        ReferenceCurve::Mc2010Softening { f_t, g_f }
        | ReferenceCurve::Hordijk1991Softening { f_t, g_f } => Some((f_t, g_f)),
        _ => None,
    });
    let mut sizes = SizeRecords::default();
    for &h in &mp.element_sizes {
        let run = SizeRun {
            model: &model,
            h,
            rate,
            e: params.youngs_modulus,
        };
        run.record(mp, params, targets, reference, &mut sizes, out)?;
    }
    let strain_plot = sizes.strain_curves.into_iter().fold(
        MaterialPlot::new(
            "Crack band: stress-strain (to 1 % of the peak)",
            STRAIN_AXIS,
            "stress [MPa]",
        ),
        MaterialPlot::curve,
    );
    let opening_plot = sizes.opening_curves.into_iter().fold(
        MaterialPlot::new(
            "Crack band: stress against crack opening",
            "crack opening w = h (eps - sigma/E) [mm]",
            "stress [MPa]",
        ),
        MaterialPlot::curve,
    );
    let opening_plot = softening_references(mp, opening_plot);
    if let Some((f_t, g_f)) = reference {
        out.tables.push(shape_table(f_t, g_f, sizes.shape_rows));
    }
    let energy_plot = energy_plot(mp, targets, &sizes.energies);
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
        rows: sizes.rows,
        note: "Each path runs until the stress has fallen below 1e-3 of its peak; the tail \
               beyond is left out of the energy."
            .into(),
    });
    out.plots.extend([strain_plot, opening_plot, energy_plot]);
    Ok(())
}

/// What the element sizes add up to: the rows of the two tables, the energies, and the curves
/// of the two plots of stress.
#[derive(Default)]
struct SizeRecords {
    /// Rows of the table per element size.
    rows: Vec<Vec<String>>,
    /// Rows of the softening-shape table (with a softening reference only).
    shape_rows: Vec<Vec<String>>,
    /// `(h [mm], h int sigma d eps [N/mm])` per element size.
    energies: Vec<(f64, f64)>,
    /// Curves of stress against strain (MPa against per mille), one per size.
    strain_curves: Vec<Series>,
    /// Curves of stress against crack opening (MPa against mm), one per size.
    opening_curves: Vec<Series>,
}

/// The tension path of one element size.
struct SizeRun<'a> {
    /// The material.
    model: &'a MicroplaneConcrete,
    /// Element size (m).
    h: f64,
    /// Axial strain rate (1/s).
    rate: f64,
    /// Young's modulus (Pa), which separates the crack opening from the elastic strain.
    e: f64,
}

impl SizeRun<'_> {
    /// Runs the path and records it: its values (into `out`), its row, its energy, its softening
    /// shape at `w1 = GF / ft` of the case's softening `reference` (`(f_t, g_f)`), and its
    /// curves down to 1 % of the peak.
    fn record(
        &self,
        mp: &MaterialPointSpec,
        params: &MicroplaneParameters,
        targets: &Targets,
        reference: Option<(f64, f64)>,
        sizes: &mut SizeRecords,
        out: &mut Outcome,
    ) -> Result<(), MaterialPointError> {
        let (h, e) = (self.h, self.e);
        let at = Selector {
            element_size: Some(h),
            ..Selector::default()
        };
        let (curve, values) = tension_run(
            self.model,
            h,
            self.rate,
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
        sizes.energies.push((h * 1e3, gf));
        let target = targets.reference(Quantity::FractureEnergy, &at);
        sizes.rows.push(vec![
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
            sizes.shape_rows.push(vec![
                num(h * 1e3),
                format!("{:.4}", shape.stress_ratio_at_w1),
                format!("{:.4}", shape.opening_at_one_percent * 1e3),
            ]);
        }
        self.draw(&curve, sizes);
        Ok(())
    }

    /// Adds the path's curves against strain and against the crack opening to the plots.
    fn draw(&self, curve: &Curve, sizes: &mut SizeRecords) {
        let (h, e) = (self.h, self.e);
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
        sizes
            .strain_curves
            .push(series(name.clone(), &axial_points(&shown, 1.0)));
        let opening: Vec<(f64, f64)> = shown
            .points
            .iter()
            .map(|p| (h * 1e3 * (p.strain[0] - p.stress[0] / e), p.stress[0] / MPA))
            .collect();
        sizes.opening_curves.push(series(name, &opening));
    }
}

/// The case's softening laws (MC2010 bilinear, Hordijk 1991) drawn on the opening plot.
fn softening_references(mp: &MaterialPointSpec, mut opening_plot: MaterialPlot) -> MaterialPlot {
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
    opening_plot
}

/// The softening shape of each element size (`shape_rows`) with the rows of MC2010 and Hordijk
/// for `f_t` (MPa) and `g_f` (N/mm): the stress at `w1 = GF / ft` and the opening where the
/// stress falls to 1 % of ft.
fn shape_table(f_t: f64, g_f: f64, mut shape_rows: Vec<Vec<String>>) -> RecordTable {
    let w1 = g_f / f_t;
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
    RecordTable {
        title: "Crack band: softening shape against MC2010 and Hordijk".into(),
        head: vec![
            "h [mm]".into(),
            format!("sigma / ft at w1 = GF/ft = {w1:.4} mm"),
            "w at 1 % of ft [mm]".into(),
        ],
        rows: shape_rows,
        note: "Crack opening w = h (eps - sigma/E) after the peak; sigma / ft with the model's \
               own peak as ft."
            .into(),
    }
}

/// `h int sigma d eps` over the element sizes, with the target GF and its band where the case
/// judges the first size.
fn energy_plot(mp: &MaterialPointSpec, targets: &Targets, energies: &[(f64, f64)]) -> MaterialPlot {
    let mut energy_plot = MaterialPlot::new(
        "Crack band: h int sigma d eps per element size",
        "element size h [mm]",
        "h int sigma d eps [N/mm]",
    )
    .curve(series("model", energies));
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
    energy_plot
}
