//! How much the elastic neighbours of a crack band lower its peak by holding it sideways
//! (`fracture/band-in-prism*`: the free prisms' bands peak at 0.964-0.969 of the material
//! point's peak, with neighbours of Poisson ratio 0.18; 0.976 and 0.981 with 0.20 and 0.22).
//!
//! One material point of the concrete (h = 50 mm) pulled in uniaxial stress gives the peak the
//! cases judge against, and its lateral strain there. Then the same point pulled along x with its
//! lateral strains held, step by step, where neighbours of Poisson ratio `nu_n` that hold it
//! completely would put them: `-nu_n sigma_x / E` (the neighbours are elastic and carry the
//! band's axial stress). Before its peak the point's axial strain is partly inelastic, so it
//! contracts by more than elastic neighbours of its own `nu`: the complete hold is a lower bound
//! of the bonded band's peak, uniaxial stress an upper one, and the ratio of the prisms' deficit
//! to the complete hold's says how far the prism holds its band.
//!
//! `cargo run --release -p impact-solver --example band_lateral_restraint [-- MATERIAL_FILE]`
//! (the shipped concrete by default; a fraction of a second)

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{uniaxial_controls, MaterialPoint};
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::read_microplane_file;

/// Largest axial strain of the paths: past every peak.
const END_STRAIN: f64 = 6e-4;

/// Axial strain increment: fine up to the peak, coarser after it.
fn increment(e: f64) -> f64 {
    if e < 3e-4 {
        2.5e-7
    } else {
        2e-6
    }
}

fn main() {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/materials/thesis-concrete.yaml".into());
    let mut parameters = read_microplane_file(std::path::Path::new(&file)).unwrap();
    // As in the prisms' bands (`rate_effect: false`).
    parameters.rate_effect = None;
    let youngs = parameters.youngs_modulus;
    let model = MicroplaneConcrete::new(parameters).unwrap();
    let h = 0.05;

    let mut point = MaterialPoint::new(&model, h).unwrap();
    let (mut free_peak, mut free_at, mut contraction) = (0.0f64, 0.0, 0.0);
    let mut e = 0.0;
    while e < END_STRAIN {
        e += increment(e);
        let q = point
            .mixed_step_subdivided(&uniaxial_controls(e), 1.0)
            .unwrap();
        if q.stress[0] > free_peak {
            (free_peak, free_at, contraction) = (q.stress[0], e, -q.strain[1]);
        }
    }
    println!("{file}, h = {h} m");
    println!(
        "uniaxial stress: peak {:.4} MPa at eps_x {:.3e}; lateral strain there -{:.3} eps_x, \
         -{:.3} of the elastic strain sigma_x / E",
        free_peak / 1e6,
        free_at,
        contraction / free_at,
        contraction / (free_peak / youngs)
    );
    println!(
        "held completely by neighbours of Poisson ratio nu_n (lateral strains -nu_n sigma_x / E):"
    );
    for nu in [0.0, 0.18, 0.20, 0.22, 0.25, 0.288, 0.30] {
        let mut point = MaterialPoint::new(&model, h).unwrap();
        let (mut peak, mut at, mut lateral) = (0.0f64, 0.0, 0.0);
        let (mut e, mut sigma_x) = (0.0, 0.0);
        while e < END_STRAIN {
            e += increment(e);
            // The neighbours' lateral strain under the axial stress of the last step (the
            // steps are small).
            let held = -nu * sigma_x / youngs;
            let q = point.strain_step([e, held, held, 0.0, 0.0, 0.0], 1.0);
            sigma_x = q.stress[0];
            if sigma_x > peak {
                (peak, at, lateral) = (sigma_x, e, q.stress[1]);
            }
        }
        println!(
            "  nu_n {nu:.3}: peak {:.4} MPa, {:.4} of uniaxial stress, at eps_x {:.3e}; lateral \
             stress there {:+.3} MPa",
            peak / 1e6,
            peak / free_peak,
            at,
            lateral / 1e6
        );
    }
}
