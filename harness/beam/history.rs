//! Checks on history columns for the beam cases: quasi-static loading, elastic stiffness, peak
//! ratios, and the force balance of a body (thesis 6.48).

/// Why a history check has no value: the history is too short, a column is zero, or a force
/// is named wrongly. Each message says what to change in the case (the column, the window or
/// the run's length).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HistoryError {
    /// Both reactions are zero over the window: nothing to compare.
    #[error("both reactions stay zero in the window")]
    ReactionsZero,
    /// The contact force stays zero.
    #[error("the contact force never rises above zero")]
    ContactNeverRises,
    /// The contact force stays above `fraction` of its peak to the end of the run.
    #[error(
        "the contact force never falls below {fraction} of its peak {peak:.4e} N after it: the \
         contact lasts to the end of the run"
    )]
    ContactNeverEnds {
        /// The fraction of the peak the force must fall below.
        fraction: f64,
        /// The peak contact force (N).
        peak: f64,
    },
    /// The internal work is never positive.
    #[error("the internal work never becomes positive")]
    WorkNeverPositive,
    /// The force column is zero throughout.
    #[error("the force is zero throughout")]
    ForceZero,
    /// The force reaches the fit's end at the first record.
    #[error("the force reaches {fraction} of its peak at the first record: no points to fit")]
    NoPointsToFit {
        /// The fraction of the peak that ends the fit.
        fraction: f64,
    },
    /// The displacement is constant over the fit.
    #[error("the displacement does not change before the fit's end")]
    DisplacementConstant,
    /// No condition or reaction probe of that name.
    #[error("no boundary condition and no `quantity: reaction` probe named `{name}`")]
    NoForceNamed {
        /// The name looked for.
        name: String,
    },
    /// The nodes of a force do not lie on one line `x = const`.
    #[error(
        "`{name}` has nodes from x = {lo} to {hi} m: a bending moment needs each force on one \
         line of nodes; split it into lines of constant x (conditions or reaction probes)"
    )]
    ForceNotOnALine {
        /// The condition or probe.
        name: String,
        /// Its smallest node x (m).
        lo: f64,
        /// Its largest node x (m).
        hi: f64,
    },
    /// A moment without forces.
    #[error("no forces given")]
    NoForces,
    /// The forces of a moment lie on both sides of its section.
    #[error("the forces lie on both sides of the section x = {section_x}: name those of one side")]
    ForcesOnBothSides {
        /// The section (m).
        section_x: f64,
    },
    /// The history has no record.
    #[error("empty history")]
    Empty,
    /// The load stays above `fraction` of its peak to the end of the run.
    #[error("the load never falls below {fraction} of its peak after it: run longer")]
    LoadNeverFalls {
        /// The fraction of the peak the load must fall below.
        fraction: f64,
    },
    /// The denominator of a ratio is zero.
    #[error("the denominator column is zero throughout")]
    DenominatorZero,
    /// Fewer than three records.
    #[error("fewer than three records: no central difference")]
    TooFewRecords,
    /// The contact force is zero throughout.
    #[error("the contact force is zero throughout")]
    ContactZero,
}

/// `max |l - r| / max(|l|, |r|)` over the records of two reaction histories.
pub fn reaction_asymmetry(left: &[f64], right: &[f64]) -> Result<f64, HistoryError> {
    let scale = left.iter().chain(right).fold(0.0f64, |a, v| a.max(v.abs()));
    if !(scale > 0.0) {
        return Err(HistoryError::ReactionsZero);
    }
    Ok(left
        .iter()
        .zip(right)
        .fold(0.0f64, |a, (l, r)| a.max((l - r).abs()))
        / scale)
}

/// End of the contact (s): the first time after the peak of `|force|` at which `|force|` falls
/// below `fraction` of that peak, interpolated linearly between the two records around it
/// (thesis 10.3.2.1 judges the failure mode "up to the moment when the beam-hammer contact force
/// drops approximately to zero"). An error when the force never rises or never falls that low.
pub fn contact_end_time(time: &[f64], force: &[f64], fraction: f64) -> Result<f64, HistoryError> {
    let magnitude: Vec<f64> = force.iter().map(|f| f.abs()).collect();
    let (peak_at, peak) = magnitude
        .iter()
        .copied()
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (i, f)| if f > best.1 { (i, f) } else { best },
        );
    if !(peak > 0.0) {
        return Err(HistoryError::ContactNeverRises);
    }
    let level = fraction * peak;
    let end = (peak_at + 1..magnitude.len())
        .find(|&i| magnitude[i] < level)
        .ok_or(HistoryError::ContactNeverEnds { fraction, peak })?;
    let (f0, f1) = (magnitude[end - 1], magnitude[end]);
    Ok(time[end - 1] + (f0 - level) / (f0 - f1) * (time[end] - time[end - 1]))
}

