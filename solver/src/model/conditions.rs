//! Boundary conditions and loads on node sets, with their time functions.

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// Displacement components, named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    /// The `x` component (index 0).
    X,
    /// The `y` component (index 1).
    Y,
    /// The `z` component (index 2).
    Z,
}

/// A scalar function of time (or of the load factor in a static analysis).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeFunction {
    /// The same value at every time.
    Constant(f64),
    /// `from` until `t0`, linear to `to` at `t1`, `to` afterwards.
    Ramp {
        /// Start of the ramp (s, or load factor).
        t0: f64,
        /// End of the ramp (s, or load factor), above `t0`.
        t1: f64,
        /// Value up to `t0`, in the unit of the quantity the function scales.
        from: f64,
        /// Value from `t1` on, in the same unit.
        to: f64,
    },
    /// Piecewise linear through `[t, value]` points in increasing `t`; constant outside.
    Table(Vec<[f64; 2]>),
    /// Zero at `t = 0`, then a constant rate reached smoothly: `rate t^2 / (2 lead_in)` for
    /// `0 <= t <= lead_in` (constant acceleration), `rate (t - lead_in / 2)` after; zero before
    /// `t = 0`. The value and its rate are continuous (a table of the same curve jumps in rate
    /// at every point, and each jump sets an undamped explicit run ringing), and the
    /// acceleration `rate / lead_in` excites the modes of frequency `omega` only to an amplitude
    /// of about `rate / (lead_in omega^2)`.
    ConstantRate {
        /// The final rate: the value's unit per second.
        rate: f64,
        /// Duration of the smooth start (s), at least 0; 0 gives a plain ramp from zero.
        lead_in: f64,
    },
}

impl TimeFunction {
    /// The function's value at time `t` (s; the load factor in a static analysis). An empty
    /// table gives 0.
    pub fn eval(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(v) => *v,
            TimeFunction::Ramp { t0, t1, from, to } => {
                if t <= *t0 {
                    *from
                } else if t >= *t1 {
                    *to
                } else {
                    from + (to - from) * (t - t0) / (t1 - t0)
                }
            }
            TimeFunction::Table(points) => {
                let Some(first) = points.first() else {
                    return 0.0;
                };
                if t <= first[0] {
                    return first[1];
                }
                for w in points.windows(2) {
                    let ([ta, va], [tb, vb]) = (w[0], w[1]);
                    if t <= tb {
                        return va + (vb - va) * (t - ta) / (tb - ta);
                    }
                }
                points[points.len() - 1][1]
            }
            TimeFunction::ConstantRate { rate, lead_in } => {
                if t <= 0.0 {
                    0.0
                } else if t < *lead_in {
                    rate * t * t / (2.0 * lead_in)
                } else {
                    rate * (t - 0.5 * lead_in)
                }
            }
        }
    }

    /// Checks the parameters: every number finite, a ramp's `t1 > t0`, a table's times
    /// increasing.
    pub fn validate(&self) -> Result<(), TimeFunctionError> {
        use TimeFunctionError as E;
        match self {
            TimeFunction::Constant(v) if !v.is_finite() => Err(E::Constant(*v)),
            TimeFunction::Ramp { t0, t1, from, to }
                if ![t0, t1, from, to].iter().all(|v| v.is_finite()) =>
            {
                Err(E::RampNotFinite([*t0, *t1, *from, *to]))
            }
            TimeFunction::Table(p) if p.iter().flatten().any(|v| !v.is_finite()) => {
                Err(E::TableNotFinite)
            }
            TimeFunction::Ramp { t0, t1, .. } if !(t1 > t0) => {
                Err(E::RampOrder { t0: *t0, t1: *t1 })
            }
            TimeFunction::Table(p) if p.is_empty() => Err(E::TableEmpty),
            TimeFunction::Table(p) if p.windows(2).any(|w| !(w[1][0] > w[0][0])) => {
                Err(E::TableOrder)
            }
            TimeFunction::ConstantRate { rate, lead_in }
                if !(rate.is_finite() && lead_in.is_finite() && *lead_in >= 0.0) =>
            {
                Err(E::ConstantRate {
                    rate: *rate,
                    lead_in: *lead_in,
                })
            }
            _ => Ok(()),
        }
    }
}

