//! The plots of a beam case: from its history the energy transformation, contact force, support
//! reactions, the force components of (6.48) and a static load-displacement curve; from its
//! record the bending-crack tips against time.

use impact_solver::problem::Problem;
use impact_solver::scene::{Analysis, Scene};
use impact_solver::Vector3;

use super::{BeamRecord, BEAM_BODY};
use crate::report::format::{self, num};
use crate::results::{PlotData, Series};
use impact_solver::analysis::Execution;
use impact_solver::output::HistoryTable;

/// The plots of a beam case from its history: energy transformation, contact force, support
/// reactions, the force components of (6.48), and a static load-displacement curve.
pub(super) fn plots(
    scene: &Scene,
    problem: &Problem,
    run: &Execution,
    existing: &[PlotData],
) -> Vec<PlotData> {
    let Some(history) = &run.history else {
        return Vec::new();
    };
    let Some(time) = history.column("time") else {
        return Vec::new();
    };
    let h = TimeHistories {
        history,
        time,
        existing,
    };
    let contact = contact_column(problem, run);
    let reactions: Vec<String> = support_names(problem)
        .iter()
        .map(|n| format!("{n}_reaction_y"))
        .filter(|c| h.has(c))
        .collect();
    [
        energy_plot(problem, &h),
        contact.as_ref().and_then(|c| contact_force_plot(&h, c)),
        reactions_plot(&h, &reactions),
        contact
            .as_ref()
            .and_then(|c| force_components_plot(scene, problem, &h, c, &reactions)),
        load_displacement_plot(&h),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// A run's history columns against time, with the plots the case draws already (`existing`),
/// which the beam's plots do not draw again.
struct TimeHistories<'a> {
    history: &'a HistoryTable,
    /// The `time` column (s).
    time: Vec<f64>,
    existing: &'a [PlotData],
}

impl TimeHistories<'_> {
    /// Whether the history has column `c`.
    fn has(&self, c: &str) -> bool {
        self.history.columns().iter().any(|x| x == c)
    }

    /// `y` against time, named `name`.
    fn series(&self, name: &str, y: Vec<f64>) -> Series {
        Series {
            name: name.to_string(),
            x: self.time.clone(),
            y,
        }
    }

    /// Column `c` against time, named after it.
    fn column(&self, c: &str) -> Option<Series> {
        self.history.column(c).map(|y| self.series(c, y))
    }

    /// Whether a plot of the case already shows every one of `names`.
    fn already(&self, names: &[String]) -> bool {
        self.existing
            .iter()
            .any(|p| names.iter().all(|n| p.series.iter().any(|s| &s.name == n)))
    }
}

/// A plot against time.
fn time_plot(title: &str, y_label: &str, series: Vec<Series>) -> PlotData {
    PlotData {
        title: title.to_string(),
        x_label: "time (s)".into(),
        y_label: y_label.to_string(),
        series,
        reference_lines: Vec::new(),
        log_log: false,
    }
}

/// Energy transformation: the kinetic energies of the bodies, the internal and friction work
/// and their sum (thesis Figs 10.11-10.14); none without a kinetic energy and one more column.
fn energy_plot(problem: &Problem, h: &TimeHistories) -> Option<PlotData> {
    let mut energy_columns: Vec<String> = problem
        .model
        .bodies
        .iter()
        .map(|b| format!("{}_kinetic", b.name))
        .filter(|c| h.has(c))
        .collect();
    energy_columns.extend(
        ["internal_work", "friction_work"]
            .into_iter()
            .filter(|c| h.has(c))
            .map(String::from),
    );
    if !(energy_columns.len() >= 2 && energy_columns.iter().any(|c| c.ends_with("_kinetic"))) {
        return None;
    }
    let mut curves: Vec<Series> = energy_columns.iter().filter_map(|c| h.column(c)).collect();
    let total: Vec<f64> = (0..h.time.len())
        .map(|k| curves.iter().map(|s| s.y[k]).sum())
        .collect();
    let total_name = if h.has("external_work") {
        "total = sum (external work, e.g. gravity, not included)"
    } else {
        "total = sum"
    };
    curves.push(h.series(total_name, total));
    Some(time_plot(
        "Energy transformation (thesis Figs 10.11-10.14)",
        "energy (J)",
        curves,
    ))
}

