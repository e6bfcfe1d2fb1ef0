//! `impact-vv calibrate`: fits the microplane parameters of the thesis concrete to the targets of
//! MICROPLANE.md and writes them, with the value achieved for every target, to a material file.

use std::path::Path;

use impact_solver::material::microplane::calibration::{
    calibrate, starting_guess, CalibratedMaterial, CalibrationRecord, Targets,
};

/// The comment at the top of a calibrated material file.
const HEADER: &str = "\
# The concrete of the thesis' beam (chapter 10): E 30000 MPa, nu 0.18, fc 45 MPa, ft 2.7 MPa,
# GF 0.10 N/mm, rho 2300 kg/m^3, for the microplane model (shared/design/MICROPLANE.md).
# Written by the calibration (`calibration.command` below reproduces it); `calibration.outcomes`
# gives the value every target reaches with these parameters (quasi-static, single element).
";

/// Runs the calibration with `evaluations` optimiser evaluations per stage and writes the result
/// to `out`; returns whether every target is met.
pub fn run(out: &Path, evaluations: usize) -> Result<bool, String> {
    let targets = Targets::thesis_concrete();
    let started = std::time::Instant::now();
    let (parameters, evaluation) =
        calibrate(&starting_guess(), &targets, evaluations, &mut |line| {
            eprintln!("[{:6.1} s] {line}", started.elapsed().as_secs_f64())
        })?;
    let outcomes = evaluation.outcomes(&targets);
    let met = outcomes.iter().all(|o| o.met);
    for o in &outcomes {
        println!(
            "{:<58} {:>12.5} {:<6} target {:<22} {}",
            o.name,
            o.achieved,
            o.unit,
            o.target,
            if o.met { "met" } else { "MISSED" }
        );
    }
    let file = CalibratedMaterial {
        parameters,
        calibration: CalibrationRecord {
            command: format!(
                "cargo run --release --bin impact-vv -- calibrate --out {} --evaluations {evaluations}",
                out.display()
            ),
            evaluations,
            targets,
            outcomes,
        },
    };
    let yaml = serde_norway::to_string(&file).map_err(|e| e.to_string())?;
    std::fs::write(out, format!("{HEADER}{yaml}"))
        .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    println!(
        "wrote {} in {:.0} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(met)
}
