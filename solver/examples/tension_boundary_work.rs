//! The stress work `int sigma : dE` of one material point of a concrete along a strain path that
//! opens a crack in x, compresses the point laterally in y and stretches it in x again (h = 50 mm,
//! quasi-static), printed per step beside the elastic energy `sigma : C0^-1 : sigma / 2` the point
//! would at least give back on unloading. A dissipative material takes in at least that much
//! work from the virgin state along any path; where the work falls below it the material has
//! generated energy (docs/MICROPLANE.md "Tensile boundary").
//!
//! `cargo run --release -p impact-solver --example tension_boundary_work [-- MATERIAL_FILE [EVERY]]`
//!
//! (`EVERY`: print every so many steps, 20 by default; every leg has 400.)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{equivalent_rate, MaterialPoint};
use impact_solver::material::microplane::experiments::{
    least_recoverable_energy, step_work, QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::{MicroplaneConcrete, Sym};
use impact_solver::material::read_microplane_file;

/// The path's corners: open x far past the peak, compress y, stretch x again.
const CORNERS: [Sym; 4] = [
    [0.0; 6],
    [5e-3, 0.0, 0.0, 0.0, 0.0, 0.0],
    [5e-3, -1.2e-3, 0.0, 0.0, 0.0, 0.0],
    [1e-2, -1.2e-3, 0.0, 0.0, 0.0, 0.0],
];
const STEPS: usize = 400;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| "cases/materials/thesis-concrete-tension-boundary.yaml".into());
    let every: usize = args.get(2).map_or(20, |a| a.parse().unwrap());
    let parameters = read_microplane_file(std::path::Path::new(&file)).unwrap();
    let (youngs, poisson) = (parameters.youngs_modulus, parameters.poisson_ratio);
    let model = MicroplaneConcrete::new(parameters).unwrap();
    let mut point = MaterialPoint::new(&model, 0.05).unwrap();
    println!("{file}: h = 50 mm, quasi-static");
    println!("leg step   E_xx      E_yy      S_xx(MPa) S_yy(MPa) S_zz(MPa)  dW(J/m3)   W(J/m3)   W - U0(J/m3)");
    let (mut work, mut lowest) = (0.0, f64::INFINITY);
    for (leg, pair) in CORNERS.windows(2).enumerate() {
        for i in 1..=STEPS {
            let t = i as f64 / STEPS as f64;
            let strain: Sym = std::array::from_fn(|j| pair[0][j] + t * (pair[1][j] - pair[0][j]));
            let dt = equivalent_rate(&point.strain, &strain, 1.0) / QUASI_STATIC_RATE;
            let (e0, s0) = (point.strain, point.stress);
            let p = point.strain_step(strain, dt);
            let dw = step_work(&e0, &s0, &p.strain, &p.stress);
            work += dw;
            let margin = work - least_recoverable_energy(&p.stress, youngs, poisson);
            lowest = lowest.min(margin);
            if i % every == 0 {
                println!(
                    "{:>3} {:>4} {:>9.2e} {:>9.2e} {:>9.3} {:>9.3} {:>9.3} {:>10.1} {:>10.1} {:>10.1}",
                    leg + 1,
                    i,
                    p.strain[0],
                    p.strain[1],
                    p.stress[0] * 1e-6,
                    p.stress[1] * 1e-6,
                    p.stress[2] * 1e-6,
                    dw,
                    work,
                    margin
                );
            }
        }
    }
    println!("work {work:.1} J/m^3; least of W - U0 along the path {lowest:.1} J/m^3");
}
