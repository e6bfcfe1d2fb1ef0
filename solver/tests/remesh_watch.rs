//! What a run that remeshes writes besides its history (issue 21, the report's penetration
//! section): the remeshing records as CSV rows written as they come, so that a run that stops
//! early keeps them; the pictures of the mesh in a plane; the stress near a probe around each
//! remeshing. The run is the sheared block of `remesh_run.rs` (a soft block sheared by its
//! boundary, remeshed as its elements distort), through `analysis::execute` as a scene runs.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use std::path::{Path, PathBuf};

use common::*;
use impact_solver::analysis::{execute, ExecuteOptions};
use impact_solver::dynamics::ExplicitSettings;
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::ops::distortion;
use impact_solver::problem::Problem;
use impact_solver::remesh::{
    von_mises, RemeshSettings, SectionFrame, NEAR_TIP_CSV_HEADER, REMESHING_CSV_HEADER,
};
use impact_solver::scene::{Analysis, ExplicitAnalysis};
use impact_solver::SolverError;

const SOFT: IsotropicElastic = IsotropicElastic {
    density: 1000.0,
    youngs_modulus: 1.0e7,
    poisson_ratio: 0.3,
};
const SIZE: f64 = 0.1;
const END: f64 = 0.02;

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("impact-remesh-watch-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The sheared block (interior nodes perturbed, boundary nodes on the box's faces exactly),
/// with a displacement probe `top` on its top face, and the analysis that remeshes it with the
/// `remeshing` options (YAML, after `body: body`) and a collapse limit 1.3 times the initial
/// worst ratio.
fn sheared_block(remeshing: &str) -> (Problem, Analysis) {
    let size = [SIZE; 3];
    let mut p = problem(
        box_body(size, [4, 4, 4], 0.3, 11),
        MaterialModel::SaintVenantKirchhoff(SOFT),
    );
    shear_the_box(&mut p, size, 1.0 / END);
    // The limit 30 % above the mesh's initial worst distortion, as the run measures it.
    let initial = p
        .model
        .tets
        .iter()
        .map(|t| distortion(&t.map(|n| p.model.reference[n as usize])))
        .fold(0.0, f64::max);
    let mut settings = ExplicitSettings::new(END);
    settings.safety = 0.5;
    settings.history_interval = Some(END / 200.0);
    let yaml = format!(
        "{{ body: body, check_every: 5, collapse_limit: {}, {remeshing} }}",
        1.3 * initial
    );
    let parsed: RemeshSettings = serde_norway::from_str(&yaml).unwrap();
    let analysis = ExplicitAnalysis {
        settings,
        remeshing: Some(parsed),
    };
    (p, Analysis::Explicit(analysis))
}

fn run(dir: &Path, problem: &mut Problem, analysis: &Analysis) -> Result<(), SolverError> {
    let options = ExecuteOptions {
        out: Some(dir),
        stem: "shear",
        final_state: true,
        fields: false,
        time_limit_s: None,
        stop: None,
        ranks: None,
        log: &impact_solver::analysis::log_to_stderr,
    };
    execute(problem, analysis, &options, &mut |_| {}).map(|_| ())
}

fn lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

fn frame(dir: &Path, k: usize) -> SectionFrame {
    let text = std::fs::read_to_string(dir.join(format!("shear_mesh_{k}.json"))).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Area of a picture's triangles (m^2).
fn area(f: &SectionFrame) -> f64 {
    f.bodies
        .iter()
        .flat_map(|b| &b.triangles)
        .map(|t| 0.5 * ((t[2] - t[0]) * (t[5] - t[1]) - (t[4] - t[0]) * (t[3] - t[1])).abs())
        .sum()
}

/// A run that stops with an error at its second remeshing (at most one allowed) has written
/// the first remeshing's row, the pictures at the start, after the remeshing and at the last
/// step it completed, and the stress near the probe around the remeshing: the rows of the
/// remeshing at its time, the steps before it on the old mesh, the transferred state, the
/// steps after.
#[test]
fn a_run_that_stops_early_keeps_its_records_pictures_and_stresses() {
    let dir = temp_dir("stopped");
    let (mut p, analysis) = sheared_block(
        "max_remeshings: 1, section: { axis: z, value: 0.0 }, \
         near_tip: { probe: top, radius: 0.04, steps: 6 }",
    );
    let err = run(&dir, &mut p, &analysis).unwrap_err();
    assert!(err.to_string().contains("remeshings allowed"), "{err}");

    let rows = lines(&dir.join("shear_remeshing.csv"));
    assert_eq!(rows[0], REMESHING_CSV_HEADER);
    assert_eq!(rows.len(), 2, "one remeshing: {rows:?}");
    let time: f64 = rows[1].split(',').next().unwrap().parse().unwrap();
    assert!(time > 0.0 && time < END);

    // Start, after the remeshing, end (the last step completed).
    let frames: Vec<SectionFrame> = (0..3).map(|k| frame(&dir, k)).collect();
    assert!(!dir.join("shear_mesh_3.json").exists());
    let events: Vec<&str> = frames.iter().map(|f| f.event.as_str()).collect();
    assert_eq!(events, ["start", "remeshing", "end"]);
    assert_eq!(frames[1].time, time);
    assert!(frames[2].time > time);
    assert_eq!([frames[0].remeshings, frames[1].remeshings], [0, 1]);
    for f in &frames {
        assert_eq!(f.bodies.len(), 1);
        assert!(f.bodies[0].remeshed);
        // The face z = 0 of the box, sheared in its own plane (x += y t / END): its area is
        // kept, whatever the mesh.
        let a = area(f);
        assert!(
            (a - SIZE * SIZE).abs() < 1e-12,
            "area {a} at t = {}",
            f.time
        );
        // The drawing axes are x, y: the top edge is at y = SIZE, sheared by t / END.
        let top = f.bodies[0]
            .triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[2], t[3]), (t[4], t[5])])
            .filter(|&(_, y)| y == SIZE)
            .map(|(x, _)| x)
            .fold(f64::NEG_INFINITY, f64::max);
        let sheared = SIZE + SIZE * f.time / END;
        assert!(
            (top - sheared).abs() < 1e-9,
            "top corner at x = {top}, not {sheared}"
        );
    }
    assert!(frames[1].bodies[0].elements > frames[0].bodies[0].elements);
    assert!(frames[1].bodies[0].triangles.len() >= frames[0].bodies[0].triangles.len());

    let near = lines(&dir.join("shear_near_tip.csv"));
    assert_eq!(near[0], NEAR_TIP_CSV_HEADER);
    let near: Vec<Vec<f64>> = near[1..]
        .iter()
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let offsets: Vec<i64> = near.iter().map(|r| r[1] as i64).collect();
    assert_eq!(offsets[..7], [-6, -5, -4, -3, -2, -1, 0]);
    assert!(near.iter().all(|r| r[0] == 1.0), "all rows of remeshing 1");
    assert!(offsets[7..].iter().zip(1..).all(|(&o, k)| o == k));
    let before = &near[5];
    let after = &near[6];
    assert_eq!(before[3], time);
    assert_eq!(after[3], time);
    for r in &near {
        println!("{r:?}");
    }
    // The transfer keeps a near-affine state: the mean stress moves by little.
    let jump = (after[6] - before[6]).abs() / before[6];
    println!(
        "mean von Mises near the probe {:.6e} -> {:.6e} Pa (max {:.6e} -> {:.6e})",
        before[6], after[6], before[5], after[5]
    );
    assert!(before[6] > 0.0 && jump < 0.05, "jump {jump}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A window keeps the triangles with a node inside it; a plane through the inside of a body
/// (x = half the box, a plane of the unperturbed box's grid) has faces only between two
/// elements, and no picture of it.
#[test]
fn a_window_restricts_a_picture_and_an_inner_plane_has_none() {
    let dir = temp_dir("window");
    let (mut p, analysis) = sheared_block(
        "max_remeshings: 0, section: { axis: z, window: [[0, 0, -1], [0.05, 0.05, 1]] }",
    );
    let _ = run(&dir, &mut p, &analysis);
    let f = frame(&dir, 0);
    assert_eq!(f.window, Some([[0.0, 0.0], [0.05, 0.05]]));
    let all = f.bodies[0].triangles.len();
    assert!(all > 0);
    for t in &f.bodies[0].triangles {
        let inside = (0..3).any(|i| t[2 * i] <= 0.05 && t[2 * i + 1] <= 0.05);
        assert!(inside, "{t:?}");
    }
    let a = area(&f);
    assert!(a > 0.25 * SIZE * SIZE - 1e-12 && a < SIZE * SIZE, "{a}");

    let size = [SIZE; 3];
    let mut inner = problem(
        box_body(size, [4, 4, 4], 0.0, 1),
        MaterialModel::SaintVenantKirchhoff(SOFT),
    );
    let analysis = ExplicitAnalysis {
        settings: ExplicitSettings::new(1e-4),
        remeshing: Some(
            serde_norway::from_str("{ body: body, section: { axis: x, value: 0.05 } }").unwrap(),
        ),
    };
    run(&dir, &mut inner, &Analysis::Explicit(analysis)).unwrap();
    let f = frame(&dir, 0);
    assert!(f.bodies.is_empty(), "{:?}", f.bodies);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The von Mises stress: 0 under pressure, `|s|` in uniaxial stress, `sqrt(3) |t|` in shear.
#[test]
fn von_mises_of_simple_states() {
    assert_eq!(von_mises(&[-5.0, -5.0, -5.0, 0.0, 0.0, 0.0]), 0.0);
    assert!((von_mises(&[7.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 7.0).abs() < 1e-12);
    assert!((von_mises(&[0.0, 0.0, 0.0, 0.0, 2.0, 0.0]) - 2.0 * 3f64.sqrt()).abs() < 1e-12);
}