/// The contact force of column `contact`, beam on impactor (thesis Fig. 10.15), unless the case
/// draws it.
fn contact_force_plot(h: &TimeHistories, contact: &String) -> Option<PlotData> {
    if h.already(std::slice::from_ref(contact)) {
        return None;
    }
    let s = h.column(contact)?;
    Some(time_plot(
        "Contact force, beam on impactor (thesis Fig. 10.15)",
        "force (N)",
        vec![s],
    ))
}

/// The support reactions (thesis Fig. 10.17), unless the case draws them.
fn reactions_plot(h: &TimeHistories, reactions: &[String]) -> Option<PlotData> {
    if reactions.is_empty() || h.already(reactions) {
        return None;
    }
    Some(time_plot(
        "Support reactions (thesis Fig. 10.17)",
        "force (N)",
        reactions.iter().filter_map(|c| h.column(c)).collect(),
    ))
}

/// The force components of (6.48) on the beam in y (thesis Fig. 10.16): inertial `dp/dt`,
/// internal (minus the support reactions), mass-proportional damping, their sum, and the contact
/// force on the beam, which the sum balances with the beam's weight. Needs the beam's momentum,
/// the reactions and three records.
fn force_components_plot(
    scene: &Scene,
    problem: &Problem,
    h: &TimeHistories,
    contact: &str,
    reactions: &[String],
) -> Option<PlotData> {
    let (history, time) = (h.history, &h.time);
    let p = history.column(&format!("{BEAM_BODY}_momentum_y"))?;
    if reactions.is_empty() || time.len() < 3 {
        return None;
    }
    let contact_on_beam: Vec<f64> = history
        .column(contact)
        .unwrap_or_default()
        .iter()
        .map(|f| -f)
        .collect();
    let inertial = central_differences(time, &p);
    let internal: Vec<f64> = (0..time.len())
        .map(|k| {
            -reactions
                .iter()
                .filter_map(|r| history.column(r))
                .map(|y| y[k])
                .sum::<f64>()
        })
        .collect();
    let damping_coefficient = match &scene.analysis {
        Analysis::Explicit(s) => s.settings.damping,
        Analysis::Release { explicit, .. } => explicit.settings.damping,
        Analysis::Static(_) => 0.0,
    };
    // Mass-proportional damping C = a M: its resultant on the beam is a p.
    let damping: Vec<f64> = p.iter().map(|p| damping_coefficient * p).collect();
    let sum: Vec<f64> = (0..time.len())
        .map(|k| inertial[k] + internal[k] + damping[k])
        .collect();
    let damping_name = if damping_coefficient == 0.0 {
        "damping (none in this scene: 0)".to_string()
    } else {
        format!("damping a p (a = {} 1/s)", num(damping_coefficient))
    };
    // The beam's weight: the components balance contact plus weight.
    let beam = &problem.model.bodies[problem.model.body_index(BEAM_BODY).unwrap_or(0)];
    let beam_mass: f64 = problem.model.mass[beam.nodes.clone()].iter().sum();
    let weight = problem.gravity.map_or(0.0, |g| g.y * beam_mass);
    let sum_name = if weight == 0.0 {
        "inertial + internal + damping".to_string()
    } else {
        format!(
            "inertial + internal + damping (= contact + weight {} kN)",
            format::num(weight / 1e3)
        )
    };
    let title = "Forces on the beam in y, (6.48) (thesis Fig. 10.16)";
    Some(time_plot(
        title,
        "force (N)",
        vec![
            h.series("inertial dp/dt", inertial),
            h.series("internal = -sum of reactions", internal),
            h.series(&damping_name, damping),
            h.series(&sum_name, sum),
            h.series("contact on beam", contact_on_beam),
        ],
    ))
}

