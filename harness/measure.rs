//! Measurements: numbers taken from a run's histories and final fields.

use impact_solver::material::MaterialModel;
use impact_solver::model::Problem;
use impact_solver::Vector3;
use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use crate::execute::Execution;
use crate::reference::analytic::{corotated_cauchy, svk_cauchy};

/// Nodes a field measure looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NodeScope {
    /// Nodes not on the boundary of the body.
    #[default]
    Interior,
    All,
}

/// Field measured against an affine exact field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldQuantity {
    Displacement,
    Velocity,
}

/// A tensor component in Voigt order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TensorComponent {
    Xx,
    Yy,
    Zz,
    Xy,
    Yz,
    Xz,
}

/// What to measure. Sweep measures (`observed_order`, stability) need a sweep in the case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Measure {
    /// Largest value of a history column.
    HistoryMax { column: String },
    /// Smallest value of a history column.
    HistoryMin { column: String },
    /// Largest |value| of a history column (a peak load whose sign is a convention).
    HistoryPeakMagnitude { column: String },
    /// Last recorded value of a history column.
    /// Last recorded value of a history column, times `scale` (for example `-1 / area` to turn
    /// a contact force into a compressive stress).
    HistoryFinal {
        column: String,
        #[serde(default = "one")]
        scale: f64,
    },
    /// Time of the largest absolute value of a column.
    PeakTime { column: String },
    /// Total time during which the column exceeds `threshold`.
    DurationAbove { column: String, threshold: f64 },
    /// Mean of a column over the time window `[from, to]`.
    PlateauMean { column: String, from: f64, to: f64 },
    /// First time the column reaches `level` (linear interpolation between records).
    ArrivalTime { column: String, level: f64 },
    /// `distance / (t_to - t_from)` from the arrival of `level` at two probes: the front speed.
    FrontSpeed {
        from: String,
        to: String,
        distance: f64,
        level: f64,
    },
    /// Largest |energy balance error| over the run, over the largest energy scale.
    EnergyBalanceError,
    /// Largest |K - K_0| / K_0 over the history: the drift of the kinetic energy.
    KineticEnergyDrift,
    /// Largest |column(t) - column(0)| over the history, divided by `scale` (for example the
    /// drift of the total momentum over one body's initial momentum).
    MaxChange { column: String, scale: f64 },
    /// Largest |v(t) - v(0)| / |v(0)| of the vector whose components are `columns` (for
    /// example the total angular momentum).
    RelativeDrift { columns: [String; 3] },
    /// (kinetic + stored energy) at the end over the initial kinetic energy: the energy left in
    /// the bodies after an impact, elastic vibration included.
    FinalEnergyRatio,
    /// |omega| of a body at the end, from its angular momentum about its centre of mass and its
    /// inertia tensor in the current configuration (`omega = I^-1 L`), times `scale` (for
    /// example `R / v` to make it dimensionless).
    BodySpin {
        body: String,
        #[serde(default = "one")]
        scale: f64,
    },
    /// Largest |field - exact| over the nodes, over the largest |exact|, for the exact field
    /// `scale (translation + gradient (X - center))`, where `scale` is the final time for an
    /// explicit displacement (constant velocity field) and 1 otherwise.
    AffineFieldError {
        quantity: FieldQuantity,
        #[serde(default)]
        translation: [f64; 3],
        gradient: [[f64; 3]; 3],
        #[serde(default)]
        center: [f64; 3],
        #[serde(default)]
        nodes: NodeScope,
    },
    /// Largest relative deviation of any element's Cauchy stress from the exact stress of the
    /// homogeneous deformation `F = I + scale gradient` (scale as in `affine_field_error`).
    UniformStressError { gradient: [[f64; 3]; 3] },
    /// Largest |sigma_ij| over all elements, divided by Young's modulus of its body.
    MaxStressOverModulus,
    /// Mean Cauchy stress component over the elements whose centroid lies in `[min, max]`.
    ElementStressMean {
        component: TensorComponent,
        min: [f64; 3],
        max: [f64; 3],
    },
    /// `(max - min) / |mean|` of a Cauchy stress component over the elements whose centroid
    /// lies in `[min, max]`: the scatter of a stress that should be uniform.
    ElementStressScatter {
        component: TensorComponent,
        min: [f64; 3],
        max: [f64; 3],
    },
    /// Mean Green-Lagrange strain component over all elements.
    ElementStrainMean { component: TensorComponent },
    /// Reaction of a constraint (static: at equilibrium; explicit: the last record), divided by
    /// `divide_by` (for example an area, giving a nominal stress).
    Reaction {
        constraint: String,
        component: TensorAxis,
        #[serde(default = "one")]
        divide_by: f64,
    },
    /// Frequency from the mean spacing of upward zero crossings of a column (Hz).
    ZeroCrossingFrequency { column: String },
    /// Observed convergence order of another metric's error over the sweep.
    ObservedOrder { metric: String },
    /// 1 if every sweep level with time-step factor up to 1 ran stably, else 0.
    StableUpToEstimate,
    /// Smallest time-step factor of the sweep whose run went unstable: the measured stability
    /// limit over the estimate (the largest factor plus one step if none did).
    MeasuredStabilityLimit,
    /// 1 if every unstable level stopped with an instability report (no NaN, no other error).
    UnstableRunsReported,
    /// The contact problems the run recorded, replayed through `solver` at `tolerance` (or
    /// `recorded`: the run's own multipliers); `quantity` is the worst over the problems (see
    /// `crate::replay`).
    ContactReplay {
        solver: String,
        quantity: crate::replay::ReplayQuantity,
        #[serde(default = "replay_tolerance")]
        tolerance: f64,
        /// Only the problems the run's solver converged on.
        #[serde(default)]
        only_converged: bool,
    },
    /// Failure mode of a beam in the final state (FORMULATION 5, thesis 10.3.2), as its code:
    /// 0 none, 1 bending, 2 mixed, 3 shear (`crate::beam::classify`). Judged against
    /// `{ failure_mode: <mode> }` with `absolute: 0`.
    FailureMode(#[serde(default)] crate::beam::BeamSpec),
    /// Largest speed of the bending-crack tip over the snapshots (`crate::beam::
    /// crack_tip_history`) over the Rayleigh speed `c_R` of the beam's elastic constants: a
    /// crack cannot outrun `c_R` (Freund 1990), the thesis finds about 0.55 `c_R`.
    CrackTipSpeedRatio(#[serde(default)] crate::beam::BeamSpec),
    /// `max K / W_int` over the records where `W_int` exceeds `above_fraction` (default 5 %)
    /// of its largest value (`crate::beam::history::kinetic_over_internal_work`).
    KineticOverInternalWork {
        #[serde(default = "kinetic_column")]
        kinetic: String,
        #[serde(default = "internal_work_column")]
        internal_work: String,
        #[serde(default = "five_percent")]
        above_fraction: f64,
        /// Only the records up to the largest |value| of this column (the peak load): past the
        /// peak of a brittle beam the crack releases stored energy as motion whatever the
        /// loading rate, so the quasi-static check belongs to the loading branch.
        #[serde(default)]
        until_peak_of: Option<String>,
        /// With `until_peak_of`: go on past the peak to the first record where that column's
        /// |value| falls below this fraction of its peak (issue 16: quasi-static through the
        /// peak and down to 80 % of it).
        #[serde(default)]
        after_peak_down_to: Option<f64>,
    },
    /// Least-squares slope of `force` against `displacement` up to the first record where
    /// |force| reaches `up_to_fraction` of its peak (`crate::beam::history::secant_stiffness`).
    SecantStiffness {
        force: String,
        displacement: String,
        up_to_fraction: f64,
    },
    /// Largest |bending moment| about the z axis at the section `x = section_x` over the run,
    /// from the y reactions of `conditions`, all on one side of the section: `M = sum_c
    /// R_c (section_x - x_c)`, each named boundary condition or `quantity: reaction` probe on one
    /// line of nodes `x = x_c` (probe a strip or a plate line by line;
    /// `crate::beam::history::peak_bending_moment`). Unlike a load,
    /// it does not depend on where a rigid plate or support strip carries its force, so it
    /// compares with a sectional (hinge) model of the beam.
    PeakBendingMoment {
        section_x: f64,
        conditions: Vec<String>,
        /// Only the records up to the largest |value| of this column (the peak load): after a
        /// brittle beam snaps, inertia forces make the reactions' moment differ from the
        /// section's, so the quasi-static branch alone gives a sectional moment.
        #[serde(default)]
        until_peak_of: Option<String>,
    },
    /// `max |numerator| / max |denominator|` over the history.
    PeakRatio {
        numerator: String,
        denominator: String,
    },
    /// Time of the largest |column| minus that of the largest |after| (s).
    PeakTimeLag { column: String, after: String },
    /// The force balance (6.48) of `body` along y summed over its nodes: `max |-contact + m g_y
    /// + sum reactions - dp/dt| / max |contact|`, with `contact` the force the body exerts on
    /// the other body of the pair, `dp/dt` by central differences of `momentum`, `m` the body's
    /// mass (`crate::beam::history::force_equilibrium_error`).
    ForceEquilibriumError {
        body: String,
        contact: String,
        reactions: Vec<String>,
        momentum: String,
    },
    /// The crack band of a prism run against the material point of its size (`crate::band`):
    /// dissipated energy per crack area, traction-opening deviation.
    CrackBand(crate::band::BandMeasure),
    /// A material-point diagnostic of the band's concrete at its size, no run needed
    /// (`crate::band::PointMeasure`): uniaxial strain, tension with shear (stress locking).
    CrackBandPoint(crate::band::PointMeasure),
}

fn kinetic_column() -> String {
    "kinetic".into()
}

fn internal_work_column() -> String {
    "internal_work".into()
}

fn five_percent() -> f64 {
    0.05
}

fn replay_tolerance() -> f64 {
    1e-10
}

/// A displacement axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TensorAxis {
    X,
    Y,
    Z,
}

