//! Whether the concrete's update gives back more work than it takes under a small oscillating
//! strain about a softened state: the diagnostic of a free crack band whose mesh modes grew until
//! its energy balance failed (docs/MICROPLANE.md "Tensile boundary").
//!
//! One material point (h = 50 mm, no rate effect) is pulled in uniaxial stress along x past its
//! peak to 0.9, 0.6, 0.3, 0.1 and 0.03 of it. About each state each strain component in turn
//! oscillates by `a` over 30 periods of `P` updates (`oscillation::oscillation_work`: a negative
//! work is energy the update creates); the work per period is printed over `E a^2`, averaged over
//! periods 2-11 and over the last 10.
//!
//! `cargo run --release -p impact-solver --example tension_boundary_oscillation [-- MATERIAL_FILE [AMPLITUDE]]`
//! (the concrete with the tensile boundary and `a` = 1e-7 by default; about a second)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{uniaxial_controls, MaterialPoint};
use impact_solver::material::microplane::oscillation::oscillation_work;
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;

/// Periods of the oscillation, in updates.
const PERIODS: [usize; 8] = [2, 3, 4, 5, 6, 8, 12, 24];

/// The states about which the strain oscillates: the stress after the peak, over the peak.
const STATES: [f64; 5] = [0.9, 0.6, 0.3, 0.1, 0.03];

/// The work per period over `E a^2` of component `c` oscillating with amplitude `a` and
/// period `period` about the state of `point`: averaged over periods 2-11 and over the last 10
/// of 30.
fn work_per_period(
    point: &MaterialPoint,
    c: usize,
    a: f64,
    period: usize,
    youngs: f64,
) -> (f64, f64) {
    let work = oscillation_work(point, c, a, period, 30, 1e-6);
    let scale = 10.0 * youngs * a * a;
    let (first, last): (f64, f64) = (work[1..11].iter().sum(), work[20..].iter().sum());
    (first / scale, last / scale)
}

fn main() {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/materials/thesis-concrete-tension-boundary.yaml".into());
    let a: f64 = std::env::args().nth(2).map_or(1e-7, |s| s.parse().unwrap());
    let mut parameters = read_microplane_file(std::path::Path::new(&file)).unwrap();
    parameters.rate_effect = None;
    let youngs = parameters.youngs_modulus;
    let model = MicroplaneConcrete::new(parameters).unwrap();
    let mut point = MaterialPoint::new(&model, 0.05).unwrap();
    println!("{file}, h = 50 mm, a = {a:e}; work per period over E a^2, periods 2-11 / last 10:");
    let (mut e, mut peak, mut state) = (0.0f64, 0.0f64, 0);
    while state < STATES.len() && e < 0.01 {
        e += if e < 1.5e-4 { 2.5e-7 } else { 1e-6 };
        let q = point
            .mixed_step_subdivided(&uniaxial_controls(e), 1.0)
            .unwrap();
        peak = peak.max(q.stress[0]);
        if e < 1e-4 || q.stress[0] >= STATES[state] * peak {
            continue;
        }
        println!(
            "eps_x {e:.3e}, sigma_x {:.3} MPa ({:.2} of the peak):",
            q.stress[0] / 1e6,
            q.stress[0] / peak
        );
        for (c, name) in ["xx", "yy", "zz", "yz", "xz", "xy"].iter().enumerate() {
            let mut line = format!("  e_{name}:");
            for period in PERIODS {
                let (first, last) = work_per_period(&point, c, a, period, youngs);
                line += &format!(" P{period} {first:+.1e}/{last:+.1e}");
            }
            println!("{line}");
        }
        state += 1;
    }
}
