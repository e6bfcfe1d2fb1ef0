//! Answers of the independent codes: fresh from the script (feature `python`) or from the cache
//! in `references/crosscheck/cache/`, which records the request each answer was computed for,
//! the date and the package versions.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::error::CrosscheckError;
use super::python;

/// How an independent answer was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AnswerMode {
    /// Computed by the script during this run (feature `python`).
    Fresh,
    /// Read from the cache file.
    Cached,
}

/// Where an independent answer came from, as the report states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// Computed in this run or read from the cache.
    pub mode: AnswerMode,
    /// Name of the Python script that computed the answer.
    pub script: String,
    /// When the answer was computed (the script's own UTC time stamp).
    pub date: String,
    /// The Python version that ran the script.
    pub python: String,
    /// Package name to version, as the script read them.
    #[serde(default)]
    pub packages: BTreeMap<String, String>,
    /// The cache file, relative to the repository.
    pub cache: String,
}

impl Provenance {
    /// One line: `cached answer of skfem_beam.py (2026-11-21T10:00:00Z; python 3.11.7,
    /// scikit-fem 12.0.2, ...) from references/crosscheck/cache/skfem-beam.json`.
    pub fn line(&self) -> String {
        let packages: Vec<String> = self
            .packages
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        let what = format!(
            "{} ({}; python {}, {})",
            self.script,
            self.date,
            self.python,
            packages.join(", ")
        );
        match self.mode {
            AnswerMode::Cached => format!(
                "CACHED answer of {what}, read from {} (built without the `python` feature)",
                self.cache
            ),
            AnswerMode::Fresh => format!("fresh answer of {what}, computed in this run"),
        }
    }
}

/// A cache file: the request and the script's answer to it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CacheEntry {
    /// The JSON request sent to the script; a cached answer is used only for the same request.
    pub request: Value,
    /// The script's JSON answer, with its provenance.
    pub answer: Value,
}

/// The cache file `name` of `references/crosscheck/cache/`.
pub fn cache_path(name: &str) -> PathBuf {
    python::scripts_dir().join("cache").join(name)
}

fn relative(path: &Path) -> String {
    path.strip_prefix(env!("CARGO_MANIFEST_DIR"))
        .unwrap_or(path)
        .display()
        .to_string()
}

/// The provenance the script wrote into its answer.
fn provenance(
    answer: &Value,
    mode: AnswerMode,
    cache: &Path,
) -> Result<Provenance, CrosscheckError> {
    let p = answer
        .get("provenance")
        .ok_or(CrosscheckError::NoProvenance)?;
    let text = |key: &str| {
        p.get(key)
            .and_then(Value::as_str)
            .map(str::to_string)
            .ok_or_else(|| CrosscheckError::ProvenanceKey { key: key.into() })
    };
    let packages = p
        .get("packages")
        .and_then(Value::as_object)
        .map(|m| {
            m.iter()
                .map(|(k, v)| (k.clone(), v.as_str().unwrap_or("?").to_string()))
                .collect()
        })
        .unwrap_or_default();
    Ok(Provenance {
        mode,
        script: text("script")?,
        date: text("date")?,
        python: text("python")?,
        packages,
        cache: relative(cache),
    })
}

/// Reads the cache file at `path`; the error names the file.
pub fn read_cache(path: &Path) -> Result<CacheEntry, CrosscheckError> {
    let text = std::fs::read_to_string(path).map_err(|e| CrosscheckError::NoCache {
        path: relative(path),
        message: e.to_string(),
    })?;
    serde_json::from_str(&text).map_err(|e| CrosscheckError::File {
        path: relative(path),
        message: e.to_string(),
    })
}

/// The keys at which two requests differ, for a message.
fn differences(a: &Value, b: &Value, at: &str, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                let (va, vb) = (
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                );
                differences(va, vb, &format!("{at}.{k}"), out);
            }
        }
        _ if a != b => out.push(format!("{at}: {a} here, {b} in the cache")),
        _ => {}
    }
}

/// The answer of `script` to `request`: computed now when this build has Python, otherwise the
/// cached one, which must have been computed for the same request (else an error says what
/// changed and how to refresh).
pub fn obtain(
    script: &str,
    request: &Value,
    cache: &Path,
) -> Result<(Value, Provenance), CrosscheckError> {
    if python::ENABLED {
        let answer = python::call_script(script, request)?;
        let p = provenance(&answer, AnswerMode::Fresh, cache)?;
        return Ok((answer, p));
    }
    let entry = read_cache(cache)?;
    if &entry.request != request {
        let mut diff = Vec::new();
        differences(request, &entry.request, "request", &mut diff);
        return Err(CrosscheckError::StaleCache {
            path: relative(cache),
            differences: diff.join("; "),
        });
    }
    let p = provenance(&entry.answer, AnswerMode::Cached, cache)?;
    Ok((entry.answer, p))
}

/// Computes the answer of `script` to `request` now and writes it, with the request, to
/// `cache`.
pub fn refresh(script: &str, request: &Value, cache: &Path) -> Result<Provenance, CrosscheckError> {
    let answer = python::call_script(script, request)?;
    let p = provenance(&answer, AnswerMode::Fresh, cache)?;
    let entry = CacheEntry {
        request: request.clone(),
        answer,
    };
    if let Some(dir) = cache.parent() {
        std::fs::create_dir_all(dir).map_err(|e| CrosscheckError::File {
            path: dir.display().to_string(),
            message: e.to_string(),
        })?;
    }
    let text = serde_json::to_string_pretty(&entry)?;
    std::fs::write(cache, text + "\n").map_err(|e| CrosscheckError::File {
        path: relative(cache),
        message: e.to_string(),
    })?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn answer() -> Value {
        json!({"provenance": {"script": "s.py", "date": "2026-11-21T00:00:00Z", "python": "3.11.7",
               "packages": {"numpy": "2.4.6"}}, "x": 1.5})
    }

    #[test]
    fn a_cached_answer_is_used_only_for_its_own_request() {
        if python::ENABLED {
            return; // with Python the script runs instead of the cache
        }
        let dir = std::env::temp_dir().join(format!("impact-vv-cache-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.json");
        let entry = CacheEntry {
            request: json!({"size": [3.0, 0.6], "young": 3.0e10}),
            answer: answer(),
        };
        std::fs::write(&path, serde_json::to_string(&entry).unwrap()).unwrap();
        let (a, p) = obtain("s.py", &entry.request, &path).unwrap();
        assert_eq!(a["x"], 1.5);
        assert_eq!(p.mode, AnswerMode::Cached);
        assert!(p.line().contains("CACHED") && p.line().contains("numpy 2.4.6"));
        assert!(p.line().contains("2026-11-21"));

        let other = json!({"size": [3.0, 0.5], "young": 3.0e10});
        let e = obtain("s.py", &other, &path).unwrap_err().to_string();
        assert!(
            e.contains("request.size") && e.contains("crosscheck-refresh"),
            "{e}"
        );

        let e = obtain("s.py", &other, &dir.join("missing.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no cached answer") && e.contains("missing.json"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn without_python_a_script_call_says_how_to_enable_it() {
        if python::ENABLED {
            return;
        }
        let e = python::call_script("skfem_beam.py", &json!({}))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--features python") && e.contains("requirements.txt"),
            "{e}"
        );
    }
}
