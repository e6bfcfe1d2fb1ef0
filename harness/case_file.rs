//! Reading case files: one YAML case per file under `cases/` (or any file named on the command
//! line), strictly parsed in two passes (the common part, then the kind's block), with paths
//! resolved against the file's folder; and selecting cases by id, glob, tag or path.

use std::path::{Path, PathBuf};

use crate::case_kind::{Block, LoadedCase, Registry};
use crate::catalogue::{CaseSpec, Sweep};

/// An error in the catalogue: names the file, the line when known, and the problem.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct CatalogueError {
    /// The case file, with the line (`path:line`) when known.
    pub path: String,
    /// What is wrong and how to fix it.
    pub message: String,
}

/// A number of the common part of a case out of its range, or a part that does not fit the
/// rest: each message names the key (`time_limit_s`, `sweep.mesh[2]`, `variant \`v\` ranks`)
/// and what to give instead.
#[derive(Debug, thiserror::Error)]
pub enum RangeError {
    /// A wall-time limit that is not a positive, finite number.
    #[error("a wall-time limit must be a positive, finite number of seconds, got {0}")]
    TimeLimit(f64),
    /// The time limit of the case.
    #[error("time_limit_s: {0}")]
    CaseTimeLimit(Box<RangeError>),
    /// The scene or a variant's analysis refused by the solver (`key` prefixes the solver's
    /// entity).
    #[error("{key}{message}")]
    Scene {
        /// `scene.` or `variant \`v\` `.
        key: String,
        /// The solver's entity and message.
        message: String,
    },
    /// A strength seed without a strength field.
    #[error(
        "variant `{variant}` strength_seed: no body of the scene has a strength field to seed; \
         give a microplane body `strength_field: {{ coefficient_of_variation, \
         correlation_length, seed }}` or remove `strength_seed`"
    )]
    SeedWithoutField {
        /// The variant.
        variant: String,
    },
    /// A rank count out of range.
    #[error(
        "variant `{variant}` ranks: must lie in 1 to {max} (the ranks of a distributed run), got \
         {ranks}"
    )]
    Ranks {
        /// The variant.
        variant: String,
        /// The most ranks.
        max: usize,
        /// The ranks given.
        ranks: usize,
    },
    /// Several ranks for an analysis that runs on one.
    #[error(
        "variant `{variant}` ranks: {ranks} ranks need an explicit analysis without remeshing; \
         a static, release or remeshing analysis runs on one rank: remove `ranks`"
    )]
    RanksNeedExplicit {
        /// The variant.
        variant: String,
        /// The ranks given.
        ranks: usize,
    },
    /// A sweep without levels.
    #[error("sweep.{key}: lists no level; give at least one, or no sweep")]
    EmptySweep {
        /// The sweep's key.
        key: &'static str,
    },
    /// A mesh level out of range.
    #[error(
        "sweep.mesh[{index}]: {divisions:?} must be at least 1 per axis and make at most {max} \
         tetrahedra"
    )]
    MeshLevel {
        /// The level's index.
        index: usize,
        /// Its divisions.
        divisions: [usize; 3],
        /// The most tetrahedra.
        max: usize,
    },
    /// A time-step factor out of range.
    #[error(
        "sweep.time_step_factor[{index}]: a factor on the stable step must be positive and \
         finite, got {factor}"
    )]
    StepFactor {
        /// The level's index.
        index: usize,
        /// The factor given.
        factor: f64,
    },
    /// A mesh-file level's size out of range.
    #[error("sweep.mesh_files[{index}].size: must be a positive, finite length (m), got {size}")]
    MeshFileSize {
        /// The level's index.
        index: usize,
        /// The size given (m).
        size: f64,
    },
}

