//! The node tags of a Gmsh 4.1 `$Nodes` section, read from the file itself.
//!
//! mshio keeps a node block's tags only when the section's header announces a sparse range
//! (`max_tag - min_tag >= num_nodes`); for a dense range it reads the tags and drops them,
//! assuming they are `min_tag, min_tag + 1, ...` in file order. A file that lists a dense range
//! out of order, or repeats a tag, would then be misread, so the tags are read here again. The
//! layout is that of the Gmsh reference manual, section "MSH file format", version 4.1:
//!
//! ```text
//! $Nodes
//!   numEntityBlocks numNodes minNodeTag maxNodeTag          (size_t)
//!   entityDim entityTag parametric                          (int)
//!   numNodesInBlock                                         (size_t)
//!   nodeTag ...                                             (size_t, numNodesInBlock of them)
//!   x y z ...                                               (double, 3 numNodesInBlock)
//!   ...                                                     (the next block)
//! $EndNodes
//! ```
//!
//! ASCII files write the numbers as whitespace-separated text; binary files (`4.1 1 size`) as
//! raw values of `size` bytes (size_t), 4 bytes (int) and 8 bytes (double), in the byte order
//! given by the integer `1` that follows the `$MeshFormat` line. Parametric nodes are refused by
//! mshio before this runs, so a node has three coordinates.

/// A node block as mshio read it: entity dimension, entity tag and node count. The re-read must
/// find the same blocks, which rules out a `$Nodes` line inside another section's binary data.
pub(super) type BlockShape = (i32, i32, usize);

/// How the numbers of a binary file are stored.
#[derive(Debug, Clone, Copy)]
struct Binary {
    size_t: usize,
    little_endian: bool,
}

/// The node tags of every block of the `$Nodes` section of `bytes`, in file order; `None` if
/// no `$Nodes` line is followed by the blocks `shapes` (mshio parsed a section this reader
/// cannot find, which would be a bug here).
pub(super) fn node_tags(
    bytes: &[u8],
    binary: bool,
    size_t: usize,
    shapes: &[BlockShape],
) -> Option<Vec<Vec<u64>>> {
    let binary = if binary {
        Some(Binary {
            size_t,
            little_endian: little_endian(bytes)?,
        })
    } else {
        None
    };
    section_starts(bytes, b"$Nodes").find_map(|start| {
        let body = &bytes[start..];
        match binary {
            Some(b) => binary_tags(body, b, shapes),
            None => ascii_tags(body, shapes),
        }
    })
}

/// Byte order of a binary file: the int `1` right after the `$MeshFormat` header line.
fn little_endian(bytes: &[u8]) -> Option<bool> {
    let start = section_starts(bytes, b"$MeshFormat").next()?;
    let header_end = start + bytes[start..].iter().position(|&b| b == b'\n')? + 1;
    let one: [u8; 4] = bytes.get(header_end..header_end + 4)?.try_into().ok()?;
    if i32::from_le_bytes(one) == 1 {
        Some(true)
    } else if i32::from_be_bytes(one) == 1 {
        Some(false)
    } else {
        None
    }
}

/// Offsets just past each line `tag` (spaces before it allowed, `\n` or `\r\n` after it, as
/// mshio accepts), in file order.
pub(super) fn section_starts<'a>(
    bytes: &'a [u8],
    tag: &'a [u8],
) -> impl Iterator<Item = usize> + 'a {
    (0..bytes.len()).filter_map(move |i| {
        if !bytes[i..].starts_with(tag) {
            return None;
        }
        let line_start = bytes[..i]
            .iter()
            .rev()
            .take_while(|&&b| b == b' ' || b == b'\t')
            .count();
        let before = i - line_start;
        if before != 0 && bytes[before - 1] != b'\n' {
            return None;
        }
        let after = i + tag.len();
        match bytes.get(after..) {
            Some([b'\n', ..]) => Some(after + 1),
            Some([b'\r', b'\n', ..]) => Some(after + 2),
            _ => None,
        }
    })
}

/// The tags of an ASCII `$Nodes` section starting at `body`.
fn ascii_tags(body: &[u8], shapes: &[BlockShape]) -> Option<Vec<Vec<u64>>> {
    let mut words = body
        .split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty())
        .map(|w| std::str::from_utf8(w).ok());
    let mut next = || words.next().flatten();
    let blocks: usize = next()?.parse().ok()?;
    if blocks != shapes.len() {
        return None;
    }
    for _ in 0..3 {
        next()?; // numNodes minNodeTag maxNodeTag
    }
    let mut tags = Vec::with_capacity(blocks);
    for &(dim, entity, count) in shapes {
        let shape: (i32, i32) = (next()?.parse().ok()?, next()?.parse().ok()?);
        let _parametric = next()?;
        let n: usize = next()?.parse().ok()?;
        if shape != (dim, entity) || n != count {
            return None;
        }
        let block = (0..n)
            .map(|_| next()?.parse().ok())
            .collect::<Option<Vec<u64>>>()?;
        for _ in 0..3 * n {
            next()?;
        }
        tags.push(block);
    }
    Some(tags)
}

