//! `impact-vv calibrate`: fits the microplane parameters to the calibration targets.

use std::path::Path;
use std::process::ExitCode;

/// Calibrates into `out` with `evaluations` model evaluations: status 0 when every target is
/// met, 1 when some are missed, 2 on an error.
pub fn exec(out: &Path, evaluations: usize, targets: Option<&Path>) -> ExitCode {
    match crate::calibrate::run(out, evaluations, targets) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!(
                "some targets are missed: see the table above and {}",
                out.display()
            );
            ExitCode::from(1)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