/// Why a time function's parameters are refused (the caller names the condition or load).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TimeFunctionError {
    /// A constant that is not finite.
    #[error("constant {0} is not finite")]
    Constant(f64),
    /// A ramp with a number that is not finite.
    #[error("ramp needs finite t0, t1, from and to, got {}, {}, {}, {}", .0[0], .0[1], .0[2], .0[3])]
    RampNotFinite([f64; 4]),
    /// A table with a point that is not finite.
    #[error("table points must be finite")]
    TableNotFinite,
    /// A ramp that ends before it starts.
    #[error("ramp needs t1 > t0, got t0 = {t0}, t1 = {t1}")]
    RampOrder {
        /// Start of the ramp (s).
        t0: f64,
        /// End of the ramp (s).
        t1: f64,
    },
    /// A table without points.
    #[error("table has no points")]
    TableEmpty,
    /// A table whose times do not increase.
    #[error("table times must increase strictly")]
    TableOrder,
    /// A constant rate with a bad rate or lead-in.
    #[error("constant_rate needs a finite rate and lead_in >= 0, got rate = {rate}, lead_in = {lead_in}")]
    ConstantRate {
        /// The rate.
        rate: f64,
        /// The lead-in (s).
        lead_in: f64,
    },
}

/// Which displacement components a condition acts on.
pub type Dofs = [bool; 3];

/// What a constraint prescribes on its nodes.
#[derive(Debug, Clone, PartialEq)]
pub enum Motion {
    /// Zero displacement on `dofs`.
    Fixed(Dofs),
    /// A symmetry plane `x[axis] = value`: the constraint's nodes (those on the plane) are held
    /// normal to it, as by [`Motion::Fixed`], and every other node of their body that reaches it
    /// is held on it for the step (the explicit solver's `symmetry_wall.rs`).
    Symmetry {
        /// The component normal to the plane (0, 1, 2 for x, y, z).
        axis: usize,
        /// The plane's coordinate (m).
        value: f64,
    },
    /// Velocity `function(t)` on `dofs`.
    Velocity(Dofs, TimeFunction),
    /// Displacement `function(t)` on `dofs`.
    Displacement(Dofs, TimeFunction),
    /// All components follow the affine velocity field `v = translation + gradient (X - center)`.
    AffineVelocity {
        /// Uniform velocity (m/s).
        translation: Vector3<f64>,
        /// Velocity gradient `dv/dX` (1/s).
        gradient: Matrix3<f64>,
        /// Reference point `X` of the gradient (m).
        center: Vector3<f64>,
    },
    /// All components follow the affine displacement field
    /// `u = scale(t) (translation + gradient (X - center))`.
    AffineDisplacement {
        /// Uniform displacement at scale 1 (m).
        translation: Vector3<f64>,
        /// Displacement gradient `du/dX` at scale 1 (dimensionless).
        gradient: Matrix3<f64>,
        /// Reference point `X` of the gradient (m).
        center: Vector3<f64>,
        /// Dimensionless factor against time (s).
        scale: TimeFunction,
    },
    /// All components follow the rigid rotation `u = (R(angle(t)) - I)(X - center)` about `axis`.
    Rotation {
        /// Unit rotation axis; the angle turns right-handed about it.
        axis: Unit<Vector3<f64>>,
        /// A point on the axis (m).
        center: Vector3<f64>,
        /// Rotation angle (rad) against time (s).
        angle: TimeFunction,
    },
}

impl Motion {
    /// Components this motion prescribes.
    pub fn dofs(&self) -> Dofs {
        match self {
            Motion::Fixed(d) | Motion::Velocity(d, _) | Motion::Displacement(d, _) => *d,
            Motion::Symmetry { axis, .. } => {
                let mut d = [false; 3];
                d[*axis] = true;
                d
            }
            Motion::AffineVelocity { .. }
            | Motion::AffineDisplacement { .. }
            | Motion::Rotation { .. } => [true; 3],
        }
    }

