//! Parameter files of the microplane concrete model (`cases/materials/*.yaml`).
//!
//! A file holds `parameters:` (a [`MicroplaneParameters`], every key checked) and, optionally, a
//! free-form `calibration:` record written by the calibration routine (targets, residuals,
//! provenance), which loaders accept and ignore. Any other top-level key is an error that names
//! the file and the line.

use std::path::Path;

use serde::de::IgnoredAny;
use serde::Deserialize;

use super::microplane::MicroplaneParameters;
use crate::error::{Result, SolverError};

/// The content of a parameter file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MicroplaneFile {
    /// The model's parameters (the `parameters:` map of the file).
    pub parameters: MicroplaneParameters,
    /// The calibration record, not read here.
    #[serde(default)]
    pub calibration: Option<IgnoredAny>,
}

impl MicroplaneFile {
    /// Parses the text of a parameter file; `source` names it in error messages, which carry the
    /// line. The parameters are validated too.
    pub fn from_yaml(text: &str, source: &str) -> Result<Self> {
        let invalid = |message: String| SolverError::InvalidScene {
            entity: format!("microplane parameter file `{source}`"),
            message,
        };
        let de = serde_norway::Deserializer::from_str(text);
        let file: Self = serde_norway::with::singleton_map_recursive::deserialize(de)
            .map_err(|e| invalid(e.to_string()))?;
        file.parameters
            .validate()
            .map_err(|m| invalid(format!("parameters: {m}")))?;
        Ok(file)
    }
}

/// Reads and validates the microplane parameters of the file at `path`.
pub fn read_microplane_file(path: &Path) -> Result<MicroplaneParameters> {
    let text = std::fs::read_to_string(path).map_err(|e| SolverError::InvalidScene {
        entity: format!("microplane parameter file `{}`", path.display()),
        message: format!("cannot read it: {e}"),
    })?;
    let text = without_byte_order_mark(&text);
    Ok(MicroplaneFile::from_yaml(text, &path.display().to_string())?.parameters)
}

/// `text` without the UTF-8 byte-order mark that Windows editors put before a file's first
/// line (of a scene, a case or a parameter file): YAML does not expect it there, and the first key would read as `\u{feff}name`, so that
/// every file would miss its first field.
pub fn without_byte_order_mark(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHIPPED: &str = include_str!("../../../cases/materials/thesis-concrete.yaml");

    /// The shipped file without its `calibration:` record, if it has one.
    fn parameters_only() -> &'static str {
        SHIPPED.split("\ncalibration:").next().unwrap()
    }

    #[test]
    fn the_shipped_file_reads_and_a_calibration_record_is_ignored() {
        let plain = MicroplaneFile::from_yaml(parameters_only(), "plain.yaml").unwrap();
        let with_record = format!(
            "{}\ncalibration:\n  targets: {{ ft: 2.7e6 }}\n  residuals: [0.01, -0.02]\n",
            parameters_only()
        );
        let recorded = MicroplaneFile::from_yaml(&with_record, "x.yaml").unwrap();
        assert_eq!(plain.parameters, recorded.parameters);
        let shipped = MicroplaneFile::from_yaml(SHIPPED, "thesis-concrete.yaml").unwrap();
        assert_eq!(plain.parameters, shipped.parameters);
        assert_eq!(plain.parameters.youngs_modulus, 30e9);
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_file() {
        let typo = parameters_only().replace("  e1:", "  e_1:");
        let msg = MicroplaneFile::from_yaml(&typo, "typo.yaml")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("typo.yaml") && msg.contains("e_1"), "{msg}");
        let top = format!("{}\nnotes: 1\n", parameters_only());
        let msg = MicroplaneFile::from_yaml(&top, "top.yaml")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("top.yaml") && msg.contains("notes"), "{msg}");
        let bad: String = parameters_only()
            .lines()
            .map(|l| match l.trim_start().starts_with("alpha:") {
                true => "  alpha: 1.5\n".to_string(),
                false => format!("{l}\n"),
            })
            .collect();
        let msg = MicroplaneFile::from_yaml(&bad, "bad.yaml")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("bad.yaml") && msg.contains("alpha"), "{msg}");
    }
}
