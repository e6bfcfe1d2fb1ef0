//! What one remeshing does to the nail's resistance (issue 21): runs the nail case without
//! remeshing to a given time, then goes on for a number of steps four ways from that state:
//! without a remeshing, after a remeshing far from the nail (the block's deep corner), after
//! one of the elements at the nose's tip with the case's mesher settings, and after the same
//! region only subdivided (no smoothing, collapses or flips, so every new element lies inside
//! its parent and carries its `F` and history exactly). Each step prints the force on the nail
//! (the rate of change of its momentum) and the mean pressure of the block's elements whose
//! centroid lies within 1 mm of the tip.
//!
//! ```text
//! cargo run --release -p impact-solver --example remesh_release -- [time = 1.5e-5] [safety = 0.6]
//! ```
//! A smaller `safety` tells a step-size effect from a physical one.
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings, RunState};
use impact_solver::kinematics::signed_volume;
use impact_solver::mesh::ops::{centroids, grow_region, MesherOptions};
use impact_solver::problem::Problem;
use impact_solver::remesh::remesh_problem;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, Scene};
use nalgebra::Vector3;

/// Body indices of the case's scene.
const BLOCK: usize = 0;
const NAIL: usize = 1;
/// Steps run after the branch point.
const STEPS: usize = 24;

fn current(p: &Problem, s: &RunState) -> Vec<Vector3<f64>> {
    let m = &p.model;
    m.reference.iter().zip(&s.u).map(|(x, u)| x + u).collect()
}

fn nail_tip(p: &Problem, x: &[Vector3<f64>]) -> Vector3<f64> {
    p.model.bodies[NAIL]
        .nodes
        .clone()
        .map(|n| x[n])
        .min_by(|a, b| a.y.total_cmp(&b.y))
        .unwrap()
}

/// The nail's momentum along y (kg m/s).
fn nail_momentum(p: &Problem, s: &RunState) -> f64 {
    let m = &p.model;
    m.bodies[NAIL]
        .nodes
        .clone()
        .map(|n| m.mass[n] * s.v_full[n].y)
        .sum()
}

/// Volume-weighted mean pressure (Pa) of the block's elements whose centroid lies within 1 mm
/// of the tip, and how many they are.
fn tip_pressure(p: &Problem, s: &RunState) -> (f64, usize) {
    let m = &p.model;
    let x = current(p, s);
    let tip = nail_tip(p, &x);
    let cauchy = &s.history.bodies[BLOCK].as_ref().unwrap().cauchy;
    let c = centroids(&x, &m.tets);
    let (mut pv, mut v, mut count) = (0.0, 0.0, 0);
    for e in m.bodies[BLOCK].elements.clone() {
        if (c[e] - tip).norm() < 1.0e-3 {
            let volume = signed_volume(&m.tets[e].map(|k| x[k as usize]));
            let s = cauchy[e - m.bodies[BLOCK].elements.start];
            pv -= (s[0] + s[1] + s[2]) / 3.0 * volume;
            v += volume;
            count += 1;
        }
    }
    (pv / v, count)
}

fn go(label: &str, p: &Problem, settings: &ExplicitSettings, state: RunState) {
    let output = OutputSettings {
        dir: None,
        stem: "release".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::resume(p, settings.clone(), output, state).unwrap();
    let mut momentum = nail_momentum(p, &solver.state());
    for k in 0..STEPS {
        solver.step().unwrap();
        let s = solver.state();
        let now = nail_momentum(p, &s);
        let (pressure, count) = tip_pressure(p, &s);
        println!(
            "{label:<10} step {k:2}  t {:.4} us  dt {:.2e} s  force on the nail {:7.1} N  \
             tip-zone pressure {:5.0} MPa ({count} elements)",
            s.time * 1e6,
            s.time_step,
            (now - momentum) / s.time_step,
            pressure / 1e6
        );
        momentum = now;
    }
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let time = args.first().copied().unwrap_or(1.5e-5);
    let case =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/penetration/nail-200ms.yaml");
    let scene = Scene::from_yaml_file_entry(&case, "scene").unwrap();
    let Analysis::Explicit(ExplicitAnalysis {
        settings,
        remeshing,
    }) = &scene.analysis
    else {
        panic!("the nail case is an explicit analysis")
    };
    let mut settings = settings.clone();
    let remeshing = remeshing.clone().unwrap();
    let problem = build_problem(&scene).unwrap();
    let output = OutputSettings {
        dir: None,
        stem: "release".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::new(&problem, settings.clone(), output).unwrap();
    while solver.state().time < time {
        solver.step().unwrap();
    }
    let state = solver.state();
    drop(solver);
    settings.safety = args.get(1).copied().unwrap_or(settings.safety);

    let x = current(&problem, &state);
    let tip = nail_tip(&problem, &x);
    println!("t {:.3} us, tip at {:?}", state.time * 1e6, tip.as_slice());
    let c = centroids(&x, &problem.model.tets);
    let block = problem.model.bodies[BLOCK].elements.clone();
    let near = |p: Vector3<f64>, r: f64| -> Vec<usize> {
        let seed: Vec<usize> = block.clone().filter(|&e| (c[e] - p).norm() < r).collect();
        grow_region(&problem.model.tets, &seed, 1)
            .into_iter()
            .filter(|e| block.contains(e))
            .collect()
    };
    let case_mesher = MesherOptions {
        min_edge: remeshing.min_edge,
        surface_deviation: remeshing.surface_deviation,
        erode: remeshing.erode,
        erode_stretch: remeshing.erode_stretch,
        ..MesherOptions::default()
    };
    let subdivision = MesherOptions {
        smoothing_sweeps: 0,
        collapse_passes: 0,
        flip_passes: 0,
        min_edge: remeshing.min_edge,
        surface_deviation: 0.0,
        erode: false,
        erode_stretch: 0.0,
    };
    go("none", &problem, &settings, state.clone());
    let at_tip = tip + Vector3::new(0.2e-3, -0.3e-3, 0.2e-3);
    for (label, centre, radius, options) in [
        ("far", Vector3::new(0.2, 0.1, 0.2), 0.08, &case_mesher),
        ("tip", at_tip, 0.8e-3, &case_mesher),
        ("tip-split", at_tip, 0.8e-3, &subdivision),
    ] {
        let region = near(centre, radius);
        let remeshed = remesh_problem(&problem, &state, &region, options, 0.0).unwrap();
        println!(
            "{label}: {} elements remeshed; {}",
            region.len(),
            remeshed.record.summary()
        );
        go(label, &remeshed.problem, &settings, remeshed.state);
    }
}
