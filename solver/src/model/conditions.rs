//! Boundary conditions and loads on node sets, with their time functions.

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// A scalar function of time (or of the load factor in a static analysis).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeFunction {
    Constant(f64),
    /// `from` until `t0`, linear to `to` at `t1`, `to` afterwards.
    Ramp {
        t0: f64,
        t1: f64,
        from: f64,
        to: f64,
    },
    /// Piecewise linear through `[t, value]` points in increasing `t`; constant outside.
    Table(Vec<[f64; 2]>),
}

impl TimeFunction {
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
        }
    }

    /// Checks the parameters: a ramp needs `t1 > t0`, a table increasing times.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            TimeFunction::Constant(v) if !v.is_finite() => {
                Err(format!("constant {v} is not finite"))
            }
            TimeFunction::Ramp { t0, t1, .. } if !(t1 > t0) => {
                Err(format!("ramp needs t1 > t0, got t0 = {t0}, t1 = {t1}"))
            }
            TimeFunction::Table(p) if p.is_empty() => Err("table has no points".into()),
            TimeFunction::Table(p) if p.windows(2).any(|w| !(w[1][0] > w[0][0])) => {
                Err("table times must increase strictly".into())
            }
            _ => Ok(()),
        }
    }
}

/// Which displacement components a condition acts on.
pub type Dofs = [bool; 3];

/// What a constraint prescribes on its nodes.
#[derive(Debug, Clone, PartialEq)]
pub enum Motion {
    /// Zero displacement on `dofs`.
    Fixed(Dofs),
    /// Velocity `function(t)` on `dofs`.
    Velocity(Dofs, TimeFunction),
    /// Displacement `function(t)` on `dofs`.
    Displacement(Dofs, TimeFunction),
    /// All components follow the affine velocity field `v = translation + gradient (X - center)`.
    AffineVelocity {
        translation: Vector3<f64>,
        gradient: Matrix3<f64>,
        center: Vector3<f64>,
    },
    /// All components follow the affine displacement field
    /// `u = scale(t) (translation + gradient (X - center))`.
    AffineDisplacement {
        translation: Vector3<f64>,
        gradient: Matrix3<f64>,
        center: Vector3<f64>,
        scale: TimeFunction,
    },
    /// All components follow the rigid rotation `u = (R(angle(t)) - I)(X - center)` about `axis`.
    Rotation {
        axis: Unit<Vector3<f64>>,
        center: Vector3<f64>,
        angle: TimeFunction,
    },
}

impl Motion {
    /// Components this motion prescribes.
    pub fn dofs(&self) -> Dofs {
        match self {
            Motion::Fixed(d) | Motion::Velocity(d, _) | Motion::Displacement(d, _) => *d,
            Motion::AffineVelocity { .. }
            | Motion::AffineDisplacement { .. }
            | Motion::Rotation { .. } => [true; 3],
        }
    }

    /// Prescribed displacement of a node at `X` at time `t`, where the motion defines one
    /// (velocity motions do not: they are integrated by the time stepper).
    pub fn displacement(&self, x: &Vector3<f64>, t: f64) -> Option<Vector3<f64>> {
        match self {
            Motion::Fixed(_) => Some(Vector3::zeros()),
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
    pub name: String,
    pub nodes: Vec<u32>,
    pub motion: Motion,
}

/// A force on each node of a set: `force_per_node * function(t)` (N).
#[derive(Debug, Clone, PartialEq)]
pub struct NodalLoad {
    pub name: String,
    pub nodes: Vec<u32>,
    pub force_per_node: Vector3<f64>,
    pub function: TimeFunction,
}