/// Parses one case file in two passes: the top-level key of its kind (one of `kinds`, or none
/// for the default kind) picks the kind; the rest of the file is read strictly as the common
/// part (`CaseSpec`), then the kind's block by the kind (`crate::case_kind::ParseKind`). Both
/// keep the file's line numbers in their errors. Paths are resolved against the file's folder.
pub fn load_case(path: &Path, kinds: &Registry) -> Result<LoadedCase, CatalogueError> {
    let fail = |message: String| CatalogueError {
        path: path.display().to_string(),
        message,
    };
    let (spec, block) = read(path, kinds.keyed.iter().map(|k| k.key))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let kind = match &block {
        Some(block) => {
            let entry = kinds
                .keyed
                .iter()
                .find(|k| k.key == block.key)
                .expect("the block's key is registered");
            (entry.parse)(Some(block), &spec, base)
        }
        None => (kinds.default)(None, &spec, base),
    }
    .map_err(|e| fail(e.to_string()))?;
    Ok(LoadedCase {
        path: path.to_path_buf(),
        spec,
        kind,
    })
}

/// The common part of a case file whose kind does not matter to the caller (a scene case read
/// for its scene): the file must have no kind's block.
pub fn load_spec(path: &Path) -> Result<CaseSpec, CatalogueError> {
    read(path, std::iter::empty()).map(|(spec, _)| spec)
}

