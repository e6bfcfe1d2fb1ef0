//! How the element eigenvalue bound (`impact_solver::model::stable_step`) compares with the
//! altitude estimate of `Model::critical_time_step` on the catalogue: for each case file given,
//! the two critical steps of its scene's model and their ratio, the factor by which a run at
//! `safety * dt_cr` would change its step with the bound.
//!
//! With `--power N` first, it also estimates the free mesh's limit `2 / sqrt(lambda_max)` of
//! `M^-1 K` (linear-elastic `K` at the materials' elastic constants) by `N` power iterations:
//! the Rayleigh quotient is below `lambda_max`, so the estimate is at or above the limit.
//!
//! Run: `cargo run --release -p impact-solver --example stable_step_catalogue -- cases/**/*.yaml`

use std::path::Path;

use impact_solver::model::stable_step::stable_length;
use impact_solver::model::Model;
use impact_solver::scene::{build_problem, Scene};
use nalgebra::{Matrix3, Vector3};

/// `f = K u` of the linear-elastic model: per element `V sigma(eps) grad N_a`.
fn stiffness_times(model: &Model, u: &[Vector3<f64>], f: &mut [Vector3<f64>]) {
    f.iter_mut().for_each(|x| *x = Vector3::zeros());
    for (e, tet) in model.tets.iter().enumerate() {
        let c = model.material_of(e).constants();
        let (lambda, mu) = (c.lambda(), c.mu());
        let g = &model.grad_n(e);
        let h: Matrix3<f64> = (0..4).map(|a| u[tet[a] as usize] * g[a].transpose()).sum();
        let eps = 0.5 * (h + h.transpose());
        let sigma = Matrix3::identity() * (lambda * eps.trace()) + eps * (2.0 * mu);
        for a in 0..4 {
            f[tet[a] as usize] += model.volume(e) * (sigma * g[a]);
        }
    }
}

/// `2 / sqrt(rho(u))` after `iterations` power iterations on `M^-1 K`, `rho` the Rayleigh
/// quotient `u^T K u / u^T M u`, from a fixed pseudo-random start.
fn power_limit(model: &Model, iterations: usize) -> f64 {
    let n = model.node_count();
    let mut rng = impact_solver::rng::SplitMix64::new(7);
    let mut u: Vec<Vector3<f64>> = (0..n)
        .map(|_| {
            Vector3::new(
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            )
        })
        .collect();
    let mut f = vec![Vector3::zeros(); n];
    let mut quotient = 0.0;
    for _ in 0..iterations {
        stiffness_times(model, &u, &mut f);
        let num: f64 = u.iter().zip(&f).map(|(a, b)| a.dot(b)).sum();
        let den: f64 = u
            .iter()
            .zip(&model.mass)
            .map(|(a, m)| m * a.norm_squared())
            .sum();
        quotient = num / den;
        for ((x, y), m) in u.iter_mut().zip(&f).zip(&model.mass) {
            *x = y / *m;
        }
        let norm = u.iter().map(|x| x.norm_squared()).sum::<f64>().sqrt();
        u.iter_mut().for_each(|x| *x /= norm);
    }
    2.0 / quotient.sqrt()
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let power: Option<usize> = if args.first().map(String::as_str) == Some("--power") {
        let n = args[1]
            .parse()
            .expect("--power N: N a number of iterations");
        args.drain(..2);
        Some(n)
    } else {
        None
    };
    println!(
        "{:<60} {:>8} {:>12} {:>12} {:>8}",
        "case", "elements", "old (s)", "new (s)", "new/old"
    );
    for arg in args {
        let path = Path::new(&arg);
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if !text.contains("\nscene:") {
            continue;
        }
        let scene = match Scene::from_yaml_file_entry(path, "scene") {
            Ok(s) => s,
            Err(e) => {
                println!("{arg:<60} scene not read: {e}");
                continue;
            }
        };
        let problem = match build_problem(&scene) {
            Ok(p) => p,
            Err(e) => {
                println!("{arg:<60} not built: {e}");
                continue;
            }
        };
        let model = &problem.model;
        // The altitude estimate (`Model::critical_time_step`: no model of the catalogue starts
        // mass-scaled or remeshed) and the element eigenvalue bound.
        let (old, _) = model.critical_time_step();
        let new = (0..model.element_count())
            .map(|e| {
                let c = model.material_of(e).constants();
                stable_length(model.min_altitude(e), &model.grad_n(e), c.lambda(), c.mu())
                    / c.dilatational_wave_speed()
            })
            .fold(f64::INFINITY, f64::min);
        println!(
            "{arg:<60} {:>8} {old:>12.4e} {new:>12.4e} {:>8.4}",
            model.element_count(),
            new / old
        );
        if let Some(iterations) = power {
            let limit = power_limit(model, iterations);
            println!(
                "{:<60} free-mesh limit (power, {iterations} its) {limit:.4e} s: {:.4} of old, {:.4} of new",
                "", limit / old, limit / new
            );
        }
    }
}
