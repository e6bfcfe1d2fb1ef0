//! Reader for Gmsh `.msh` files in format 4.1, ASCII or binary.
//!
//! `mshio` parses the `$Entities`, `$Nodes` and `$Elements` sections; `$PhysicalNames` is always
//! ASCII, even in binary files, and `mshio` skips it, so it is read here.
//!
//! Choices:
//! - Only linear tetrahedra (type 4) become elements. Lower-dimensional elements (points, lines,
//!   triangles, ...) only feed node sets; any other volume element is an error, because silently
//!   dropping it would lose mass.
//! - Nodes are renumbered 0.. in file order, keeping only those used by a tetrahedron or by a
//!   physical group. Geometry-only nodes (a circle's centre, say) are dropped because they would
//!   carry no mass.
//! - Element nodes keep the file's order: orientation is checked by [`Mesh::validate`].
//! - Every physical group becomes `node_sets[name]` (`"dim:tag"` when unnamed): the sorted node
//!   ids of all elements on its entities, plus, for points, the nodes classified on them. Groups
//!   sharing a name (in different dimensions) are merged.
//!
//! - Node tags are those written in the file. mshio drops them when the section's tag range is
//!   dense, so they are then read again from the file (`super::gmsh_tags`); a tag listed
//!   twice, or tag 0 (reserved by Gmsh), is an error.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use mshio::{ElementType, MshFile};
use nalgebra::Vector3;

use super::{gmsh_tags, Mesh};
pub use crate::error::GmshError;
use crate::error::{Result, SolverError};

/// Physical group key: (dimension, physical tag).
type Group = (i32, i32);

/// Reads a Gmsh 4.1 mesh (ASCII or binary) and returns its linear tetrahedra.
///
/// See the module documentation for which nodes, elements and node sets are kept.
pub fn read_msh(path: &Path) -> Result<Mesh> {
    let bytes = std::fs::read(path).map_err(|e| SolverError::MeshRead {
        path: path.to_path_buf(),
        reason: GmshError::Read(e.to_string()),
    })?;
    parse_msh(&bytes, &path.to_string_lossy())
}

/// Same from bytes already in memory; `name` labels error messages.
pub fn parse_msh(bytes: &[u8], name: &str) -> Result<Mesh> {
    let fail = |reason: GmshError| SolverError::MeshRead {
        path: name.into(),
        reason,
    };
    let binary = check_format(bytes).map_err(fail)?;
    let names = physical_names(bytes).map_err(fail)?;
    // mshio panics on a few malformed inputs (e.g. an unsupported data size); a bad file must be
    // an error, not a crash.
    let parsed = std::panic::catch_unwind(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| describe_parse_error(&e, bytes, binary))
    })
    .unwrap_or(Err(GmshError::ParserGaveUp));
    let msh = parsed.map_err(fail)?;
    let tags = node_tags(&msh, bytes, binary).map_err(fail)?;
    build(&msh, &tags, &names).map_err(fail)
}

/// The node tags of every `$Nodes` block, in file order: mshio's when it kept them (a sparse
/// range), otherwise read again from the file, because mshio then drops the tags written and
/// a file listing them out of order or twice would be misread.
fn node_tags(
    msh: &MshFile<u64, i32, f64>,
    bytes: &[u8],
    binary: bool,
) -> std::result::Result<Vec<Vec<u64>>, GmshError> {
    let Some(nodes) = &msh.data.nodes else {
        return Ok(Vec::new());
    };
    if nodes.node_blocks.iter().all(|b| b.node_tags.is_some()) {
        return nodes
            .node_blocks
            .iter()
            .map(|block| match &block.node_tags {
                Some(map) if map.len() == block.nodes.len() => {
                    let mut tags = vec![0; block.nodes.len()];
                    map.iter().for_each(|(&tag, &i)| tags[i] = tag);
                    Ok(tags)
                }
                _ => Err(GmshError::RepeatedTagInBlock {
                    dim: block.entity_dim,
                    tag: block.entity_tag,
                }),
            })
            .collect();
    }
    let shapes: Vec<_> = nodes
        .node_blocks
        .iter()
        .map(|b| (b.entity_dim, b.entity_tag, b.nodes.len()))
        .collect();
    gmsh_tags::node_tags(bytes, binary, msh.header.size_t_size, &shapes)
        .ok_or(GmshError::NodeTagsUnreadable)
}

/// Rejects other versions up front: mshio would only say "unsupported version", without which.
/// Returns whether the file is binary.
fn check_format(bytes: &[u8]) -> std::result::Result<bool, GmshError> {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]);
    let mut lines = head.lines();
    if lines.next().map(str::trim_end) != Some("$MeshFormat") {
        return Err(GmshError::NotGmsh);
    }
    let mut header = lines.next().unwrap_or("").split_whitespace();
    match header.next() {
        Some("4.1") => Ok(header.next() == Some("1")),
        Some(version) => Err(GmshError::UnsupportedVersion(version.to_string())),
        None => Err(GmshError::TruncatedHeader),
    }
}

