//! The inputs a checkpoint was written for: each input file by its role in the scene (the scene
//! file, a body's mesh, a material's parameter file), its path and the FNV-1a 64 hash of its
//! bytes. A resume compares them role by role, so that the message names what changed.

use std::path::{Path, PathBuf};

use super::bytes::{fnv1a64, Read, Reader, Writer};
use super::error::CheckpointError;
use crate::scene::{MaterialSpec, MeshSource, Scene};

/// One input: its role, its path as the run was given it, and the hash of its bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Input {
    /// What the file is to the run (`scene file`, ``mesh of body `slab` ``).
    pub role: String,
    /// The path as the run read it.
    pub path: PathBuf,
    /// FNV-1a 64 of the file's bytes ([`super::bytes::fnv1a64`]).
    pub hash: u64,
}

/// The inputs of a run, in a fixed order (the scene file, then per body its mesh and material
/// files).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Inputs(pub Vec<Input>);

impl Inputs {
    /// The scene file at `path` and every file `scene` (read from it, paths resolved) reads.
    pub fn of_scene_file(path: &Path, scene: &Scene) -> Result<Self, CheckpointError> {
        let mut files = vec![("scene file".to_string(), path.to_path_buf())];
        let material_file = |m: &MaterialSpec| match m {
            MaterialSpec::Microplane(spec) => spec.file.clone(),
            _ => None,
        };
        for body in &scene.bodies {
            if let MeshSource::Gmsh(p) = &body.mesh {
                files.push((format!("mesh of body `{}`", body.name), p.clone()));
            }
            if let Some(p) = material_file(&body.material) {
                files.push((format!("material file of body `{}`", body.name), p));
            }
            for r in &body.regions {
                if let Some(p) = material_file(&r.material) {
                    files.push((format!("material file of region `{}`", r.name), p));
                }
            }
        }
        let inputs = files
            .into_iter()
            .map(|(role, path)| {
                let bytes = std::fs::read(&path).map_err(|source| CheckpointError::Io {
                    path: path.clone(),
                    action: "reading an input to hash it",
                    source,
                })?;
                Ok(Input {
                    role,
                    hash: fnv1a64(&bytes),
                    path,
                })
            })
            .collect::<Result<Vec<_>, CheckpointError>>()?;
        Ok(Self(inputs))
    }

    /// One input given by its bytes (a scene built in memory).
    pub fn from_bytes(role: &str, bytes: &[u8]) -> Self {
        Self(vec![Input {
            role: role.to_string(),
            path: PathBuf::from(role),
            hash: fnv1a64(bytes),
        }])
    }

    /// The first difference between the inputs a checkpoint was written for (`self`) and the
    /// run's (`now`), in words; `None` when they are the same.
    pub fn difference(&self, now: &Inputs) -> Option<String> {
        for input in &now.0 {
            match self.0.iter().find(|i| i.role == input.role) {
                None => {
                    return Some(format!(
                        "the {} `{}` is new (the checkpoint's run had none)",
                        input.role,
                        input.path.display()
                    ))
                }
                Some(then) if then.hash != input.hash => {
                    return Some(format!(
                        "the {} `{}` has changed (hash {:016x}, was {:016x} when the checkpoint \
                         was written)",
                        input.role,
                        input.path.display(),
                        input.hash,
                        then.hash
                    ))
                }
                Some(_) => {}
            }
        }
        self.0
            .iter()
            .find(|then| !now.0.iter().any(|i| i.role == then.role))
            .map(|then| {
                format!(
                    "the checkpoint's run read the {} `{}`, which this run does not",
                    then.role,
                    then.path.display()
                )
            })
    }

    /// Writes the list.
    pub fn write(&self, w: &mut Writer) {
        w.usize(self.0.len());
        for i in &self.0 {
            w.str(&i.role);
            w.str(&i.path.to_string_lossy());
            w.u64(i.hash);
        }
    }

    /// Reads what [`Self::write`] wrote.
    pub fn read(r: &mut Reader) -> Read<Self> {
        let n = r.usize("input count")?;
        let mut inputs = Vec::new();
        for _ in 0..n {
            inputs.push(Input {
                role: r.str("input role")?,
                path: PathBuf::from(r.str("input path")?),
                hash: r.u64("input hash")?,
            });
        }
        Ok(Self(inputs))
    }
}
