//! The isotropy experiment: the model's update and elastic stiffness against Hooke's law in
//! random strain directions.

use crate::material_point::MaterialPointError;
use impact_solver::material::microplane::experiments::isotropy_error;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters, SphereRule};
use impact_solver::rng::SplitMix64;

use super::{value, ISOTROPY_SAMPLES, ISOTROPY_STRAIN, MPA};
use crate::material_point::plots::series;
use crate::material_point::{
    rule_name, MaterialPlot, MaterialPointSpec, Outcome, Quantity, RecordTable, Selector, Targets,
};
use crate::report::format::num;

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
pub(super) fn isotropy(
    mp: &MaterialPointSpec,
    params: &MicroplaneParameters,
    targets: &Targets,
    out: &mut Outcome,
) -> Result<(), MaterialPointError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hooke_gives_e_in_uniaxial_stress() {
        let (e, nu) = (30e9, 0.18);
        let s = hooke(e, nu, &[1e-4, -nu * 1e-4, -nu * 1e-4, 0.0, 0.0, 0.0]);
        assert!((s[0] - e * 1e-4).abs() < 1e-9 * e * 1e-4);
        assert!(s[1].abs() < 1e-9 * s[0]);
    }
}
