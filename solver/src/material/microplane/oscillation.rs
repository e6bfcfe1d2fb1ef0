//! The work a material point takes under a small strain oscillation about its state: the check
//! that an update does not give back more work than it takes, which an explicit solver would
//! turn into growing modes of the mesh (docs/MICROPLANE.md "Tensile boundary").
//!
//! One strain component oscillates, `e_c = e_c* + a sin(2 pi n / P)` over the updates `n` with
//! the others held at the point's strain `e*`, and the work of each period is
//! `sum_n sigma_n : (e_(n+1) - e_(n-1)) / 2` over its `P` updates (central differences, as the
//! explicit solver's internal work). A stress that is a function of the strain gives zero to
//! second order in `a`, a secant unloading line exactly zero; a negative work is energy the update
//! creates, as a stiffness that lags the strain does (a delayed restoring force is a negative
//! damping).

use super::contract;
use super::driver::MaterialPoint;
use super::Sym;

/// The work per unit volume (J/m^3) of each of `periods` periods of `period` updates of
/// component `component` (`[11, 22, 33, 23, 13, 12]`, tensor shears) oscillating with amplitude
/// `amplitude` about the state of `point` (a copy of it; `point` is left as it is), each
/// update in `dt` seconds.
pub fn oscillation_work(
    point: &MaterialPoint,
    component: usize,
    amplitude: f64,
    period: usize,
    periods: usize,
    dt: f64,
) -> Vec<f64> {
    let mut p = point.clone();
    let base = p.strain;
    let strain_at = |n: usize| -> Sym {
        let mut s = base;
        let phase = 2.0 * std::f64::consts::PI * n as f64 / period as f64;
        s[component] += amplitude * phase.sin();
        s
    };
    let updates = periods * period;
    let stresses: Vec<Sym> = (0..=updates + 1)
        .map(|n| p.strain_step(strain_at(n), dt).stress)
        .collect();
    (0..periods)
        .map(|k| {
            (k * period + 1..=(k + 1) * period)
                .map(|n| {
                    let (next, previous) = (strain_at(n + 1), strain_at(n - 1));
                    let step: Sym = std::array::from_fn(|i| 0.5 * (next[i] - previous[i]));
                    contract(&stresses[n], &step)
                })
                .sum()
        })
        .collect()
}
