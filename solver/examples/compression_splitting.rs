//! Uniaxial compression of one material point (h = 50 mm, quasi-static) of a concrete with the
//! tensile boundary (`tension_boundary.rs`), to find why the lateral-stress Newton stops: per
//! increment the axial stress and strain, the lateral strain, and the planes whose crack strain
//! is open; at the increment that does not converge, the lateral stress residual
//! `sigma_22 = sigma_33` as a function of the (equal) lateral strains, with the driver and the
//! crack strain of the most opened plane (its traction and its driver `t + theta nu <-s_min>` on
//! that stress, `crack_strain`), and the finite-difference Jacobian there.
//!
//! `cargo run --release -p impact-solver --example compression_splitting -- MATERIAL_FILE`
//! (a calibrated file with a `tension_boundary`, e.g. the output of `impact-vv calibrate
//! --targets cases/materials/thesis-concrete-tension-boundary-targets.yaml`).

// Example code: an `unwrap` that fails stops the example (the lint is for library code).
#![allow(clippy::unwrap_used)]
use impact_solver::material::microplane::driver::{uniaxial_controls, MaterialPoint};
use impact_solver::material::microplane::{state, Microplane, MicroplaneConcrete};
use impact_solver::material::read_microplane_file;

const H: f64 = 0.05;

/// `n . e . n` with tensor shears.
fn normal_part(n: &[f64; 3], e: &[f64; 6]) -> f64 {
    n[0] * n[0] * e[0]
        + n[1] * n[1] * e[1]
        + n[2] * n[2] * e[2]
        + 2.0 * (n[1] * n[2] * e[3] + n[0] * n[2] * e[4] + n[0] * n[1] * e[5])
}

/// The smaller principal value of the stress `s` in the plane (along its tangents `m`, `k`).
fn smallest_in_plane(plane: &Microplane, s: &[f64; 6]) -> f64 {
    let along = |a: &[f64; 3], b: &[f64; 3]| {
        a[0] * (s[0] * b[0] + s[5] * b[1] + s[4] * b[2])
            + a[1] * (s[5] * b[0] + s[1] * b[1] + s[3] * b[2])
            + a[2] * (s[4] * b[0] + s[3] * b[1] + s[2] * b[2])
    };
    let (mm, kk, mk) = (
        along(&plane.m, &plane.m),
        along(&plane.k, &plane.k),
        along(&plane.m, &plane.k),
    );
    0.5 * (mm + kk) - (0.25 * (mm - kk).powi(2) + mk * mk).sqrt()
}

/// Per plane `(y_max, y)`, and the element crack strain `sum 6 w y n n`.
fn cracks(model: &MicroplaneConcrete, values: &[f32]) -> (Vec<(f64, f64)>, [f64; 6]) {
    let mut out = Vec::new();
    let mut crack = [0.0; 6];
    for (p, plane) in model.planes().iter().enumerate() {
        let s = state::HEADER + state::PER_PLANE * p + state::D_POSITIVE;
        let (ymax, y) = (values[s] as f64, values[s + 1] as f64);
        out.push((ymax, y));
        let n = plane.normal;
        let nn = [
            n[0] * n[0],
            n[1] * n[1],
            n[2] * n[2],
            n[1] * n[2],
            n[0] * n[2],
            n[0] * n[1],
        ];
        for i in 0..6 {
            crack[i] += 6.0 * plane.weight * y * nn[i];
        }
    }
    (out, crack)
}

fn main() {
    let file = std::env::args().nth(1).unwrap();
    let p = read_microplane_file(std::path::Path::new(&file)).unwrap();
    let boundary = p.tension_boundary.unwrap();
    let (poisson, theta) = (p.poisson_ratio, boundary.strain_weight);
    let model = MicroplaneConcrete::new(p).unwrap();
    let mut point = MaterialPoint::new(&model, H).unwrap();
    let de = 1e-5;
    for i in 1..=600 {
        let axial = -de * i as f64;
        let saved = point.clone();
        match point.mixed_step_subdivided(&uniaxial_controls(axial), de / 1e-6) {
            Ok(q) => {
                let (planes, crack) = cracks(&model, &point.state.values);
                let open: Vec<String> = planes
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.1 > 0.0)
                    .map(|(p, c)| format!("{p}:{:.2e}", c.1))
                    .collect();
                if i % 10 == 0 || !open.is_empty() {
                    println!(
                        "eps_11 {:.3e}  sigma_11 {:7.2} MPa  eps_22 {:.3e}  eps_cr_22 {:.2e}  open planes {}",
                        q.strain[0],
                        q.stress[0] * 1e-6,
                        q.strain[1],
                        crack[1],
                        open.join(" ")
                    );
                }
            }
            Err(err) => {
                println!("stops at eps_11 {axial:.3e}: {err}");
                let point = saved;
                println!(
                    "last converged: eps {:?}\n  sigma {:?} MPa",
                    point.strain,
                    point.stress.map(|s| s * 1e-6)
                );
                scan_lateral(&model, &point, axial, de / 1e-6, poisson, theta);
                return;
            }
        }
    }
}

/// The lateral stress at the failing axial strain as the equal lateral strains sweep from the
/// last converged value upwards, and the driver of the most opened plane.
fn scan_lateral(
    model: &MicroplaneConcrete,
    point: &MaterialPoint,
    axial: f64,
    dt: f64,
    poisson: f64,
    theta: f64,
) {
    let start = point.strain[1];
    println!("lateral strain scan at eps_11 = {axial:.3e} (eps_22 = eps_33, shears 0):");
    let mut best = f64::NEG_INFINITY;
    for k in 0..=40 {
        let lateral = start * (1.0 + 0.05 * k as f64);
        let strain = [axial, lateral, lateral, 0.0, 0.0, 0.0];
        let mut trial = point.clone();
        let q = trial.strain_step(strain, dt);
        let (planes, crack) = cracks(model, &trial.state.values);
        let (p, (_, y)) = planes
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .unwrap();
        let plane = &model.planes()[p];
        let n = plane.normal;
        let traction = normal_part(&n, &q.stress);
        // The driver `t + theta nu <-s_min>` of `crack_strain`, on this stress.
        let driver = traction + theta * poisson * (-smallest_in_plane(plane, &q.stress)).max(0.0);
        best = best.max(q.stress[1]);
        println!(
            "  eps_22 {lateral:.4e}: sigma_22 {:8.3} MPa, sigma_11 {:7.2} MPa; plane {p} n {:.2?}: y {y:.3e}, traction {:.3} MPa, driver {:.3} MPa, eps_cr_22 {:.3e}",
            q.stress[1] * 1e-6,
            q.stress[0] * 1e-6,
            n,
            traction * 1e-6,
            driver * 1e-6,
            crack[1]
        );
    }
    println!("largest sigma_22 on the scan: {:.3} MPa", best * 1e-6);
    // Jacobian d sigma_(22,33) / d eps_(22,33) at the last converged lateral strains.
    let base = [axial, start, start, 0.0, 0.0, 0.0];
    let s0 = point.clone().strain_step(base, dt).stress;
    let step = 1e-9;
    for (j, name) in [(1, "22"), (2, "33")] {
        let mut strain = base;
        strain[j] += step;
        let s = point.clone().strain_step(strain, dt).stress;
        println!(
            "  d sigma_22 / d eps_{name} = {:.3e} Pa, d sigma_33 / d eps_{name} = {:.3e} Pa",
            (s[1] - s0[1]) / step,
            (s[2] - s0[2]) / step
        );
    }
}