/// `max K_i / W_i` over the records where the internal work `W_i` exceeds `fraction` of its
/// largest value: a loading is quasi-static when the kinetic energy `K` stays a small part of
/// the work stored (CATALOGUE, `beam/static-3pt`: below 1 %). The first records, where `W` is
/// still near zero, are left out so that the ratio is not a quotient of two round-offs.
pub fn kinetic_over_internal_work(
    kinetic: &[f64],
    work: &[f64],
    fraction: f64,
) -> Result<f64, HistoryError> {
    let peak = work.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(peak > 0.0) {
        return Err(HistoryError::WorkNeverPositive);
    }
    Ok(kinetic
        .iter()
        .zip(work)
        .filter(|(_, w)| **w > fraction * peak)
        .map(|(k, w)| k / w)
        .fold(f64::NEG_INFINITY, f64::max))
}

/// Least-squares slope `sum (d - d_m)(F - F_m) / sum (d - d_m)^2` of `force` against
/// `displacement` over the records up to the first at which `|force|` reaches `fraction` of
/// its largest absolute value: the secant (elastic) stiffness before cracking.
pub fn secant_stiffness(
    force: &[f64],
    displacement: &[f64],
    fraction: f64,
) -> Result<f64, HistoryError> {
    let peak = force.iter().fold(0.0f64, |a, f| a.max(f.abs()));
    if !(peak > 0.0) {
        return Err(HistoryError::ForceZero);
    }
    let end = force
        .iter()
        .position(|f| f.abs() >= fraction * peak)
        .unwrap_or(force.len() - 1);
    let n = end + 1;
    if n < 2 {
        return Err(HistoryError::NoPointsToFit { fraction });
    }
    crate::curve::least_squares_slope(&displacement[..n], &force[..n])
        .ok_or(HistoryError::DisplacementConstant)
}

/// A line force of the moment measure: the history column of its y force and the x of its
/// line of nodes. `name` is a boundary condition (its column `<name>_reaction_y`) or a probe of
/// `quantity: reaction` (column `<name>_y`): the part of a condition's reaction carried by one
/// line of its nodes. An error if the nodes do not lie on one line `x = const` (to 1e-9 m).
pub fn force_line(
    problem: &impact_solver::problem::Problem,
    name: &str,
) -> Result<(String, f64), HistoryError> {
    use impact_solver::model::ProbeQuantity;
    let (nodes, column) = if let Some(c) = problem.constraints.iter().find(|c| c.name == name) {
        (&c.nodes, format!("{name}_reaction_y"))
    } else if let Some(p) = problem
        .probes
        .iter()
        .find(|p| p.name == name && p.quantity == ProbeQuantity::Reaction)
    {
        (&p.nodes, format!("{name}_y"))
    } else {
        return Err(HistoryError::NoForceNamed { name: name.into() });
    };
    let xs: Vec<f64> = nodes
        .iter()
        .map(|&n| problem.model.reference[n as usize].x)
        .collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if xs.is_empty() || hi - lo > 1e-9 {
        return Err(HistoryError::ForceNotOnALine {
            name: name.into(),
            lo,
            hi,
        });
    }
    Ok((column, lo))
}

/// Largest |M| over the records of `M_i = sum_c R_c,i (section_x - x_c)`, the moment about the
/// z axis at the section `x = section_x` of the forces `R_c` (y reactions, one column each)
/// acting at `x_c` on one side of it (statics of the free body cut at the section). An error
/// if the forces lie on both sides.
pub fn peak_bending_moment(
    section_x: f64,
    forces: &[(Vec<f64>, f64)],
) -> Result<f64, HistoryError> {
    if forces.is_empty() {
        return Err(HistoryError::NoForces);
    }
    let left = forces.iter().all(|(_, x)| *x <= section_x);
    let right = forces.iter().all(|(_, x)| *x >= section_x);
    if !(left || right) {
        return Err(HistoryError::ForcesOnBothSides { section_x });
    }
    let records = forces.iter().map(|(f, _)| f.len()).min().unwrap_or(0);
    Ok((0..records)
        .map(|i| {
            forces
                .iter()
                .map(|(f, x)| f[i] * (section_x - x))
                .sum::<f64>()
                .abs()
        })
        .fold(0.0, f64::max))
}

