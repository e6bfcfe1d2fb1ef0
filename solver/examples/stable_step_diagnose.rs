//! Compares stable time-step estimates with the exact limit on Kuhn meshes of box cells of
//! aspect ratio 1..10 (issue O1, docs/stable-time-step.md):
//!
//! - `alt`: the altitude estimate `min_e h_e / c_d` (FORMULATION 2, before O1);
//! - `eig`: Irons' element bound `min_e 2 / omega_e` (`impact_solver::model::stable_step`);
//! - `free`, `bc`: the exact central-difference limit `2 / sqrt(lambda_max(M^-1 K))` of the
//!   assembled mesh (dense symmetric eigen solve), free and with the `x` dofs of the `x = 0`
//!   face held (the push scene of O1).
//!
//! Cells are `r x 1 x 1` (long, "needle") and `1 x r x r` (flat, "plate"), `r` the aspect
//! ratio, in boxes of `[6, 4, 4]` cells and of `[10, 1, 1]` cells (the one-cell bar of O1).
//!
//! Run: `cargo run --release -p impact-solver --example stable_step_diagnose`

use impact_solver::kinematics::shape_gradients;
use impact_solver::mesh::{box_mesh, element_quality, BoxSpec};
use impact_solver::model::stable_step::eigen_length;
use nalgebra::{DMatrix, Vector3};

/// `K = sum_e V B^T D B` and the lumped masses `rho V / 4` per node.
fn assemble(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    rho: f64,
    lambda: f64,
    mu: f64,
) -> (DMatrix<f64>, Vec<f64>) {
    let n = nodes.len();
    let mut k = DMatrix::<f64>::zeros(3 * n, 3 * n);
    let mut mass = vec![0.0; n];
    for tet in tets {
        let x = tet.map(|i| nodes[i as usize]);
        let (g, v) = shape_gradients(&x).expect("box cells have positive volumes");
        // Stiffness block of nodes a, b: V (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a.g_b) I).
        for a in 0..4 {
            for b in 0..4 {
                let block = (g[a] * g[b].transpose()) * lambda
                    + (g[b] * g[a].transpose()) * mu
                    + nalgebra::Matrix3::identity() * (mu * g[a].dot(&g[b]));
                let (ia, ib) = (3 * tet[a] as usize, 3 * tet[b] as usize);
                for i in 0..3 {
                    for j in 0..3 {
                        k[(ia + i, ib + j)] += v * block[(i, j)];
                    }
                }
            }
            mass[tet[a] as usize] += rho * v / 4.0;
        }
    }
    (k, mass)
}

/// `2 / sqrt(lambda_max)` of `M^-1 K` restricted to the free dofs.
fn exact_limit(k: &DMatrix<f64>, mass: &[f64], free: &[usize]) -> f64 {
    let m = free.len();
    let a = DMatrix::from_fn(m, m, |i, j| {
        let (p, q) = (free[i], free[j]);
        k[(p, q)] / (mass[p / 3] * mass[q / 3]).sqrt()
    });
    let lambda_max = a.symmetric_eigenvalues().max();
    2.0 / lambda_max.sqrt()
}

fn main() {
    let rho: f64 = 2300.0;
    println!(
        "{:>5} {:>6} {:>6} {:>10} | {:>7} {:>7} {:>7} | {:>7} {:>7}",
        "nu", "shape", "ratio", "divisions", "eig/alt", "free/alt", "bc/alt", "free/eig", "bc/eig"
    );
    for nu in [0.2f64, 0.3] {
        let e: f64 = 30.0e9;
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let c_d = ((lambda + 2.0 * mu) / rho).sqrt();
        for divisions in [[6, 4, 4], [10, 1, 1]] {
            for shape in ["needle", "plate"] {
                for ratio in [1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0] {
                    let cell: [f64; 3] = match shape {
                        "needle" => [ratio, 1.0, 1.0],
                        _ => [1.0, ratio, ratio],
                    };
                    let h = 0.01;
                    let spec = BoxSpec {
                        origin: [0.0; 3],
                        size: [0, 1, 2].map(|i| cell[i] * h * divisions[i] as f64),
                        divisions,
                        mirror: Vec::new(),
                    };
                    let mesh = box_mesh(&spec);
                    let mut alt = f64::INFINITY;
                    let mut eig = f64::INFINITY;
                    for tet in &mesh.tets {
                        let x = tet.map(|i| mesh.nodes[i as usize]);
                        let (g, _) = shape_gradients(&x).expect("positive volume");
                        alt = alt.min(element_quality(&x).min_altitude / c_d);
                        eig = eig.min(eigen_length(&g, lambda, mu) / c_d);
                    }
                    let (k, mass) = assemble(&mesh.nodes, &mesh.tets, rho, lambda, mu);
                    let all: Vec<usize> = (0..3 * mesh.nodes.len()).collect();
                    let held: Vec<usize> = all
                        .iter()
                        .copied()
                        .filter(|&d| !(d % 3 == 0 && mesh.nodes[d / 3].x.abs() < 1e-12))
                        .collect();
                    let free = exact_limit(&k, &mass, &all);
                    let bc = exact_limit(&k, &mass, &held);
                    println!(
                        "{nu:>5} {shape:>6} {ratio:>6} {:>10} | {:>7.3} {:>7.3} {:>7.3} | {:>7.3} {:>7.3}",
                        format!("{divisions:?}").replace(' ', ""),
                        eig / alt,
                        free / alt,
                        bc / alt,
                        free / eig,
                        bc / eig
                    );
                }
            }
        }
    }
}
