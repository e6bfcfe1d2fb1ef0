//! An explicit analysis as a scene writes it: the integrator's settings
//! ([`ExplicitSettings`], owned by `dynamics`) and, in the same YAML map, the remeshing of one
//! body ([`RemeshSettings`], owned by `remesh`). The integrator never sees the remeshing: the
//! driver (`analysis::execute`) hands it to the remeshing run, which pauses the integrator.
//!
//! The map is read in one pass by the settings' own (derived) reader, with the `remeshing` key
//! taken out on the way, so every key keeps its checks and its messages (an unknown key, with
//! `remeshing` among the keys expected; a wrong type; with the line and column of the file).

use std::fmt;
use std::sync::OnceLock;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

use crate::dynamics::ExplicitSettings;
use crate::error::Result;
use crate::remesh::RemeshSettings;

/// The settings of an explicit analysis: the integrator's, and the remeshing of one body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExplicitAnalysis {
    /// The integrator's settings: end time, time step, output intervals, stopping rules.
    #[serde(flatten)]
    pub settings: ExplicitSettings,
    /// Adaptive remeshing of one body (thesis chapter 8); `None` runs on the initial mesh.
    pub remeshing: Option<RemeshSettings>,
}

impl From<ExplicitSettings> for ExplicitAnalysis {
    /// An analysis on the initial mesh (no remeshing).
    fn from(settings: ExplicitSettings) -> Self {
        Self {
            settings,
            remeshing: None,
        }
    }
}

impl ExplicitAnalysis {
    /// Checks the settings under `key` (`analysis.explicit` or `analysis.release.explicit`),
    /// then the remeshing keys (`RemeshSettings::validate`).
    pub fn validate(&self, key: &str) -> Result<()> {
        self.settings.validate(key)?;
        if let Some(r) = &self.remeshing {
            r.validate()?;
        }
        Ok(())
    }
}

/// The key under which a scene writes the remeshing.
const REMESHING: &str = "remeshing";

impl<'de> Deserialize<'de> for ExplicitAnalysis {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<Self, D::Error> {
        let mut remeshing = None;
        let settings = ExplicitSettings::deserialize(TakeRemeshing {
            inner: deserializer,
            remeshing: &mut remeshing,
        })?;
        Ok(Self {
            settings,
            remeshing: remeshing.flatten(),
        })
    }
}

/// A deserializer that hands the map to the settings' reader without its `remeshing` entry,
/// which it reads into `remeshing` (`Some(None)` for `remeshing: null`).
struct TakeRemeshing<'a, D> {
    inner: D,
    remeshing: &'a mut Option<Option<RemeshSettings>>,
}

impl<'de, D: Deserializer<'de>> Deserializer<'de> for TakeRemeshing<'_, D> {
    type Error = D::Error;

    fn deserialize_any<V: Visitor<'de>>(
        self,
        visitor: V,
    ) -> std::result::Result<V::Value, D::Error> {
        self.inner.deserialize_any(WithoutRemeshing {
            visitor,
            fields: None,
            remeshing: self.remeshing,
        })
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> std::result::Result<V::Value, D::Error> {
        self.inner.deserialize_struct(
            name,
            fields,
            WithoutRemeshing {
                visitor,
                fields: Some(fields),
                remeshing: self.remeshing,
            },
        )
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

/// The settings' visitor, given the map without its `remeshing` entry; `fields` are the
/// settings' keys, when known.
struct WithoutRemeshing<'a, V> {
    visitor: V,
    fields: Option<&'static [&'static str]>,
    remeshing: &'a mut Option<Option<RemeshSettings>>,
}

impl<'de, V: Visitor<'de>> Visitor<'de> for WithoutRemeshing<'_, V> {
    type Value = V::Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        self.visitor.expecting(f)
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> std::result::Result<V::Value, A::Error> {
        self.visitor.visit_map(MapWithoutRemeshing {
            map,
            fields: self.fields,
            remeshing: self.remeshing,
        })
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<V::Value, A::Error> {
        self.visitor.visit_seq(seq)
    }
}

/// The entries of the map but `remeshing`, whose value goes to `remeshing`.
struct MapWithoutRemeshing<'a, A> {
    map: A,
    fields: Option<&'static [&'static str]>,
    remeshing: &'a mut Option<Option<RemeshSettings>>,
}