/// Number of records of the quasi-static branch of a load history: up to and including the
/// largest |load|, or with `after_peak_down_to = Some(f)` on to the first record after the peak
/// where |load| falls below `f` times its peak (an error if it never does: the run is too
/// short).
pub fn records_through_peak(
    load: &[f64],
    after_peak_down_to: Option<f64>,
) -> Result<usize, HistoryError> {
    let peak = (0..load.len())
        .max_by(|&a, &b| load[a].abs().total_cmp(&load[b].abs()))
        .ok_or(HistoryError::Empty)?;
    let end = match after_peak_down_to {
        None => peak,
        Some(f) => {
            let bound = f * load[peak].abs();
            (peak..load.len())
                .find(|&i| load[i].abs() < bound)
                .ok_or(HistoryError::LoadNeverFalls { fraction: f })?
        }
    };
    Ok(end + 1)
}

/// `max |numerator| / max |denominator|`.
pub fn peak_ratio(numerator: &[f64], denominator: &[f64]) -> Result<f64, HistoryError> {
    let max_abs = |y: &[f64]| y.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let den = max_abs(denominator);
    if !(den > 0.0) {
        return Err(HistoryError::DenominatorZero);
    }
    Ok(max_abs(numerator) / den)
}

/// Time of the largest |column| minus the time of the largest |after|: positive when `column`
/// peaks later.
pub fn peak_time_lag(time: &[f64], column: &[f64], after: &[f64]) -> Result<f64, HistoryError> {
    let at = |y: &[f64]| {
        (0..y.len())
            .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
            .map(|i| time[i])
            .ok_or(HistoryError::Empty)
    };
    Ok(at(column)? - at(after)?)
}