/// Static load against mid-span displacement (thesis Fig. 10.5), unless the case draws it.
fn load_displacement_plot(h: &TimeHistories) -> Option<PlotData> {
    let load = h.history.column("load_plate_reaction_y")?;
    let disp = h.history.column("midspan_y")?;
    if h.existing.iter().any(|p| p.x_label.contains("midspan_y")) {
        return None;
    }
    Some(PlotData {
        title: "Load against mid-span displacement (thesis Fig. 10.5)".into(),
        x_label: "midspan_y (m)".into(),
        y_label: "load_plate_reaction_y (N)".into(),
        series: vec![Series {
            name: "load plate reaction".into(),
            x: disp,
            y: load,
        }],
        reference_lines: Vec::new(),
        log_log: false,
    })
}

/// The bending-crack tips against time: the heights the cohesive and the traction-free tip
/// have reached, with the initiation length; none before any crack. Their speeds are windowed
/// readings with a resolution, given in the crack table, not a curve.
pub(super) fn tip_plots(record: &BeamRecord) -> Vec<PlotData> {
    let Some(tip) = &record.crack_tip else {
        return Vec::new();
    };
    if !tip.cohesive.iter().any(|h| h.is_finite()) {
        return Vec::new();
    }
    let series = |name: &str, y: &[f64]| crate::results::Series {
        name: name.into(),
        x: tip.times.clone(),
        y: y.to_vec(),
    };
    let line = |label: &str, y: f64| crate::results::ReferenceLine {
        label: label.into(),
        y,
        band: None,
    };
    let mut lines = vec![line("beam height", record.size[1])];
    if let Some(i) = tip.initiation {
        lines.push(line("initiation length", i.length));
    }
    vec![PlotData {
        title: "Bending-crack tips: height reached (cohesive at w_p, traction-free at w_cr / 2)"
            .into(),
        x_label: "time (s)".into(),
        y_label: "height above the bottom face (m)".into(),
        series: vec![
            series("cohesive tip", &tip.cohesive),
            series("traction-free tip", &tip.traction_free),
        ],
        reference_lines: lines,
        log_log: false,
    }]
}

/// Names of the constraints that hold bottom nodes of the beam over a stretch of x (the supports,
/// not pins at single nodes).
fn support_names(problem: &Problem) -> Vec<String> {
    let model = &problem.model;
    let Some(body) = model.body_index(BEAM_BODY) else {
        return Vec::new();
    };
    let b = &model.bodies[body];
    let (lo, hi) = bounds(&model.reference[b.nodes.clone()]);
    let tol = 1e-6 * (hi.y - lo.y).max(f64::MIN_POSITIVE);
    problem
        .constraints
        .iter()
        .filter(|c| {
            c.nodes.len() > 1
                && c.nodes.iter().all(|&n| {
                    b.nodes.contains(&(n as usize)) && model.reference[n as usize].y < lo.y + tol
                })
        })
        .map(|c| c.name.clone())
        .collect()
}

/// `dy/dt` by central differences (one-sided at the ends).
pub fn central_differences(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len().min(y.len());
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            if b == a {
                0.0
            } else {
                (y[b] - y[a]) / (t[b] - t[a])
            }
        })
        .collect()
}

/// Lower and upper corners of a point cloud.
pub(super) fn bounds(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    points.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// The history column of the vertical contact force of the first pair with the beam.
pub(super) fn contact_column(problem: &Problem, run: &Execution) -> Option<String> {
    let history = run.history.as_ref()?;
    problem
        .contact
        .iter()
        .map(|p| format!("{}_force_y", p.name))
        .chain(std::iter::once("impact_force_y".to_string()))
        .find(|c| history.columns().contains(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn central_differences_of_a_line_are_its_slope() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 3.0, 5.0, 7.0];
        assert_eq!(central_differences(&t, &y), vec![2.0; 4]);
    }
}
