//! The elastic refinement reference of `beam/static-3pt` on 25 mm cells (120 x 24 x 12, 111 k
//! unknowns), timed, to measure the linear solvers' memory and time (issue 20):
//!
//! ```text
//! /usr/bin/time -v cargo run --release -p impact-references --example elastic_reference_25mm -- [cg|lu] [nx ny nz]
//! ```
//!
//! (`/usr/bin/time -v` on the built binary, `target/release/examples/elastic_reference_25mm`,
//! gives its own peak memory, "Maximum resident set size", rather than cargo's.)

#![allow(clippy::unwrap_used)]

use std::path::Path;
use std::time::Instant;

use impact_references::elastic_refinement::{solve_elastic, ElasticStiffnessSpec};
use impact_solver::scene::{Component, Scene};
use impact_solver::statics::LinearSolver;

/// The scene of a case file (its `scene:` entry), relative paths resolved against the file.
fn case_scene(case: &Path) -> Scene {
    Scene::from_yaml_file_entry(case, "scene").unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let linear_solver = match args.first().map(String::as_str) {
        None | Some("cg") => LinearSolver::conjugate_gradient(),
        Some("lu") => LinearSolver::Lu,
        Some(other) => panic!("unknown solver `{other}`: cg or lu"),
    };
    let divisions = match &args[1.min(args.len())..] {
        [] => [120, 24, 12],
        [x, y, z] => [x.parse().unwrap(), y.parse().unwrap(), z.parse().unwrap()],
        _ => panic!("divisions are three numbers: nx ny nz"),
    };
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/beam/static-3pt.yaml");
    let scene = case_scene(&case);
    let spec = ElasticStiffnessSpec {
        condition: "load_plate".into(),
        component: Component::Y,
        divisions,
        displacement: -1.0e-4,
    };
    let start = Instant::now();
    let solved = solve_elastic(&scene, &spec, linear_solver).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    println!("{}", solved.description);
    println!(
        "stiffness {:e} N/m ({:.2} MN/m); {} elements, {} unknowns; {} Newton iterations, {} \
         conjugate-gradient iterations; {seconds:.1} s",
        solved.stiffness,
        solved.stiffness / 1e6,
        solved.elements,
        solved.unknowns,
        solved.newton_iterations,
        solved.linear_iterations
    );
}
