//! Calls a reference script of `references/crosscheck/` through an embedded Python interpreter
//! (pyo3, cargo feature `python`).
//!
//! A script is a module with `run(request: str) -> str`: JSON in, JSON out (see
//! `references/crosscheck/README.md`). The interpreter is the one pyo3 was built against; the
//! packages come from its `site-packages`, or from the virtual environment named by
//! `$VIRTUAL_ENV` when one is active (an embedded interpreter does not read it by itself).

use std::path::Path;

use super::error::CrosscheckError;

/// Whether this build can call Python (the `python` feature).
pub const ENABLED: bool = cfg!(feature = "python");

/// The folder of the reference scripts and their caches: `references/crosscheck/`.
pub fn scripts_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("references")
        .join("crosscheck")
}

/// Runs `run(request)` of the script `name` (a file of [`scripts_dir`]) and parses its answer.
#[cfg(feature = "python")]
pub fn call_script(
    name: &str,
    request: &serde_json::Value,
) -> Result<serde_json::Value, CrosscheckError> {
    use pyo3::prelude::*;
    use std::ffi::CString;

    let path = scripts_dir().join(name);
    let code = std::fs::read_to_string(&path).map_err(|e| CrosscheckError::ReadScript {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let cstring = |s: &str| {
        CString::new(s).map_err(|e| CrosscheckError::File {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    };
    let (code, file, module) = (
        cstring(&code)?,
        cstring(&path.display().to_string())?,
        cstring(name.trim_end_matches(".py"))?,
    );
    let request = request.to_string();
    let answer: Result<String, PyErr> = Python::attach(|py| {
        if let Some(venv) = std::env::var_os("VIRTUAL_ENV") {
            // A POSIX virtual environment keeps its packages in lib/pythonX.Y/site-packages,
            // whatever layout the embedded interpreter's own installation uses.
            let sys = py.import("sys")?;
            let version: (u32, u32) = sys
                .getattr("version_info")?
                .extract::<(u32, u32, u32, String, u32)>()
                .map(|v| (v.0, v.1))?;
            let site = std::path::Path::new(&venv)
                .join("lib")
                .join(format!("python{}.{}", version.0, version.1))
                .join("site-packages");
            sys.getattr("path")?
                .call_method1("insert", (0, site.display().to_string()))?;
        }
        let module = PyModule::from_code(py, &code, &file, &module)?;
        module.getattr("run")?.call1((request,))?.extract()
    });
    let answer = answer.map_err(|e| {
        let hint = if e.to_string().contains("ModuleNotFoundError") {
            format!(
                ". Fix: `python3 -m pip install -r {}` (or activate the virtual environment that \
                 has them)",
                scripts_dir().join("requirements.txt").display()
            )
        } else {
            String::new()
        };
        CrosscheckError::Raised {
            name: name.into(),
            error: e.to_string(),
            hint,
        }
    })?;
    serde_json::from_str(&answer).map_err(|e| CrosscheckError::InvalidJson {
        name: name.into(),
        message: e.to_string(),
    })
}

/// Without the `python` feature no script can run: the caller uses the cached answer.
#[cfg(not(feature = "python"))]
pub fn call_script(
    name: &str,
    _request: &serde_json::Value,
) -> Result<serde_json::Value, CrosscheckError> {
    Err(CrosscheckError::NoPython { name: name.into() })
}