/// The first pass: the common part, checked and with its paths resolved, and the block of the
/// one kind among `keys` that the file names, if any.
fn read<'k>(
    path: &Path,
    keys: impl Iterator<Item = &'k str>,
) -> Result<(CaseSpec, Option<Block>), CatalogueError> {
    let fail = |message: String| CatalogueError {
        path: path.display().to_string(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let text = impact_solver::scene::without_byte_order_mark(&text).to_string();
    let top = top_level_keys(&text);
    let given: Vec<&str> = keys
        .filter(|k| top.iter().any(|(key, _)| key == k))
        .collect();
    if given.len() > 1 {
        let names: Vec<String> = given.iter().map(|k| format!("`{k}`")).collect();
        return Err(fail(format!(
            "a case is of one kind, but {} are all given: keep one",
            names.join(" and ")
        )));
    }
    let (common, block) = match given.first() {
        Some(key) => {
            let (common, block) = split_block(&text, key);
            (common, Some(block))
        }
        None => (text, None),
    };
    let de = serde_norway::Deserializer::from_str(&common);
    let mut spec: CaseSpec = serde_norway::with::singleton_map_recursive::deserialize(de)
        .map_err(|e| fail(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    resolve_paths(&mut spec, base);
    for curve in spec.plots.iter().flat_map(|p| p.reference_curves.iter()) {
        curve.read().map_err(|e| fail(e.to_string()))?;
    }
    if spec.metrics.is_empty() {
        return Err(fail(
            "the case has no metrics: every case measures something against a reference".into(),
        ));
    }
    for v in &spec.variants {
        if spec.variants.iter().filter(|w| w.name == v.name).count() > 1 {
            return Err(fail(format!("variant `{}` appears twice", v.name)));
        }
    }
    for m in &spec.metrics {
        if spec.metrics.iter().filter(|n| n.name == m.name).count() > 1 {
            return Err(fail(format!("metric `{}` appears twice", m.name)));
        }
    }
    check_ranges(&spec).map_err(|e| fail(e.to_string()))?;
    Ok((spec, block))
}

/// The most ranks a variant may ask for: in the default build each is a thread of the harness.
pub const MAX_RANKS: usize = 1024;

/// The ranges of the common part's numbers, each error naming its key: the time limit, the
/// sweep's levels, the variants' ranks and analyses, and the scene (`Scene::validate`).
fn check_ranges(spec: &CaseSpec) -> Result<(), RangeError> {
    let scene_error = |key: &str, e: impact_solver::SolverError| RangeError::Scene {
        key: key.into(),
        message: match e {
            impact_solver::SolverError::InvalidScene { entity, message } => {
                format!("{entity}: {message}")
            }
            other => other.to_string(),
        },
    };
    if let Some(limit) = spec.time_limit_s {
        check_time_limit(limit).map_err(|m| RangeError::CaseTimeLimit(Box::new(m)))?;
    }
    if let Some(sweep) = &spec.sweep {
        check_sweep(sweep)?;
    }
    if let Some(scene) = &spec.scene {
        scene.validate().map_err(|e| scene_error("scene.", e))?;
    }
    for v in &spec.variants {
        let key = format!("variant `{}`", v.name);
        let has_field = spec.scene.as_ref().is_some_and(|scene| {
            scene.bodies.iter().any(|b| {
                matches!(&b.material, impact_solver::scene::MaterialSpec::Microplane(m)
                    if m.strength_field.is_some())
            })
        });
        if v.strength_seed.is_some() && !has_field {
            return Err(RangeError::SeedWithoutField {
                variant: v.name.clone(),
            });
        }
        if let Some(analysis) = &v.analysis {
            analysis
                .validate()
                .map_err(|e| scene_error(&format!("{key} "), e))?;
        }
        if let Some(n) = v.ranks {
            if !(1..=MAX_RANKS).contains(&n) {
                return Err(RangeError::Ranks {
                    variant: v.name.clone(),
                    max: MAX_RANKS,
                    ranks: n,
                });
            }
            let analysis = v
                .analysis
                .as_ref()
                .or(spec.scene.as_ref().map(|s| &s.analysis));
            let explicit_only = matches!(
                analysis,
                Some(impact_solver::scene::Analysis::Explicit(s)) if s.remeshing.is_none()
            );
            if n > 1 && !explicit_only {
                return Err(RangeError::RanksNeedExplicit {
                    variant: v.name.clone(),
                    ranks: n,
                });
            }
        }
    }
    Ok(())
}

/// A wall-time limit (s) must be positive and finite (`time_limit_s`, `--time-limit`).
pub fn check_time_limit(limit: f64) -> Result<(), RangeError> {
    if limit > 0.0 && limit.is_finite() {
        Ok(())
    } else {
        Err(RangeError::TimeLimit(limit))
    }
}

/// Every level of a sweep must be a run: at least one level, factors and sizes positive and
/// finite, divisions at least 1 and within the mesh limit.
fn check_sweep(sweep: &Sweep) -> Result<(), RangeError> {
    let empty = |key| RangeError::EmptySweep { key };
    match sweep {
        Sweep::Mesh(levels) if levels.is_empty() => Err(empty("mesh")),
        Sweep::TimeStepFactor(f) if f.is_empty() => Err(empty("time_step_factor")),
        Sweep::MeshFiles(f) if f.is_empty() => Err(empty("mesh_files")),
        Sweep::Mesh(levels) => levels.iter().enumerate().try_for_each(|(i, d)| {
            let tets = d
                .iter()
                .try_fold(6usize, |n, &k| n.checked_mul(k))
                .filter(|&t| t <= impact_solver::scene::MAX_ELEMENTS);
            match tets {
                Some(t) if t > 0 => Ok(()),
                _ => Err(RangeError::MeshLevel {
                    index: i,
                    divisions: *d,
                    max: impact_solver::scene::MAX_ELEMENTS,
                }),
            }
        }),
        Sweep::TimeStepFactor(factors) => factors.iter().enumerate().try_for_each(|(i, f)| {
            if *f > 0.0 && f.is_finite() {
                Ok(())
            } else {
                Err(RangeError::StepFactor {
                    index: i,
                    factor: *f,
                })
            }
        }),
        Sweep::MeshFiles(levels) => levels.iter().enumerate().try_for_each(|(i, l)| {
            if l.size > 0.0 && l.size.is_finite() {
                Ok(())
            } else {
                Err(RangeError::MeshFileSize {
                    index: i,
                    size: l.size,
                })
            }
        }),
    }
}

/// Resolves the common part's paths (meshes, material files, measured curves, sweep meshes)
/// against the case file's folder.
fn resolve_paths(spec: &mut CaseSpec, base: &Path) {
    let resolve = |p: &mut PathBuf| {
        if p.is_relative() {
            *p = base.join(&*p);
        }
    };
    for body in spec.scene.iter_mut().flat_map(|s| s.bodies.iter_mut()) {
        if let impact_solver::scene::MeshSource::Gmsh(p) = &mut body.mesh {
            resolve(p);
        }
        if let Some(p) = body.material.file_mut() {
            resolve(p);
        }
        for p in body
            .regions
            .iter_mut()
            .filter_map(|r| r.material.file_mut())
        {
            resolve(p);
        }
    }
    for curve in spec
        .plots
        .iter_mut()
        .flat_map(|p| p.reference_curves.iter_mut())
    {
        resolve(&mut curve.file);
    }
    if let Some(Sweep::MeshFiles(levels)) = &mut spec.sweep {
        levels.iter_mut().for_each(|l| resolve(&mut l.file));
    }
}

/// The keys at the top level of a YAML mapping, with their line index (0-based).
fn top_level_keys(text: &str) -> Vec<(String, usize)> {
    text.lines()
        .enumerate()
        .filter_map(|(i, line)| {
            let first = line.chars().next()?;
            if !(first.is_ascii_alphabetic() || first == '_') {
                return None;
            }
            let (key, _) = line.split_once(':')?;
            Some((key.trim().to_string(), i))
        })
        .collect()
}

/// Splits `text` at the top-level `key`: the text without the block (its lines blanked) and
/// the block (every other line blanked), both keeping the line numbers of the file.
fn split_block(text: &str, key: &str) -> (String, Block) {
    let lines: Vec<&str> = text.lines().collect();
    let start = top_level_keys(text)
        .into_iter()
        .find(|(k, _)| k == key)
        .map_or(lines.len(), |(_, i)| i);
    // The block runs until the next line that starts at column 0 with anything but a comment.
    let end = (start + 1..lines.len())
        .find(|&i| {
            let l = lines[i];
            l.chars()
                .next()
                .is_some_and(|c| !c.is_whitespace() && c != '#')
        })
        .unwrap_or(lines.len());
    let mut common = String::with_capacity(text.len());
    let mut block = String::with_capacity(text.len());
    for (i, line) in lines.iter().enumerate() {
        let (to, blank) = if (start..end).contains(&i) {
            (&mut block, &mut common)
        } else {
            (&mut common, &mut block)
        };
        to.push_str(line);
        to.push('\n');
        blank.push('\n');
    }
    (
        common,
        Block {
            key: key.to_string(),
            text: block,
        },
    )
}

/// Every `*.yaml` case under `dir` (recursively, sorted by path), skipping `dir/examples` and
/// `dir/materials` (scenes and material data, not cases). All errors are collected.
pub fn load_catalogue(
    dir: &Path,
    kinds: &Registry,
) -> Result<Vec<LoadedCase>, Vec<CatalogueError>> {
    let mut files = Vec::new();
    collect_yaml(dir, dir, &mut files);
    files.sort();
    let mut cases = Vec::new();
    let mut errors = Vec::new();
    for f in files {
        match load_case(&f, kinds) {
            Ok(c) => cases.push(c),
            Err(e) => errors.push(e),
        }
    }
    for (i, c) in cases.iter().enumerate() {
        if let Some(other) = cases[..i].iter().find(|o| o.spec.id == c.spec.id) {
            errors.push(CatalogueError {
                path: c.path.display().to_string(),
                message: format!(
                    "case id `{}` is also used by {}",
                    c.spec.id,
                    other.path.display()
                ),
            });
        }
    }
    if errors.is_empty() {
        Ok(cases)
    } else {
        Err(errors)
    }
}

fn collect_yaml(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            let skip = path.parent() == Some(root)
                && matches!(
                    path.file_name().and_then(|n| n.to_str()),
                    Some("examples" | "materials" | "meshes")
                );
            if !skip {
                collect_yaml(root, &path, out);
            }
        } else if path.extension().is_some_and(|e| e == "yaml" || e == "yml") {
            out.push(path);
        }
    }
}

/// Whether a case is selected by a pattern: its id, a glob with `*`, a tag `tag:<name>`, or the
/// path of its file.
pub fn matches(case: &LoadedCase, pattern: &str) -> bool {
    if let Some(tag) = pattern.strip_prefix("tag:") {
        return case.spec.tags.iter().any(|t| t == tag);
    }
    if Path::new(pattern) == case.path || case.path.ends_with(pattern) {
        return true;
    }
    glob_match(pattern, &case.spec.id)
}

/// `*` matches any run of characters; everything else literally.
fn glob_match(pattern: &str, text: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    if parts.len() == 1 {
        return pattern == text;
    }
    let mut rest = text;
    for (i, part) in parts.iter().enumerate() {
        if i == 0 {
            let Some(r) = rest.strip_prefix(part) else {
                return false;
            };
            rest = r;
        } else if i == parts.len() - 1 {
            return rest.ends_with(part);
        } else {
            let Some(pos) = rest.find(part) else {
                return false;
            };
            rest = &rest[pos + part.len()..];
        }
    }
    true
}