fn one() -> f64 {
    1.0
}

impl Measure {
    /// Whether the measure is computed over the levels of a sweep rather than from one run.
    pub fn is_sweep_measure(&self) -> bool {
        matches!(
            self,
            Measure::ObservedOrder { .. }
                | Measure::StableUpToEstimate
                | Measure::MeasuredStabilityLimit
                | Measure::UnstableRunsReported
        )
    }

    /// Evaluates a per-run measure.
    pub fn evaluate(&self, problem: &Problem, run: &Execution) -> Result<f64, String> {
        let history = || {
            run.history
                .as_ref()
                .ok_or("this measure needs an explicit run's history".to_string())
        };
        let column = |name: &str| -> Result<Vec<f64>, String> {
            let h = history()?;
            h.column(name).ok_or_else(|| {
                format!(
                    "the history has no column `{name}`; it has {:?}",
                    h.columns()
                )
            })
        };
        let time = || column("time");
        let explicit_time = run.summary.as_ref().map_or(1.0, |s| s.time);
        Ok(match self {
            Measure::HistoryMax { column: c } => {
                column(c)?.into_iter().fold(f64::NEG_INFINITY, f64::max)
            }
            Measure::HistoryPeakMagnitude { column: c } => {
                column(c)?.into_iter().fold(0.0, |a: f64, x| a.max(x.abs()))
            }
            Measure::HistoryMin { column: c } => {
                column(c)?.into_iter().fold(f64::INFINITY, f64::min)
            }
            Measure::HistoryFinal { column: c, scale } => {
                column(c)?.last().ok_or("empty history")? * scale
            }
            Measure::PeakTime { column: c } => {
                let (t, y) = (time()?, column(c)?);
                let i = (0..y.len())
                    .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                    .ok_or("empty history")?;
                t[i]
            }
            Measure::DurationAbove {
                column: c,
                threshold,
            } => {
                let (t, y) = (time()?, column(c)?);
                (1..y.len())
                    .filter(|&i| y[i] > *threshold)
                    .map(|i| t[i] - t[i - 1])
                    .sum()
            }
            Measure::PlateauMean {
                column: c,
                from,
                to,
            } => {
                let (t, y) = (time()?, column(c)?);
                let window: Vec<f64> = (0..y.len())
                    .filter(|&i| t[i] >= *from && t[i] <= *to)
                    .map(|i| y[i])
                    .collect();
                if window.is_empty() {
                    return Err(format!("no record of `{c}` between t = {from} and {to}"));
                }
                window.iter().sum::<f64>() / window.len() as f64
            }
            Measure::ArrivalTime { column: c, level } => crossing(&time()?, &column(c)?, *level)?,
            Measure::FrontSpeed {
                from,
                to,
                distance,
                level,
            } => {
                let t = time()?;
                distance
                    / (crossing(&t, &column(to)?, *level)? - crossing(&t, &column(from)?, *level)?)
            }
            Measure::EnergyBalanceError => {
                run.summary
                    .as_ref()
                    .ok_or("needs an explicit run")?
                    .max_relative_energy_error
            }
            Measure::KineticEnergyDrift => {
                let k = column("kinetic")?;
                let k0 = k[0];
                if !(k0 > 0.0) {
                    return Err("the initial kinetic energy is zero".into());
                }
                k.iter().map(|x| (x - k0).abs() / k0).fold(0.0, f64::max)
            }
            Measure::MaxChange { column: c, scale } => {
                let y = column(c)?;
                y.iter().map(|x| (x - y[0]).abs()).fold(0.0, f64::max) / scale
            }
            Measure::RelativeDrift { columns } => {
                let c = [
                    column(&columns[0])?,
                    column(&columns[1])?,
                    column(&columns[2])?,
                ];
                let at = |i: usize| Vector3::new(c[0][i], c[1][i], c[2][i]);
                let initial = at(0).norm();
                if initial == 0.0 {
                    return Err("the vector is zero at the start: no relative drift".into());
                }
                (0..c[0].len())
                    .map(|i| (at(i) - at(0)).norm())
                    .fold(0.0, f64::max)
                    / initial
            }
            Measure::FinalEnergyRatio => {
                let (k, w) = (column("kinetic")?, column("stored_energy")?);
                (k[k.len() - 1] + w[w.len() - 1]) / k[0]
            }
            Measure::BodySpin { body, scale } => {
                let b = problem
                    .model
                    .body_index(body)
                    .ok_or_else(|| format!("no body named `{body}`"))?;
                let v = run.v.as_ref().ok_or("needs an explicit run")?;
                let nodes = problem.model.bodies[b].nodes.clone();
                let (mass, x) = (&problem.model.mass, |n: usize| {
                    problem.model.reference[n] + run.u[n]
                });
                let total: f64 = nodes.clone().map(|n| mass[n]).sum();
                let center = nodes
                    .clone()
                    .fold(Vector3::zeros(), |a, n| a + x(n) * mass[n])
                    / total;
                let v_center = nodes
                    .clone()
                    .fold(Vector3::zeros(), |a, n| a + v[n] * mass[n])
                    / total;
                let (mut l, mut inertia) = (Vector3::zeros(), Matrix3::zeros());
                for n in nodes {
                    let r = x(n) - center;
                    l += r.cross(&(v[n] - v_center)) * mass[n];
                    inertia +=
                        (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass[n];
                }
                let omega = inertia
                    .try_inverse()
                    .ok_or("the body's inertia tensor is singular")?
                    * l;
                omega.norm() * scale
            }
            Measure::AffineFieldError {
                quantity,
                translation,
                gradient,
                center,
                nodes,
            } => {
                let (field, scale) = match quantity {
                    FieldQuantity::Displacement => (
                        &run.u,
                        if run.summary.is_some() {
                            explicit_time
                        } else {
                            1.0
                        },
                    ),
                    FieldQuantity::Velocity => {
                        (run.v.as_ref().ok_or("needs an explicit run")?, 1.0)
                    }
                };
                let g = Matrix3::from_row_slice(&gradient.concat());
                let (t, c) = (Vector3::from(*translation), Vector3::from(*center));
                let boundary = boundary_node_flags(problem);
                let exact = |x: &Vector3<f64>| (t + g * (x - c)) * scale;
                let norm = problem
                    .model
                    .reference
                    .iter()
                    .map(|x| exact(x).norm())
                    .fold(0.0, f64::max);
                let mut worst: f64 = 0.0;
                for (n, x) in problem.model.reference.iter().enumerate() {
                    if *nodes == NodeScope::Interior && boundary[n] {
                        continue;
                    }
                    worst = worst.max((field[n] - exact(x)).norm());
                }
                worst / norm
            }
            Measure::UniformStressError { gradient } => {
                let scale = if run.summary.is_some() {
                    explicit_time
                } else {
                    1.0
                };
                let f = Matrix3::identity() + Matrix3::from_row_slice(&gradient.concat()) * scale;
                let fields = run.element_fields(&problem.model);
                let mut worst: f64 = 0.0;
                for (e, s) in fields.cauchy.iter().enumerate() {
                    let exact = match problem.model.material_of(e) {
                        MaterialModel::SaintVenantKirchhoff(c) => svk_cauchy(c, &f),
                        MaterialModel::LinearElastic(c) => corotated_cauchy(c, &f),
                        MaterialModel::Microplane(_) => {
                            return Err("uniform_stress_error has no closed form for microplane \
                                        concrete"
                                .into())
                        }
                    };
                    let diff = matrix_from_voigt(s) - exact;
                    worst = worst.max(max_abs(&diff) / max_abs(&exact));
                }
                worst
            }
            Measure::MaxStressOverModulus => {
                let fields = run.element_fields(&problem.model);
                fields
                    .cauchy
                    .iter()
                    .enumerate()
                    .map(|(e, s)| {
                        s.iter().fold(0.0f64, |a, x| a.max(x.abs()))
                            / problem.model.material_of(e).constants().youngs_modulus
                    })
                    .fold(0.0, f64::max)
            }
            Measure::ElementStressMean {
                component,
                min,
                max,
            } => {
                let values = element_stress_in_box(problem, run, *component, min, max)?;
                values.iter().sum::<f64>() / values.len() as f64
            }
            Measure::ElementStressScatter {
                component,
                min,
                max,
            } => {
                let values = element_stress_in_box(problem, run, *component, min, max)?;
                let mean = values.iter().sum::<f64>() / values.len() as f64;
                let (lo, hi) = values
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                        (lo.min(v), hi.max(v))
                    });
                (hi - lo) / mean.abs()
            }
            Measure::ElementStrainMean { component } => {
                let fields = run.element_fields(&problem.model);
                fields
                    .green_lagrange
                    .iter()
                    .map(|s| s[*component as usize])
                    .sum::<f64>()
                    / fields.green_lagrange.len() as f64
            }
            Measure::Reaction {
                constraint,
                component,
                divide_by,
            } => {
                let c = problem
                    .constraints
                    .iter()
                    .position(|c| &c.name == constraint)
                    .ok_or_else(|| format!("no constraint named `{constraint}`"))?;
                let axis = *component as usize;
                let value = match (&run.static_solution, &run.summary) {
                    (Some(s), None) => s.constraint_reaction(problem, c)[axis],
                    _ => *column(&format!("{constraint}_reaction_{}", ["x", "y", "z"][axis]))?
                        .last()
                        .ok_or("empty history")?,
                };
                value / divide_by
            }
            Measure::ZeroCrossingFrequency { column: c } => {
                let (t, y) = (time()?, column(c)?);
                let mean = y.iter().sum::<f64>() / y.len() as f64;
                let ups: Vec<f64> = (1..y.len())
                    .filter(|&i| y[i - 1] < mean && y[i] >= mean)
                    .map(|i| t[i - 1] + (mean - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]))
                    .collect();
                if ups.len() < 2 {
                    return Err(format!("`{c}` crosses its mean fewer than twice"));
                }
                (ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0])
            }
            Measure::ContactReplay {
                solver,
                quantity,
                tolerance,
                only_converged,
            } => crate::replay::evaluate(
                &run.contact_problems,
                solver,
                *quantity,
                *tolerance,
                *only_converged,
            )?,
            Measure::FailureMode(spec) => {
                crate::beam::cracks::failure_mode_at(problem, spec, &run.u)?
                    .0
                    .code()
            }
            Measure::CrackTipSpeedRatio(spec) => {
                let snapshots = run.snapshots();
                if snapshots.is_empty() {
                    return Err("crack_tip_speed_ratio needs snapshots: set the explicit \
                                analysis' snapshot_interval"
                        .into());
                }
                let tip = crate::beam::crack_tip_history(problem, snapshots, spec)?;
                let b = problem
                    .model
                    .body_index(&spec.body)
                    .ok_or_else(|| format!("no body named `{}`", spec.body))?;
                let c_r = crate::reference::analytic::rayleigh_wave_speed(
                    &problem.model.bodies[b].material.constants(),
                );
                tip.iter().map(|p| p.2).fold(0.0, f64::max) / c_r
            }
            Measure::KineticOverInternalWork {
                kinetic,
                internal_work,
                above_fraction,
                until_peak_of,
                after_peak_down_to,
            } => {
                let (mut k, mut w) = (column(kinetic)?, column(internal_work)?);
                if let Some(c) = until_peak_of {
                    let end = crate::beam::history::records_through_peak(
                        &column(c)?,
                        *after_peak_down_to,
                    )
                    .map_err(|e| format!("`{c}`: {e}"))?;
                    k.truncate(end);
                    w.truncate(end);
                }
                crate::beam::history::kinetic_over_internal_work(&k, &w, *above_fraction)?
            }
            Measure::SecantStiffness {
                force,
                displacement,
                up_to_fraction,
            } => crate::beam::history::secant_stiffness(
                &column(force)?,
                &column(displacement)?,
                *up_to_fraction,
            )?,
            Measure::PeakBendingMoment {
                section_x,
                conditions,
                until_peak_of,
            } => {
                let end = match until_peak_of {
                    Some(c) => crate::beam::history::records_through_peak(&column(c)?, None)?,
                    None => usize::MAX,
                };
                let mut forces = Vec::with_capacity(conditions.len());
                for name in conditions {
                    let (c, x) = crate::beam::history::force_line(problem, name)?;
                    let mut f = column(&c)?;
                    f.truncate(end);
                    forces.push((f, x));
                }
                crate::beam::history::peak_bending_moment(*section_x, &forces)?
            }
            Measure::PeakRatio {
                numerator,
                denominator,
            } => crate::beam::history::peak_ratio(&column(numerator)?, &column(denominator)?)?,
            Measure::PeakTimeLag { column: c, after } => {
                crate::beam::history::peak_time_lag(&time()?, &column(c)?, &column(after)?)?
            }
            Measure::ForceEquilibriumError {
                body,
                contact,
                reactions,
                momentum,
            } => {
                let b = problem
                    .model
                    .body_index(body)
                    .ok_or_else(|| format!("no body named `{body}`"))?;
                let mass: f64 = problem.model.bodies[b]
                    .nodes
                    .clone()
                    .map(|n| problem.model.mass[n])
                    .sum();
                let g = problem.gravity.map_or(0.0, |g| g.y);
                let reactions = reactions
                    .iter()
                    .map(|r| column(r))
                    .collect::<Result<Vec<_>, _>>()?;
                crate::beam::history::force_equilibrium_error(
                    &time()?,
                    &column(contact)?,
                    &reactions,
                    &column(momentum)?,
                    mass * g,
                )?
            }
            Measure::CrackBand(m) => m.evaluate(&problem.model, &|c| column(c))?,
            Measure::CrackBandPoint(m) => m.evaluate(&problem.model)?,
            sweep => {
                return Err(format!(
                    "{sweep:?} is a sweep measure: the case needs a sweep"
                ))
            }
        })
    }
}

