//! The optimiser of the calibration: Nelder & Mead's simplex (1965) over the free parameters,
//! searched in the logarithm of their values.

use super::super::MicroplaneParameters;

/// Nelder-Mead simplex minimisation of `f` from `x0` with initial steps `step`, for at most
/// `evaluations` evaluations (standard coefficients 1, 2, 1/2, 1/2).
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64]) -> f64,
    x0: &[f64],
    step: &[f64],
    evaluations: usize,
) -> (Vec<f64>, f64) {
    let n = x0.len();
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    simplex.push((x0.to_vec(), f(x0)));
    for i in 0..n {
        let mut x = x0.to_vec();
        x[i] += step[i];
        let v = f(&x);
        simplex.push((x, v));
    }
    let mut count = n + 1;
    while count < evaluations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (simplex[n].1 - simplex[0].1).abs() < 1e-10 * (1.0 + simplex[0].1.abs()) {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|j| simplex[..n].iter().map(|p| p.0[j]).sum::<f64>() / n as f64)
            .collect();
        let along = |t: f64| -> Vec<f64> {
            (0..n)
                .map(|j| centroid[j] + t * (simplex[n].0[j] - centroid[j]))
                .collect()
        };
        let reflected = along(-1.0);
        let fr = f(&reflected);
        count += 1;
        if fr < simplex[0].1 {
            let expanded = along(-2.0);
            let fe = f(&expanded);
            count += 1;
            simplex[n] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let contracted = if fr < simplex[n].1 {
                along(-0.5)
            } else {
                along(0.5)
            };
            let fc = f(&contracted);
            count += 1;
            if fc < simplex[n].1.min(fr) {
                simplex[n] = (contracted, fc);
            } else {
                let best = simplex[0].0.clone();
                for p in simplex.iter_mut().skip(1) {
                    p.0 = (0..n).map(|j| best[j] + 0.5 * (p.0[j] - best[j])).collect();
                    p.1 = f(&p.0);
                    count += 1;
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex.swap_remove(0)
}

/// A parameter the optimiser may change, searched in the logarithm of its value.
#[derive(Debug, Clone, Copy)]
pub enum Free {
    /// `e1`, strain scale of tension (5.19).
    E1,
    /// `m`, exponent of tension (5.19), kept in `[0.5, 20]`.
    M,
    /// `e2`, strain scale of deviatoric compression (5.19).
    E2,
    /// `n`, exponent of deviatoric compression (5.19), kept in `[0.5, 20]`.
    N,
    /// `e3`, strain scale of shear (5.20).
    E3,
    /// `e4`, growth of the shear strain scale with volumetric compression (5.20).
    E4,
    /// `k`, exponent of shear (5.20), kept in `[0.5, 20]`.
    K,
    /// The dilatancy (MICROPLANE "Dilatancy"), kept at most 10.
    Dilatancy,
    /// The tensile boundary's `strength` `f0` (docs/MICROPLANE.md "Tensile boundary"); NaN and
    /// left alone without a boundary.
    BoundaryStrength,
}

impl Free {
    pub(super) fn get(self, p: &MicroplaneParameters) -> f64 {
        match self {
            Free::E1 => p.e1,
            Free::M => p.m,
            Free::E2 => p.e2,
            Free::N => p.n,
            Free::E3 => p.e3,
            Free::E4 => p.e4,
            Free::K => p.k,
            Free::Dilatancy => p.dilatancy,
            Free::BoundaryStrength => p.tension_boundary.map_or(f64::NAN, |b| b.strength),
        }
    }

    /// Sets the value, keeping exponents within `[0.5, 20]`: beyond, the laws become step
    /// functions whose parameters no target can pin down.
    pub(super) fn set(self, p: &mut MicroplaneParameters, v: f64) {
        let exponent = v.clamp(0.5, 20.0);
        match self {
            Free::E1 => p.e1 = v,
            Free::M => p.m = exponent,
            Free::E2 => p.e2 = v,
            Free::N => p.n = exponent,
            Free::E3 => p.e3 = v,
            Free::E4 => p.e4 = v,
            Free::K => p.k = exponent,
            Free::Dilatancy => p.dilatancy = v.min(10.0),
            Free::BoundaryStrength => {
                if let Some(b) = &mut p.tension_boundary {
                    b.strength = v;
                }
            }
        }
    }
}
