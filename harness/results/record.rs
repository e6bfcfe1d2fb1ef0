//! A kind's record in a case's result: stored as JSON under the kind's key
//! ([`CaseResult::records`]), read back as the kind's type, and an error naming the case, the key
//! and the field when it does not read.

use serde::Serialize;

use super::CaseResult;

/// A kind's record that does not read as its type: the report shows it in the kind's section
/// instead of leaving the case out.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("case {case}: the `{key}` record does not read: {message}")]
pub struct RecordError {
    /// The case, with its variant.
    pub case: String,
    /// The kind's key (`contact_comparison`, `material`, ...) or record file.
    pub key: String,
    /// The JSON reader's error, with the field and the type it expected.
    pub message: String,
}

impl CaseResult {
    /// The record a kind stored under `key`, read back as its type; `None` when there is none
    /// or it does not read. The report reads with [`CaseResult::read_record`], which tells the
    /// two apart.
    pub fn record<T: serde::de::DeserializeOwned>(&self, key: &str) -> Option<T> {
        self.read_record(key).ok().flatten()
    }

    /// The record a kind stored under `key`, read back as its type: `None` when there is none,
    /// an error naming the case, the key and the field when it does not read as `T` (a results
    /// file of another version, or edited by hand).
    pub fn read_record<T: serde::de::DeserializeOwned>(
        &self,
        key: &str,
    ) -> Result<Option<T>, RecordError> {
        let Some(value) = self.records.get(key) else {
            return Ok(None);
        };
        T::deserialize(value).map(Some).map_err(|e| RecordError {
            case: self.label(),
            key: key.to_string(),
            message: e.to_string(),
        })
    }

    /// `id`, or `id [variant]` for a variant other than the case's own analysis.
    pub fn label(&self) -> String {
        if self.variant.is_empty() || self.variant == "default" {
            self.id.clone()
        } else {
            format!("{} [{}]", self.id, self.variant)
        }
    }

    /// Stores a kind's record under `key`.
    pub fn set_record<T: Serialize>(&mut self, key: &str, record: &T) {
        match serde_json::to_value(record) {
            Ok(v) => {
                self.records.insert(key.to_string(), v);
            }
            Err(e) => eprintln!("{}: the `{key}` record could not be stored: {e}", self.id),
        }
    }
}
