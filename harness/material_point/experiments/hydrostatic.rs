//! The hydrostatic experiment: compression and unloading, damage, compaction and the work
//! given back.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::hydrostatic_compression;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};

use super::{note_stop, value, work, HYDROSTATIC_END, HYDROSTATIC_STEPS, MPA, PER_MILLE};
use crate::material_point::plots::series;
use crate::material_point::{
    MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, Selector,
};
use crate::reference::concrete::microplane_hydrostatic_returned_fraction;
use crate::report::format::num;

/// Hydrostatic compression and unloading: damage, and compaction then stiffening of the
/// secant bulk modulus.
pub(super) fn hydrostatic(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    h: f64,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
    let model = MicroplaneConcrete::new(*params)?;
    let end = mp.end.unwrap_or(HYDROSTATIC_END);
    let steps = mp.steps.unwrap_or(HYDROSTATIC_STEPS);
    out.setup.push(format!(
        "all normal strains to -{} (volumetric strain -{}) in {steps} increments and back",
        num(end),
        num(3.0 * end)
    ));
    let (curve, damaged) = hydrostatic_compression(&model, h, end, steps)?;
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