/// The force balance of a body, thesis (6.48) summed over its nodes:
/// `F_contact + m g + sum R - dp/dt = 0`, with `F_contact = -contact_on_other` (the recorded
/// contact force is the one the body exerts on the other one), `R` the reactions of its
/// constraints and `p` its momentum, all along one axis. `dp/dt` is the central difference
/// `(p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1})` at the interior records; that difference is
/// exactly the mean of `dp/dt` over `[t_{i-1}, t_{i+1}]`, so it is compared with the mean of the
/// forces over the same window (trapezoidal rule), not with their value at `t_i`: a force that
/// switches on between two records (the first contact) then costs a second-order error instead
/// of a spurious residual of half the force. Returns `max_i |residual_i| /
/// max_i |contact_on_other_i|`.
pub fn force_equilibrium_error(
    time: &[f64],
    contact_on_other: &[f64],
    reactions: &[Vec<f64>],
    momentum: &[f64],
    weight: f64,
) -> Result<f64, HistoryError> {
    let n = time.len();
    if n < 3 {
        return Err(HistoryError::TooFewRecords);
    }
    let scale = contact_on_other.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if !(scale > 0.0) {
        return Err(HistoryError::ContactZero);
    }
    let force =
        |i: usize| -contact_on_other[i] + weight + reactions.iter().map(|c| c[i]).sum::<f64>();
    let worst = (1..n - 1)
        .map(|i| {
            let window = time[i + 1] - time[i - 1];
            let dp = (momentum[i + 1] - momentum[i - 1]) / window;
            let mean = ((time[i] - time[i - 1]) * (force(i - 1) + force(i))
                + (time[i + 1] - time[i]) * (force(i) + force(i + 1)))
                / (2.0 * window);
            (mean - dp).abs()
        })
        .fold(0.0, f64::max);
    Ok(worst / scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_through_the_peak_and_down_to_a_fraction_after_it() {
        let load = [0.0, -1.0, -3.0, -4.0, -3.5, -2.9, -1.0];
        assert_eq!(records_through_peak(&load, None).unwrap(), 4);
        // 80 % of 4 is 3.2: the first record below it after the peak is -2.9, the sixth.
        assert_eq!(records_through_peak(&load, Some(0.8)).unwrap(), 6);
        assert!(records_through_peak(&load, Some(0.1)).is_err());
        assert!(records_through_peak(&[], None).is_err());
    }

    /// A moment's forces come from boundary conditions (column `<name>_reaction_y`) or from
    /// reaction probes (column `<name>_y`), each on one line of nodes of constant x; a
    /// displacement probe, an unknown name or a set spread in x is refused.
    #[test]
    fn force_lines_from_conditions_and_reaction_probes() {
        let scene = impact_solver::scene::Scene::from_yaml(
            "name: bar
bodies:
  - name: bar
    mesh: { box: { origin: [0, 0, 0], size: [0.2, 0.1, 0.1], divisions: [2, 1, 1] } }
    material: { linear_elastic: { density: 2400, youngs_modulus: 3.0e10, poisson_ratio: 0.2 } }
boundary_conditions:
  - { name: end, body: bar, nodes: { box: { min: [0, 0, 0], max: [0, 0.1, 0.1] } }, motion: { fixed: [x, y, z] } }
  - { name: strip, body: bar, nodes: { box: { min: [0, 0, 0], max: [0.1, 0, 0.1] } }, motion: { fixed: [y] } }
probes:
  - { name: middle, body: bar, nodes: { box: { min: [0.1, 0, 0], max: [0.1, 0, 0.1] } }, quantity: reaction }
  - { name: moved, body: bar, nodes: { box: { min: [0.1, 0, 0], max: [0.1, 0, 0.1] } }, quantity: displacement }
analysis:
  explicit: { end_time: 1.0e-6 }
",
            "bar.yaml",
        )
        .unwrap();
        let problem = impact_solver::scene::build_problem(&scene).unwrap();
        assert_eq!(
            force_line(&problem, "end").unwrap(),
            ("end_reaction_y".to_string(), 0.0)
        );
        let (column, x) = force_line(&problem, "middle").unwrap();
        assert_eq!(column, "middle_y");
        assert!((x - 0.1).abs() < 1e-12);
        assert!(force_line(&problem, "strip")
            .unwrap_err()
            .to_string()
            .contains("split it into lines"));
        assert!(force_line(&problem, "moved")
            .unwrap_err()
            .to_string()
            .contains("no boundary condition"));
        assert!(force_line(&problem, "nothing").is_err());
    }

    #[test]
    fn quasi_static_ratio_skips_the_start() {
        let w = [0.0, 1e-9, 1.0, 5.0, 10.0];
        let k = [0.0, 1e-6, 0.01, 0.02, 0.05];
        // At 5 %: records with W > 0.5: 0.01/1, 0.02/5, 0.05/10.
        assert!((kinetic_over_internal_work(&k, &w, 0.05).unwrap() - 0.01).abs() < 1e-15);
        assert!(kinetic_over_internal_work(&k, &[0.0; 5], 0.05).is_err());
    }

    #[test]
    fn bending_moment_of_a_simply_supported_beam() {
        // Point load 2P at mid-span x = 1 of a 2 m span: reactions P at x = 0 and 2; at the
        // section under the load M = P * 1 from either side, the load itself at zero lever.
        let p = vec![0.0, 10.0, 20.0, 5.0];
        let load: Vec<f64> = p.iter().map(|v| -2.0 * v).collect();
        let left = [(p.clone(), 0.0), (load.clone(), 1.0)];
        assert_eq!(peak_bending_moment(1.0, &left).unwrap(), 20.0);
        let right = [(p.clone(), 2.0)];
        assert_eq!(peak_bending_moment(1.0, &right).unwrap(), 20.0);
        // A load split over two lines 0.1 m either side of a section at 0.9: the lever of each.
        let half: Vec<f64> = p.iter().map(|v| -v).collect();
        let split = [(p.clone(), 0.0), (half.clone(), 0.8)];
        assert!(
            (peak_bending_moment(0.9, &split).unwrap() - 20.0 * 0.9 + 20.0 * 0.1).abs() < 1e-12
        );
        assert!(peak_bending_moment(1.0, &[(p, 0.0), (half, 1.5)]).is_err());
    }

    #[test]
    fn secant_stiffness_of_a_softening_curve() {
        // Linear at 2e7 N/m up to the peak of 1000 N at 50 um, then softening: with fraction
        // 0.3 the fit sees only records up to the first at or above 300 N (d = 15 um).
        let d: Vec<f64> = (0..100).map(|i| i as f64 * 1e-6).collect();
        let f: Vec<f64> = d
            .iter()
            .map(|d| {
                if *d <= 50e-6 {
                    2e7 * d
                } else {
                    1000.0 - 1e7 * (d - 50e-6)
                }
            })
            .collect();
        let k = secant_stiffness(&f, &d, 0.3).unwrap();
        assert!((k - 2e7).abs() < 1e-3, "{k}");
    }

    #[test]
    fn peak_ratio_and_lag() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let a = [0.0, 1.0, -4.0, 2.0];
        let b = [0.0, 8.0, 2.0, 1.0];
        assert_eq!(peak_ratio(&a, &b).unwrap(), 0.5);
        assert_eq!(peak_time_lag(&t, &a, &b).unwrap(), 1.0);
        assert!(peak_ratio(&a, &[0.0; 4]).is_err());
    }

    #[test]
    fn equilibrium_of_a_body_pushed_down_and_held() {
        // Body of mass 2 under gravity 10: weight -20 N. Contact on the other body +c (so -c on
        // this one), reaction R; momentum p(t) = int (-c + W + R) dt exactly for quadratic p.
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 1e-3).collect();
        let c: Vec<f64> = t.iter().map(|t| 1000.0 * t).collect();
        let r: Vec<f64> = t.iter().map(|t| 300.0 * t + 20.0).collect();
        // -c + W + R = -700 t; p = -350 t^2.
        let p: Vec<f64> = t.iter().map(|t| -350.0 * t * t).collect();
        let e = force_equilibrium_error(&t, &c, std::slice::from_ref(&r), &p, -20.0).unwrap();
        assert!(e < 1e-9, "{e}");
        // A force switching on between two records, with the momentum it gives exactly: the
        // window means match where the force is constant on each side.
        let ts: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let cs: Vec<f64> = ts
            .iter()
            .map(|&t| if t >= 4.0 { 100.0 } else { 0.0 })
            .collect();
        let ps: Vec<f64> = ts.iter().map(|&t| -100.0 * (t - 4.0).max(0.0)).collect();
        let step = force_equilibrium_error(&ts, &cs, &[], &ps, 0.0).unwrap();
        // Trapezoid over [3, 5] gives -75 N mean against -50: 0.25, where the point value
        // would give 0.5.
        assert!((step - 0.25).abs() < 1e-12, "{step}");
        // Forgetting the reaction shows.
        let e = force_equilibrium_error(&t, &c, &[], &p, -20.0).unwrap();
        assert!(e > 0.1);
    }

    #[test]
    fn contact_ends_when_the_force_falls_below_a_fraction_of_its_peak() {
        // A half-sine pulse of 0.5 ms sampled every 10 us, then a later small touch.
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 1e-5).collect();
        let f: Vec<f64> = t
            .iter()
            .map(|&t| {
                if t <= 5e-4 {
                    (std::f64::consts::PI * t / 5e-4).sin() * 1e6
                } else if (7e-4..8e-4).contains(&t) {
                    5e4
                } else {
                    0.0
                }
            })
            .collect();
        // sin falls below 1 % at pi t / T = pi - asin(0.01): the linear interpolation between
        // the records at 490 and 500 us lands within the record spacing of it.
        let exact = 5e-4 * (1.0 - 0.01f64.asin() / std::f64::consts::PI);
        let end = contact_end_time(&t, &f, 0.01).unwrap();
        assert!((end - exact).abs() < 1e-5, "{end} {exact}");
        assert!(end <= 5e-4);
        // The later touch does not move the end; a force that never falls is an error.
        assert!(contact_end_time(&t, &vec![1.0; 100], 0.01).is_err());
        assert!(contact_end_time(&t, &vec![0.0; 100], 0.01).is_err());
    }

    #[test]
    fn reaction_asymmetry_over_the_larger_reaction() {
        assert_eq!(
            reaction_asymmetry(&[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0]).unwrap(),
            0.0
        );
        let a = reaction_asymmetry(&[0.0, 1.0, -4.0], &[0.0, 1.2, -3.9]).unwrap();
        assert!((a - 0.2 / 4.0).abs() < 1e-15);
        assert!(reaction_asymmetry(&[0.0], &[0.0]).is_err());
    }
}