    /// Prescribed displacement of a node at `X` at time `t`, where the motion defines one
    /// (velocity motions do not: they are integrated by the time stepper).
    pub fn displacement(&self, x: &Vector3<f64>, t: f64) -> Option<Vector3<f64>> {
        match self {
            Motion::Fixed(_) | Motion::Symmetry { .. } => Some(Vector3::zeros()),
            Motion::Displacement(_, f) => Some(Vector3::repeat(f.eval(t))),
            Motion::AffineDisplacement {
                translation,
                gradient,
                center,
                scale,
            } => Some((translation + gradient * (x - center)) * scale.eval(t)),
            Motion::Rotation {
                axis,
                center,
                angle,
            } => {
                let r = Rotation3::from_axis_angle(axis, angle.eval(t));
                let d = x - center;
                Some(r * d - d)
            }
            Motion::Velocity(..) | Motion::AffineVelocity { .. } => None,
        }
    }

    /// Prescribed velocity of a node at `X` at time `t`, where the motion defines one.
    pub fn velocity(&self, x: &Vector3<f64>, t: f64) -> Option<Vector3<f64>> {
        match self {
            Motion::Velocity(_, f) => Some(Vector3::repeat(f.eval(t))),
            Motion::AffineVelocity {
                translation,
                gradient,
                center,
            } => Some(translation + gradient * (x - center)),
            _ => None,
        }
    }
}

/// A constraint: `motion` on the nodes of a set. `name` labels its reaction-force history.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// Label of the constraint's reaction-force history columns.
    pub name: String,
    /// Constrained nodes, as indices into the model's node arrays.
    pub nodes: Vec<u32>,
    /// What the constraint prescribes on those nodes.
    pub motion: Motion,
}

/// A force on each node of a set: `force_per_node * function(t)` (N).
#[derive(Debug, Clone, PartialEq)]
pub struct NodalLoad {
    /// Label of the load in error messages.
    pub name: String,
    /// Loaded nodes, as indices into the model's node arrays.
    pub nodes: Vec<u32>,
    /// Force on each node at a function value of 1 (N), in the global frame.
    pub force_per_node: Vector3<f64>,
    /// Dimensionless factor against time (s; the load factor in a static analysis).
    pub function: TimeFunction,
}

#[cfg(test)]
mod tests {
    use super::TimeFunction;

    /// `constant_rate`: the quadratic lead-in meets the straight line with the same value and
    /// slope, and the slope is `rate` from then on.
    #[test]
    fn constant_rate_is_smooth_and_reaches_its_rate() {
        let f = TimeFunction::ConstantRate {
            rate: -4e-3,
            lead_in: 0.01,
        };
        assert_eq!(f.eval(-1.0), 0.0);
        assert_eq!(f.eval(0.0), 0.0);
        // At the end of the lead-in: rate T / 2 from both sides, slope rate from both sides.
        let t = 0.01;
        assert!((f.eval(t) - (-4e-3 * 0.005)).abs() < 1e-18);
        let slope = |a: f64, b: f64| (f.eval(b) - f.eval(a)) / (b - a);
        let h = 1e-7;
        // One-sided slopes differ by O(h) only (a kink would leave O(rate) = 4e-3).
        assert!((slope(t - h, t) - slope(t, t + h)).abs() < 1e-6);
        assert!((slope(0.05, 0.06) + 4e-3).abs() < 1e-15);
        // Half the rate halfway through the lead-in.
        assert!((slope(0.005 - h, 0.005 + h) + 2e-3).abs() < 1e-9);
        // No lead-in: a plain ramp from zero.
        let ramp = TimeFunction::ConstantRate {
            rate: 2.0,
            lead_in: 0.0,
        };
        assert_eq!(ramp.eval(0.5), 1.0);
        assert!(TimeFunction::ConstantRate {
            rate: 1.0,
            lead_in: -1.0
        }
        .validate()
        .is_err());
    }
}
