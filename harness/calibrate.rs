//! `impact-vv calibrate`: fits the microplane parameters of the thesis concrete to the targets of
//! MICROPLANE.md and writes them, with the value achieved for every target, to a material file.
//! `--targets FILE` calibrates another concrete instead: the file gives its elastic constants,
//! its targets and the comment written at the top of the material file ([`TargetsFile`]).

use std::path::Path;

use impact_solver::material::microplane::calibration::{
    calibrate, starting_guess, CalibratedMaterial, CalibrationRecord, Targets,
};

/// The comment at the top of a calibrated material file.
const HEADER: &str = "\
# The concrete of the thesis' beam (chapter 10): E 30000 MPa, nu 0.18, fc 45 MPa, ft 2.7 MPa,
# GF 0.10 N/mm, rho 2300 kg/m^3, for the microplane model (docs/MICROPLANE.md).
# Written by the calibration (`calibration.command` below reproduces it); `calibration.outcomes`
# gives the value every target reaches with these parameters (quasi-static, single element).
";

/// A concrete to calibrate other than the thesis's: measured elastic constants and density (kept
/// as they are) and the strength and fracture targets. The starting guess is the thesis's with
/// these elastic constants and `s_i_min = -ft`.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetsFile {
    /// The comment at the top of the written material file (source of the data).
    pub header: String,
    /// kg/m^3.
    pub density: f64,
    /// Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio (dimensionless).
    pub poisson_ratio: f64,
    /// The strengths, strains, fracture energy and bands the calibration aims at.
    pub targets: Targets,
}

/// Why the calibration cannot run or write its result: each message names the file.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// The targets file cannot be read.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
    /// The targets file is not valid YAML of targets.
    #[error("{path}: {message}")]
    Targets {
        /// The file.
        path: String,
        /// The YAML reader's error.
        message: String,
    },
    /// The optimiser failed.
    #[error("calibration failed: {0}")]
    Failed(impact_solver::material::microplane::calibration::CalibrationError),
    /// The parameters cannot be written as YAML.
    #[error(transparent)]
    Yaml(#[from] serde_norway::Error),
    /// The parameter file cannot be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// The operating system's reason.
        message: String,
    },
}

/// Runs the calibration with `evaluations` optimiser evaluations per stage and writes the result
/// to `out`; returns whether every target is met. `targets_file`: another concrete than the
/// thesis's ([`TargetsFile`]).
pub fn run(
    out: &Path,
    evaluations: usize,
    targets_file: Option<&Path>,
) -> Result<bool, CalibrateError> {
    let (targets, start, header) = match targets_file {
        None => (
            Targets::thesis_concrete(),
            starting_guess(),
            HEADER.to_string(),
        ),
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| CalibrateError::Read {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
            let file: TargetsFile =
                serde_norway::from_str(&text).map_err(|e| CalibrateError::Targets {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?;
            let mut start = starting_guess();
            start.density = file.density;
            start.youngs_modulus = file.youngs_modulus;
            start.poisson_ratio = file.poisson_ratio;
            start.s_i_min = -file.targets.ft;
            let header = file
                .header
                .lines()
                .map(|l| format!("# {l}\n"))
                .collect::<String>();
            (file.targets, start, header)
        }
    };
    let started = std::time::Instant::now();
    let (parameters, evaluation) = calibrate(&start, &targets, evaluations, &mut |line| {
        eprintln!("[{:6.1} s] {line}", started.elapsed().as_secs_f64())
    })
    .map_err(CalibrateError::Failed)?;
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
                "cargo run --release --bin impact-vv -- calibrate --out {} --evaluations {evaluations}{}",
                out.display(),
                targets_file
                    .map(|p| format!(" --targets {}", p.display()))
                    .unwrap_or_default()
            ),
            evaluations,
            targets,
            outcomes,
        },
    };
    let yaml = serde_norway::to_string(&file)?;
    std::fs::write(out, format!("{header}{yaml}")).map_err(|e| CalibrateError::Write {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    println!(
        "wrote {} in {:.0} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(met)
}