/// Maps each named physical group to its name, from the optional `$PhysicalNames` section.
fn physical_names(bytes: &[u8]) -> std::result::Result<HashMap<Group, String>, GmshError> {
    let Some(start) = find_line(bytes, b"$PhysicalNames") else {
        return Ok(HashMap::new());
    };
    let body = &bytes[start + b"$PhysicalNames".len()..];
    let end = find_line(body, b"$EndPhysicalNames").ok_or(GmshError::UnterminatedPhysicalNames)?;
    let text = String::from_utf8_lossy(&body[..end]);
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let count: usize = lines.next().and_then(|l| l.parse().ok()).unwrap_or(0);
    let mut names = HashMap::new();
    for line in lines {
        let mut fields = line.splitn(3, char::is_whitespace);
        let dim = fields.next().and_then(|f| f.parse().ok());
        let tag = fields.next().and_then(|f| f.parse().ok());
        let name = fields.next().map(|f| f.trim().trim_matches('"'));
        let (Some(dim), Some(tag), Some(name)) = (dim, tag, name) else {
            return Err(GmshError::BadPhysicalName(line.to_string()));
        };
        names.insert((dim, tag), name.to_string());
    }
    if names.len() != count {
        return Err(GmshError::PhysicalNameCount {
            announced: count,
            listed: names.len(),
        });
    }
    Ok(names)
}

/// Offset of the first line that is exactly `tag`; anchoring on line starts keeps
/// `$EndPhysicalNames` from matching `$PhysicalNames`.
fn find_line(bytes: &[u8], tag: &[u8]) -> Option<usize> {
    (0..bytes.len()).find(|&i| {
        (i == 0 || bytes[i - 1] == b'\n')
            && bytes[i..].starts_with(tag)
            && matches!(bytes.get(i + tag.len()), None | Some(b'\n' | b'\r'))
    })
}

/// mshio's own `Display` appends a hex dump of the whole rest of the file; name the place
/// instead.
fn describe_parse_error(e: &mshio::MshParserError<&[u8]>, bytes: &[u8], binary: bool) -> GmshError {
    let trace = e.filtered_backtrace();
    let offset_of = |rest: &[u8]| (rest.as_ptr() as usize).saturating_sub(bytes.as_ptr() as usize);
    let Some((rest, kind)) = trace.first() else {
        // Only nom's own errors, without mshio's context: typically a section holding more
        // entries than its header announces, so that the `$End...` line is not where expected.
        // The innermost error still points into the file.
        return match e.backtrace.first() {
            Some((rest, _)) => unexpected_at(bytes, offset_of(rest), binary),
            None => GmshError::Malformed,
        };
    };
    let mut place = place_of(bytes, offset_of(rest), binary);
    for (_, k) in trace[1..].iter().rev() {
        place += &format!(
            ", in {}",
            k.context().map_or_else(|| k.to_string(), str::to_string)
        );
    }
    GmshError::Parse {
        place,
        reason: kind.to_string().trim_end_matches('.').to_string(),
    }
}