/// The tags of a binary `$Nodes` section starting at `body`.
fn binary_tags(body: &[u8], b: Binary, shapes: &[BlockShape]) -> Option<Vec<Vec<u64>>> {
    let mut at = 0usize;
    let mut take = |n: usize| -> Option<&[u8]> {
        let s = body.get(at..at.checked_add(n)?)?;
        at += n;
        Some(s)
    };
    let unsigned = |s: &[u8]| -> Option<u64> {
        let mut v = [0u8; 8];
        match (s.len(), b.little_endian) {
            (1..=8, true) => v[..s.len()].copy_from_slice(s),
            (1..=8, false) => v[8 - s.len()..].copy_from_slice(s),
            _ => return None,
        }
        Some(if b.little_endian {
            u64::from_le_bytes(v)
        } else {
            u64::from_be_bytes(v)
        })
    };
    let int = |s: &[u8]| -> Option<i32> {
        let v: [u8; 4] = s.try_into().ok()?;
        Some(if b.little_endian {
            i32::from_le_bytes(v)
        } else {
            i32::from_be_bytes(v)
        })
    };
    let blocks = usize::try_from(unsigned(take(b.size_t)?)?).ok()?;
    if blocks != shapes.len() {
        return None;
    }
    take(3 * b.size_t)?; // numNodes minNodeTag maxNodeTag
    let mut tags = Vec::with_capacity(blocks);
    for &(dim, entity, count) in shapes {
        let shape = (int(take(4)?)?, int(take(4)?)?);
        take(4)?; // parametric
        let n = usize::try_from(unsigned(take(b.size_t)?)?).ok()?;
        if shape != (dim, entity) || n != count {
            return None;
        }
        let raw = take(n.checked_mul(b.size_t)?)?;
        let block = raw
            .chunks_exact(b.size_t)
            .map(unsigned)
            .collect::<Option<Vec<u64>>>()?;
        take(n.checked_mul(24)?)?; // x y z, 8 bytes each
        tags.push(block);
    }
    Some(tags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_lines_are_found_at_line_starts_only() {
        let text = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n  $Nodes\r\nx $Nodes\n$NodesX\n";
        let starts: Vec<usize> = section_starts(text, b"$Nodes").collect();
        assert_eq!(starts, [45]);
        assert_eq!(&text[45..47], b"x ");
    }

    #[test]
    fn ascii_tags_are_read_in_file_order() {
        let body = b"2 3 1 3\n0 5 0 1\n3\n0 0 0\n2 1 0 2\n2\n1\n1 0 0\n0 1 0\n$EndNodes\n";
        assert_eq!(
            ascii_tags(body, &[(0, 5, 1), (2, 1, 2)]),
            Some(vec![vec![3], vec![2, 1]])
        );
        // A block that is not the one mshio read: not this section.
        assert_eq!(ascii_tags(body, &[(0, 5, 1), (2, 2, 2)]), None);
    }

    #[test]
    fn binary_tags_of_both_byte_orders_and_sizes() {
        for (little_endian, size_t) in [(true, 8), (false, 8), (true, 4)] {
            let mut body = Vec::new();
            let size = |v: u64, out: &mut Vec<u8>| {
                let bytes = if little_endian {
                    v.to_le_bytes()[..size_t].to_vec()
                } else {
                    v.to_be_bytes()[8 - size_t..].to_vec()
                };
                out.extend(bytes);
            };
            let int = |v: i32| {
                if little_endian {
                    v.to_le_bytes()
                } else {
                    v.to_be_bytes()
                }
            };
            for v in [1, 2, 1, 2] {
                size(v, &mut body);
            }
            body.extend(int(3));
            body.extend(int(7));
            body.extend(int(0));
            size(2, &mut body);
            size(2, &mut body);
            size(1, &mut body);
            body.extend([0u8; 48]);
            let b = Binary {
                size_t,
                little_endian,
            };
            assert_eq!(
                binary_tags(&body, b, &[(3, 7, 2)]),
                Some(vec![vec![2, 1]]),
                "{b:?}"
            );
            assert_eq!(binary_tags(&body[..body.len() - 1], b, &[(3, 7, 2)]), None);
        }
    }
}
