//! A contact pair's solver as a scene (or a catalogue variant) writes it: the solver's one
//! spelling from `contact::registry`, alone or with its stopping rule.
//!
//! ```yaml
//! solver: gauss-seidel/thesis                                        # the default
//! solver: { name: conic/coulomb, tolerance: 1.0e-10, max_iterations: 200 }
//! ```
//!
//! Read by hand rather than by a derived untagged enum, so that an unknown name or key is an
//! error that names the known ones instead of "data did not match any variant".

use std::fmt;

use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::contact::registry::{SolverChoice, SolverKind};

/// The keys of the long form.
const KEYS: &[&str] = &["name", "tolerance", "max_iterations"];

/// Which solver a pair uses, and the stopping rule where the scene overrides the solver's
/// defaults ([`SolverChoice::new`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactSolverSpec {
    /// The solver, by its one name in `contact::registry` (default `gauss-seidel/thesis`).
    pub kind: SolverKind,
    /// What the solver's stopping test bounds (default 1e-10).
    pub tolerance: Option<f64>,
    /// Sweeps (Gauss-Seidel) or interior-point iterations per conic solve (default: the
    /// registry's per solver).
    pub max_iterations: Option<usize>,
}

impl ContactSolverSpec {
    /// The solver and stopping rule the stepper uses.
    pub fn choice(&self) -> SolverChoice {
        let mut choice = SolverChoice::new(self.kind);
        if let Some(tolerance) = self.tolerance {
            choice.limits.tolerance = tolerance;
        }
        if let Some(max_iterations) = self.max_iterations {
            choice.limits.max_iterations = max_iterations;
        }
        choice
    }
}

impl Serialize for ContactSolverSpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if self.tolerance.is_none() && self.max_iterations.is_none() {
            return serializer.serialize_str(self.kind.name());
        }
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry("name", self.kind.name())?;
        if let Some(tolerance) = self.tolerance {
            map.serialize_entry("tolerance", &tolerance)?;
        }
        if let Some(max_iterations) = self.max_iterations {
            map.serialize_entry("max_iterations", &max_iterations)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for ContactSolverSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(SpecVisitor)
    }
}

struct SpecVisitor;

impl<'de> Visitor<'de> for SpecVisitor {
    type Value = ContactSolverSpec;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            "a contact solver name, or { name, tolerance, max_iterations } with such a name",
        )
    }

    fn visit_str<E: de::Error>(self, name: &str) -> Result<Self::Value, E> {
        Ok(ContactSolverSpec {
            kind: SolverKind::from_name(name).map_err(E::custom)?,
            ..Default::default()
        })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut spec = ContactSolverSpec::default();
        let mut named = false;
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "name" => {
                    let name: String = map.next_value()?;
                    spec.kind = SolverKind::from_name(&name).map_err(de::Error::custom)?;
                    named = true;
                }
                "tolerance" => spec.tolerance = Some(map.next_value()?),
                "max_iterations" => spec.max_iterations = Some(map.next_value()?),
                other => return Err(de::Error::unknown_field(other, KEYS)),
            }
        }
        if !named {
            return Err(de::Error::missing_field("name"));
        }
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(yaml: &str) -> Result<ContactSolverSpec, serde_norway::Error> {
        serde_norway::from_str(yaml)
    }

    #[test]
    fn a_name_alone_or_with_its_stopping_rule_reads_and_writes_back() {
        let short = read("conic/relaxed").unwrap();
        assert_eq!(short.kind, SolverKind::ConicRelaxed);
        assert_eq!(short.choice(), SolverChoice::new(SolverKind::ConicRelaxed));
        let long =
            read("{ name: gauss-seidel/thesis, tolerance: 1.0e-12, max_iterations: 9 }").unwrap();
        assert_eq!(long.choice().limits.tolerance, 1e-12);
        assert_eq!(long.choice().limits.max_iterations, 9);
        for spec in [short, long] {
            let text = serde_norway::to_string(&spec).unwrap();
            assert_eq!(read(&text).unwrap(), spec, "{text}");
        }
    }

    #[test]
    fn old_spellings_and_unknown_keys_are_errors_naming_what_is_known() {
        let e = read("gauss_seidel").unwrap_err().to_string();
        assert!(
            e.contains("gauss-seidel/thesis") && e.contains("conic/coulomb"),
            "{e}"
        );
        let e = read("{ conic: { mode: coulomb } }")
            .unwrap_err()
            .to_string();
        assert!(e.contains("conic") && e.contains("name"), "{e}");
        let e = read("{ tolerance: 1.0e-9 }").unwrap_err().to_string();
        assert!(e.contains("name"), "{e}");
    }
}