/// `line N` (ASCII) or `byte N` (binary) of `offset`.
fn place_of(bytes: &[u8], offset: usize, binary: bool) -> String {
    if binary {
        return format!("byte {offset}");
    }
    let line = bytes[..offset.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count();
    format!("line {}", line + 1)
}

/// The error for a parse that stopped at `offset` without a reason: the place, the section it
/// lies in (the last `$Section` line before it) and, in an ASCII file, the text found there.
fn unexpected_at(bytes: &[u8], offset: usize, binary: bool) -> GmshError {
    let offset = offset.min(bytes.len());
    let mut place = place_of(bytes, offset, binary);
    let section = (0..offset)
        .rev()
        .filter(|&i| bytes[i] == b'$' && (i == 0 || bytes[i - 1] == b'\n'))
        .find_map(|i| {
            let name: String = bytes[i + 1..offset]
                .iter()
                .take_while(|b| b.is_ascii_alphabetic())
                .map(|&b| char::from(b))
                .collect();
            (!name.is_empty()).then_some(name)
        });
    let expected = match &section {
        Some(name) if name.starts_with("End") => {
            place += &format!(", after `${name}`");
            "the next `$Section` line".to_string()
        }
        Some(name) => {
            place += &format!(", in `${name}`");
            format!("`$End{name}`")
        }
        None => "a `$Section` line".to_string(),
    };
    let found = if binary {
        String::new()
    } else {
        let line = bytes[offset..].split(|&b| b == b'\n').next().unwrap_or(&[]);
        let text = String::from_utf8_lossy(line);
        let text = text.trim_end();
        if text.is_empty() {
            " (end of file)".to_string()
        } else {
            format!(" `{}`", text.chars().take(60).collect::<String>())
        }
    };
    GmshError::Parse {
        place,
        reason: format!(
            "unexpected data{found} where {expected} should be; a count in the section's \
             header may not match the entries that follow"
        ),
    }
}

/// Turns the parsed file into a [`Mesh`] following the rules in the module documentation.
/// `tags` holds the node tags of each `$Nodes` block ([`node_tags`]).
fn build(
    msh: &MshFile<u64, i32, f64>,
    tags: &[Vec<u64>],
    names: &HashMap<Group, String>,
) -> std::result::Result<Mesh, GmshError> {
    let mut coords = Vec::new();
    let mut index_of = HashMap::new();
    let mut point_nodes: HashMap<i32, Vec<usize>> = HashMap::new();
    if let Some(nodes) = &msh.data.nodes {
        for (block, tags) in nodes.node_blocks.iter().zip(tags) {
            let first = coords.len();
            for (k, (&tag, node)) in tags.iter().zip(&block.nodes).enumerate() {
                if tag == 0 {
                    return Err(GmshError::ZeroNodeTag {
                        dim: block.entity_dim,
                        tag: block.entity_tag,
                    });
                }
                if index_of.insert(tag, first + k).is_some() {
                    return Err(GmshError::RepeatedNodeTag(tag));
                }
                coords.push(Vector3::new(node.x, node.y, node.z));
            }
            if block.entity_dim == 0 {
                point_nodes
                    .entry(block.entity_tag)
                    .or_default()
                    .extend(first..coords.len());
            }
        }
    }

    let mut physical: HashMap<Group, &[i32]> = HashMap::new();
    if let Some(entities) = &msh.data.entities {
        let points = entities.points.iter().map(|e| (0, e.tag, &e.physical_tags));
        let curves = entities.curves.iter().map(|e| (1, e.tag, &e.physical_tags));
        let surfaces = entities
            .surfaces
            .iter()
            .map(|e| (2, e.tag, &e.physical_tags));
        let volumes = entities
            .volumes
            .iter()
            .map(|e| (3, e.tag, &e.physical_tags));
        for (dim, tag, tags) in points.chain(curves).chain(surfaces).chain(volumes) {
            physical.insert((dim, tag), tags.as_slice());
        }
    }

    let mut tets: Vec<[usize; 4]> = Vec::new();
    let mut groups: BTreeMap<Group, Vec<usize>> =
        names.keys().map(|&group| (group, Vec::new())).collect();
    for (&tag, nodes) in &point_nodes {
        for &group in physical.get(&(0, tag)).copied().unwrap_or_default() {
            groups.entry((0, group)).or_default().extend(nodes);
        }
    }
    for block in msh.data.elements.iter().flat_map(|e| &e.element_blocks) {
        let (dim, entity) = (block.entity_dim, block.entity_tag);
        if block.element_type == ElementType::Tet10 {
            return Err(GmshError::QuadraticTetrahedra { entity });
        }
        let is_tet = block.element_type == ElementType::Tet4;
        if dim == 3 && !is_tet {
            return Err(GmshError::OtherVolumeElements {
                entity,
                kind: format!("{:?}", block.element_type),
                code: block.element_type as i32,
            });
        }
        let entity_groups = physical.get(&(dim, entity)).copied().unwrap_or_default();
        for element in &block.elements {
            let ids = element
                .nodes
                .iter()
                .map(|tag| {
                    index_of.get(tag).copied().ok_or(GmshError::UnknownNode {
                        element: element.element_tag,
                        tag: *tag,
                    })
                })
                .collect::<std::result::Result<Vec<usize>, GmshError>>()?;
            if is_tet {
                tets.push([ids[0], ids[1], ids[2], ids[3]]);
            }
            for &group in entity_groups {
                groups.entry((dim, group)).or_default().extend(&ids);
            }
        }
    }
    if tets.is_empty() {
        return Err(GmshError::NoTetrahedra);
    }

    let mut used = vec![false; coords.len()];
    tets.iter()
        .flatten()
        .chain(groups.values().flatten())
        .for_each(|&i| used[i] = true);
    let mut new_id = vec![u32::MAX; coords.len()];
    let mut kept = Vec::new();
    for (i, x) in coords.into_iter().enumerate().filter(|&(i, _)| used[i]) {
        new_id[i] = u32::try_from(kept.len()).map_err(|_| GmshError::TooManyNodes)?;
        kept.push(x);
    }

    let mut node_sets: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    for ((dim, tag), members) in groups {
        let name = names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("{dim}:{tag}"));
        let set = node_sets.entry(name).or_default();
        set.extend(members.iter().map(|&i| new_id[i]));
    }
    for set in node_sets.values_mut() {
        set.sort_unstable();
        set.dedup();
    }
    Ok(Mesh {
        nodes: kept,
        tets: tets.iter().map(|t| t.map(|i| new_id[i])).collect(),
        node_sets,
    })
}