impl<'de, A: MapAccess<'de>> MapAccess<'de> for MapWithoutRemeshing<'_, A> {
    type Error = A::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        mut seed: K,
    ) -> std::result::Result<Option<K::Value>, A::Error> {
        loop {
            let key = KeyOrRemeshing {
                seed,
                fields: self.fields,
            };
            match self.map.next_key_seed(key)? {
                None => return Ok(None),
                Some(Key::Other(key)) => return Ok(Some(key)),
                Some(Key::Remeshing(back)) => {
                    if self.remeshing.is_some() {
                        return Err(de::Error::duplicate_field(REMESHING));
                    }
                    *self.remeshing = Some(self.map.next_value()?);
                    seed = back;
                }
            }
        }
    }

    fn next_value_seed<S: DeserializeSeed<'de>>(
        &mut self,
        seed: S,
    ) -> std::result::Result<S::Value, A::Error> {
        self.map.next_value_seed(seed)
    }

    fn size_hint(&self) -> Option<usize> {
        self.map.size_hint()
    }
}

/// A key of the map: `remeshing` (the settings' key seed handed back), or another key read by
/// the settings' key seed.
enum Key<K, T> {
    Remeshing(K),
    Other(T),
}

/// Reads a key with the settings' key seed unless it is `remeshing`; the key is read by the
/// file's own deserializer, so an unknown key's error carries its place in the file, and it
/// lists the settings' keys and `remeshing` as the keys expected.
struct KeyOrRemeshing<K> {
    seed: K,
    fields: Option<&'static [&'static str]>,
}

/// The keys of an explicit analysis: the settings' `fields`, then `remeshing`.
fn expected_keys(fields: &'static [&'static str]) -> &'static [&'static str] {
    static KEYS: OnceLock<Vec<&'static str>> = OnceLock::new();
    KEYS.get_or_init(|| fields.iter().copied().chain([REMESHING]).collect())
}

impl<'de, K: DeserializeSeed<'de>> DeserializeSeed<'de> for KeyOrRemeshing<K> {
    type Value = Key<K, K::Value>;

    fn deserialize<D: Deserializer<'de>>(
        self,
        deserializer: D,
    ) -> std::result::Result<Self::Value, D::Error> {
        deserializer.deserialize_identifier(self)
    }
}

impl<'de, K: DeserializeSeed<'de>> Visitor<'de> for KeyOrRemeshing<K> {
    type Value = Key<K, K::Value>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("field identifier")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> std::result::Result<Self::Value, E> {
        match self.fields {
            _ if v == REMESHING => Ok(Key::Remeshing(self.seed)),
            Some(fields) if !fields.contains(&v) => {
                Err(de::Error::unknown_field(v, expected_keys(fields)))
            }
            _ => self
                .seed
                .deserialize(de::value::StrDeserializer::<E>::new(v))
                .map(Key::Other),
        }
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> std::result::Result<Self::Value, E> {
        self.seed
            .deserialize(de::value::U64Deserializer::<E>::new(v))
            .map(Key::Other)
    }

    fn visit_bytes<E: de::Error>(self, v: &[u8]) -> std::result::Result<Self::Value, E> {
        match std::str::from_utf8(v) {
            Ok(s) => self.visit_str(s),
            Err(_) => self
                .seed
                .deserialize(de::value::BytesDeserializer::<E>::new(v))
                .map(Key::Other),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> std::result::Result<ExplicitAnalysis, serde_norway::Error> {
        serde_norway::from_str(text)
    }

    #[test]
    fn the_remeshing_is_read_beside_the_settings() {
        let a = parse("{ end_time: 1.0e-3, remeshing: { body: block }, safety: 0.5 }").unwrap();
        assert_eq!(a.settings.end_time, 1.0e-3);
        assert_eq!(a.settings.safety, 0.5);
        assert_eq!(a.remeshing.map(|r| r.body), Some("block".to_string()));
        let none = parse("{ end_time: 1.0e-3, remeshing: null }").unwrap();
        assert_eq!(none, ExplicitAnalysis::from(ExplicitSettings::new(1.0e-3)));
    }

    #[test]
    fn every_key_keeps_its_message() {
        let unknown = parse("end_time: 1.0e-3\nsafty: 0.5\n")
            .unwrap_err()
            .to_string();
        assert!(
            unknown.starts_with("unknown field `safty`, expected one of `end_time`,")
                && unknown
                    .contains("`mesh_stability_eta`, `checkpoint`, `remeshing` at line 2 column 1"),
            "{unknown}"
        );
        let twice = parse("{ end_time: 1.0, remeshing: { body: a }, remeshing: { body: b } }");
        assert!(twice
            .unwrap_err()
            .to_string()
            .contains("duplicate field `remeshing`"));
        let wrong = parse("{ end_time: 1.0, remeshing: { body: a, check_every: x } }");
        assert!(wrong
            .unwrap_err()
            .to_string()
            .starts_with("remeshing.check_every: invalid type"));
        let missing = parse("{ remeshing: { body: a } }").unwrap_err().to_string();
        assert!(missing.starts_with("missing field `end_time`"), "{missing}");
    }
}