/// First time `signal` reaches `level` (upward or downward, whichever way it starts from).
fn crossing(time: &[f64], signal: &[f64], level: f64) -> Result<f64, String> {
    let start = signal.first().copied().unwrap_or(0.0);
    let up = level >= start;
    for i in 1..signal.len() {
        let reached = if up {
            signal[i] >= level
        } else {
            signal[i] <= level
        };
        if reached {
            let s = (level - signal[i - 1]) / (signal[i] - signal[i - 1]);
            return Ok(time[i - 1] + s * (time[i] - time[i - 1]));
        }
    }
    Err(format!("the signal never reaches {level}"))
}

fn boundary_node_flags(problem: &Problem) -> Vec<bool> {
    let mut flags = vec![false; problem.model.node_count()];
    // Bodies share no nodes, so the faces of all elements at once are the bodies' boundaries.
    for f in impact_solver::mesh::boundary_faces_of(&problem.model.tets) {
        for n in f.nodes {
            flags[n as usize] = true;
        }
    }
    flags
}

fn matrix_from_voigt(v: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2])
}

fn max_abs(m: &Matrix3<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// One Cauchy stress component of every element whose reference centroid lies in `[min, max]`.
fn element_stress_in_box(
    problem: &Problem,
    run: &Execution,
    component: TensorComponent,
    min: &[f64; 3],
    max: &[f64; 3],
) -> Result<Vec<f64>, String> {
    let fields = run.element_fields(&problem.model);
    let values: Vec<f64> = problem
        .model
        .tets
        .iter()
        .enumerate()
        .filter(|(_, tet)| {
            let centroid = tet
                .iter()
                .map(|&n| problem.model.reference[n as usize])
                .sum::<Vector3<f64>>()
                / 4.0;
            (0..3).all(|a| centroid[a] >= min[a] && centroid[a] <= max[a])
        })
        .map(|(e, _)| fields.cauchy[e][component as usize])
        .collect();
    if values.is_empty() {
        return Err(format!(
            "no element centroid lies in the box {min:?} - {max:?}"
        ));
    }
    Ok(values)
}
