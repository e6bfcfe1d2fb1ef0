//! The conic contact solver on the external problems of `references/contact-problems` (Siconos
//! test data, FCLIB family, Apache-2.0): every solve returns a report in both modes, and the Coulomb mode
//! solves the two small problems to a natural-map error of 1e-6 (Acary, Bremond & Huber 2018
//! normalisation, `/||q||`).

use std::path::PathBuf;

use impact_solver::contact::conic::{associated_natural_map, ConicMode, ConicSolver};
use impact_solver::contact::problem::natural_map_error;
use impact_solver::contact::problem_file::read_problem;
use impact_solver::contact::solver::{ContactSolver, SolveLimits};

/// The committed problem folder (see its README for origin and licence).
fn problem_folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../references/contact-problems")
}

#[test]
fn external_problems_in_both_modes() {
    let folder = problem_folder();
    let entries = std::fs::read_dir(&folder).unwrap_or_else(|e| {
        panic!(
            "the external contact problems are committed at {}: {e}; restore the checkout",
            folder.display()
        )
    });
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    println!(
        "{:<32} {:<8} {:<14} {:>5} {:>5} {:>8} {:>9} {:>9}",
        "file", "mode", "status", "ipm", "outer", "ms", "nat.map", "assoc.map"
    );
    // nat.map: natural-map error of Coulomb's law (ABH 2018, /||q||); assoc.map: the same for
    // the associated law the relaxed mode solves.
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let (problem, _) = read_problem(path).unwrap_or_else(|e| panic!("{name}: {e}"));
        for mode in [ConicMode::Relaxed, ConicMode::Coulomb] {
            let mut solver = ConicSolver::new(mode);
            let report = solver
                .solve(&problem, &SolveLimits::default())
                .unwrap_or_else(|e| panic!("{name} {mode:?}: {e}"));
            assert_eq!(report.r.len(), problem.q.len());
            let error = natural_map_error(&problem, &report.r).relative;
            println!(
                "{:<32} {:<8} {:<14} {:>5} {:>5} {:>8.2} {:>9.2e} {:>9.2e}",
                name,
                format!("{mode:?}"),
                report.status.label(),
                report.iterations,
                report.outer_iterations,
                report.seconds * 1e3,
                error,
                associated_natural_map(&problem, &report.r)
            );
            for note in &report.notes {
                println!("    note: {note}");
            }
            // Measured: 9.6e-8 and 5.8e-12 (Clarabel 0.11, tolerance 1e-8).
            let small = ["frictioncontact3d_1c", "fc3d_example1"].contains(&name.as_str());
            if mode == ConicMode::Coulomb && small {
                assert!(report.status.converged(), "{name}: {:?}", report.status);
                assert!(error <= 1e-6, "{name}: natural-map error {error:e}");
            }
        }
    }
}
