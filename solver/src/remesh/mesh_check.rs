//! The checks a run makes after a local remeshing ([`crate::mesh::ops::remesh_region`]), before it
//! transfers the fields: the new mesh is valid, fills the same body, and is better shaped.

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::error::{Result, SolverError};
use crate::geometry::proximity::closest_point_on_triangle;
use crate::kinematics::signed_volume;
use crate::mesh::ops::distortion::collapse_ratio;
use crate::mesh::ops::fragments::{loose_fragments, shares_a_node};
use crate::mesh::ops::mesher::RemeshedRegion;
use crate::mesh::{boundary_faces_of, face_key, BoundaryFace, TET_FACES};

/// Relative tolerance on the region's volume and the outer boundary's area: both are sums of
/// pieces that tile the same set, equal up to the round-off of the sums.
pub const REMESH_TOLERANCE: f64 = 1e-12;

/// What [`check_remeshed`] measured.
#[derive(Debug, Clone, PartialEq)]
pub struct RemeshCheck {
    /// Number of elements in the region before the remeshing.
    pub region_elements_before: usize,
    /// Number of elements replacing it.
    pub region_elements_after: usize,
    /// Volume of the region before (current configuration, m^3).
    pub region_volume_before: f64,
    /// Volume of the elements replacing it (m^3).
    pub region_volume_after: f64,
    /// Area of the body's outer boundary before (m^2).
    pub boundary_area_before: f64,
    /// Area of the outer boundary after (m^2).
    pub boundary_area_after: f64,
    /// Smallest element volume in the new region (m^3).
    pub min_volume_after: f64,
    /// Worst collapse ratio (8.1) of the region before.
    pub worst_ratio_before: f64,
    /// Worst collapse ratio of the elements replacing the region.
    pub worst_ratio_after: f64,
}

fn fail(message: String) -> SolverError {
    SolverError::Remesh {
        entity: "remeshed region".to_string(),
        message,
    }
}

fn boundary_area(x: &[Vector3<f64>], faces: &[BoundaryFace]) -> f64 {
    faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.nodes.map(|n| x[n as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum()
}

/// Checks the remeshing `new` of the elements `region` of the old mesh (`x`, `tets`, current
/// coordinates), and measures it. An error says which check failed:
///
/// * **validity:** every new element has a positive volume (none inverted or flat);
/// * **untouched elements:** every copied element has the old element's nodes, each at its old
///   coordinates bit for bit;
/// * **volume:** the region's volume is kept to [`REMESH_TOLERANCE`] (relative), less what
///   peeled slivers took and surface collapses moved;
/// * **outer boundary:** its area is kept to [`REMESH_TOLERANCE`] (less the peeled slivers'
///   and surface collapses' changes), and every old boundary node
///   is kept and still on the boundary, or slid along the old boundary (on one of its old faces),
///   or merged into a neighbour by an edge collapse;
/// * **conformity:** no face is held by more than two elements, and every face the region
///   shared with the rest of the mesh is held by two. A hanging node would leave faces held by
///   one element inside the body, which the boundary-area check sees as extra boundary.
///
/// The quality before and after is the worst collapse ratio `chi` (8.1) of the region's old
/// elements and of the elements replacing them.
pub fn check_remeshed(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    new: &RemeshedRegion,
) -> Result<RemeshCheck> {
    let mut in_region = vec![false; tets.len()];
    for &e in region {
        if e >= tets.len() {
            return Err(fail(format!("region element {e} is out of range")));
        }
        in_region[e] = true;
    }
    let mut region = region.to_vec();
    region.sort_unstable();
    region.dedup();
    let region = &region[..];
    if new.kept_nodes.len() != x.len() || new.element_origin.len() != new.tets.len() {
        return Err(fail(format!(
            "{} kept-node entries for {} old nodes, {} origins for {} elements",
            new.kept_nodes.len(),
            x.len(),
            new.element_origin.len(),
            new.tets.len()
        )));
    }
    let min_volume = check_validity(new)?;
    check_copies(x, tets, new)?;
    let (before, after, peeled_area_change) = check_volume(x, tets, region, new)?;
    check_conformity(tets, region, &in_region, new)?;
    let (area_before, area_after) = check_boundary(x, tets, new, peeled_area_change)?;
    let xn = &new.nodes;
    let worst = |x: &[Vector3<f64>], list: &mut dyn Iterator<Item = &[u32; 4]>| {
        list.map(|t| collapse_ratio(&t.map(|n| x[n as usize])))
            .fold(0.0, f64::max)
    };
    Ok(RemeshCheck {
        region_elements_before: region.len(),
        region_elements_after: new.tets.len() - new.first_region_element,
        region_volume_before: before,
        region_volume_after: after,
        boundary_area_before: area_before,
        boundary_area_after: area_after,
        min_volume_after: min_volume,
        worst_ratio_before: worst(x, &mut region.iter().map(|&e| &tets[e])),
        worst_ratio_after: worst(xn, &mut new.tets[new.first_region_element..].iter()),
    })
}

/// Validity: every new element's nodes exist and its volume is positive. Returns the smallest
/// volume of the region's new elements (m^3).
fn check_validity(new: &RemeshedRegion) -> Result<f64> {
    let xn = &new.nodes;
    let mut min_volume = f64::INFINITY;
    for (e, tet) in new.tets.iter().enumerate() {
        if tet.iter().any(|&n| n as usize >= xn.len()) {
            return Err(fail(format!(
                "element {e} has a node out of range: {tet:?}"
            )));
        }
        let v = signed_volume(&tet.map(|n| xn[n as usize]));
        if !(v > 0.0) {
            return Err(fail(format!(
                "new element {e} has volume {v:.6e} m^3: inverted or flat"
            )));
        }
        if e >= new.first_region_element {
            min_volume = min_volume.min(v);
        }
    }

    Ok(min_volume)
}

/// Untouched elements: a copied element has the old element's nodes, each at its old
/// coordinates bit for bit.
fn check_copies(x: &[Vector3<f64>], tets: &[[u32; 4]], new: &RemeshedRegion) -> Result<()> {
    let xn = &new.nodes;
    // Untouched elements: same nodes, same coordinates.
    for (e, origin) in new.element_origin.iter().enumerate() {
        let Some(old) = origin else { continue };
        let old_tet = tets[*old as usize];
        let mapped = old_tet.map(|n| new.kept_nodes[n as usize]);
        if mapped != new.tets[e].map(Some) {
            return Err(fail(format!(
                "element {e} claims to copy old element {old} but its nodes differ"
            )));
        }
        for (k, &n) in old_tet.iter().enumerate() {
            if xn[new.tets[e][k] as usize] != x[n as usize] {
                return Err(fail(format!("old node {n} of element {e} has moved")));
            }
        }
    }

    Ok(())
}

/// The region's volume, kept less what peeled slivers took and surface collapses moved.
/// Returns the volume before and after (m^3) and the boundary area the peeled slivers changed
/// (m^2).
fn check_volume(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    region: &[usize],
    new: &RemeshedRegion,
) -> Result<(f64, f64, f64)> {
    let xn = &new.nodes;
    // Volume of the region.
    let before: f64 = region
        .iter()
        .map(|&e| signed_volume(&tets[e].map(|n| x[n as usize])))
        .sum();
    // Peeled boundary slivers take their volume, and change the boundary by their faces.
    let peeled_volume: f64 = new.peeled.iter().map(|(t, _)| signed_volume(t)).sum();
    let peeled_area_change: f64 = new
        .peeled
        .iter()
        .map(|(t, outer)| {
            TET_FACES
                .iter()
                .zip(outer)
                .map(|(f, &was_outer)| {
                    let [a, b, c] = f.map(|i| t[i]);
                    let area = 0.5 * (b - a).cross(&(c - a)).norm();
                    if was_outer {
                        -area
                    } else {
                        area
                    }
                })
                .sum::<f64>()
        })
        .sum();
    let after: f64 = new.tets[new.first_region_element..]
        .iter()
        .map(|t| signed_volume(&t.map(|n| xn[n as usize])))
        .sum();
    // Surface collapses move the boundary by their own volume (bounded by the mesher's
    // `surface_deviation` times the area they touch).
    if !((after + peeled_volume - new.surface_volume_change - before).abs()
        <= REMESH_TOLERANCE * before)
    {
        return Err(fail(format!(
            "region volume {after:.15e} m^3 differs from the old {before:.15e} m^3 by {:.3e} \
             (relative) after the {} peeled elements ({peeled_volume:.6e} m^3) and the \
             surface collapses ({:.6e} m^3) are accounted for",
            (after + peeled_volume - new.surface_volume_change - before).abs() / before,
            new.peeled.len(),
            new.surface_volume_change
        )));
    }

    Ok((before, after, peeled_area_change))
}

/// Conformity: no face held by more than two elements, no loose fragment, and every face the
/// region shared with the rest held by two.
fn check_conformity(
    tets: &[[u32; 4]],
    region: &[usize],
    in_region: &[bool],
    new: &RemeshedRegion,
) -> Result<()> {
    let xn = &new.nodes;
    // Conformity: face counts in the new mesh.
    let mut count: HashMap<[u32; 3], u32> = HashMap::with_capacity(4 * new.tets.len());
    for tet in &new.tets {
        for f in TET_FACES {
            *count.entry(face_key(f.map(|i| tet[i]))).or_insert(0) += 1;
        }
    }
    // The first such face in element order, so that the message is the same on every run.
    let over = new
        .tets
        .iter()
        .flat_map(|tet| TET_FACES.map(|f| face_key(f.map(|i| tet[i]))))
        .find(|face| count[face] > 2);
    if let Some(face) = over {
        return Err(fail(format!(
            "face {face:?} is held by {} elements: not conforming",
            count[&face]
        )));
    }
    // No new element hangs on the body by nodes or edges only, in a loose fragment
    // (`fragments.rs`): a node one held looked like a surface node to it and an inner node to
    // the rest (nail run, 143 us).
    let first = new.first_region_element;
    let mut holders: HashMap<[u32; 3], Vec<usize>> = new.tets[first..]
        .iter()
        .flat_map(|tet| TET_FACES.map(|f| (face_key(f.map(|i| tet[i])), Vec::new())))
        .collect();
    for (e, tet) in new.tets.iter().enumerate() {
        for f in TET_FACES {
            if let Some(list) = holders.get_mut(&face_key(f.map(|i| tet[i]))) {
                list.push(e);
            }
        }
    }
    let candidates: Vec<usize> = (first..new.tets.len()).collect();
    let mut face_neighbours = |e: usize| -> Vec<usize> {
        TET_FACES
            .iter()
            .flat_map(|f| &holders[&face_key(f.map(|i| new.tets[e][i]))])
            .copied()
            .filter(|&o| o != e)
            .collect()
    };
    let mut uses = vec![0usize; xn.len()];
    for n in new.tets.iter().flatten() {
        uses[*n as usize] += 1;
    }
    let hangs = |piece: &[usize]| shares_a_node(&new.tets, piece, &|n| uses[n as usize]);
    if let Some(piece) = loose_fragments(&candidates, &mut face_neighbours, &hangs).first() {
        return Err(fail(format!(
            "new elements {piece:?} hang on the body by nodes or edges only (a loose fragment)"
        )));
    }
    let region_faces: std::collections::HashSet<[u32; 3]> = region
        .iter()
        .flat_map(|&r| TET_FACES.map(|f| face_key(f.map(|i| tets[r][i]))))
        .collect();
    for (e, tet) in tets.iter().enumerate() {
        if in_region[e] {
            continue;
        }
        for f in TET_FACES {
            let face = f.map(|i| tet[i]);
            // A face of an outside element that a region element also holds.
            if !region_faces.contains(&face_key(face)) {
                continue;
            }
            let mapped = face.map(|n| new.kept_nodes[n as usize]);
            let key = match mapped {
                [Some(a), Some(b), Some(c)] => face_key([a, b, c]),
                _ => return Err(fail(format!("interface face {face:?} lost a node"))),
            };
            if count.get(&key) != Some(&2) {
                return Err(fail(format!(
                    "interface face {face:?} of old element {e} is not shared by two elements"
                )));
            }
        }
    }

    Ok(())
}

/// The outer boundary: its area kept (less the peeled slivers' and surface collapses'
/// changes), and every old boundary node kept on it, slid along it or merged. Returns the area
/// before and after (m^2).
fn check_boundary(
    x: &[Vector3<f64>],
    tets: &[[u32; 4]],
    new: &RemeshedRegion,
    peeled_area_change: f64,
) -> Result<(f64, f64)> {
    let xn = &new.nodes;
    // Outer boundary.
    let old_faces = boundary_faces_of(tets);
    let new_faces = boundary_faces_of(&new.tets);
    let (area_before, area_after) = (boundary_area(x, &old_faces), boundary_area(xn, &new_faces));
    if !((area_after - area_before - peeled_area_change - new.surface_area_change).abs()
        <= REMESH_TOLERANCE * area_before)
    {
        return Err(fail(format!(
            "outer boundary area {area_after:.15e} m^2 differs from the old {area_before:.15e} \
             m^2 (a hanging node, or a boundary node moved off the boundary)"
        )));
    }
    let mut on_boundary = vec![false; xn.len()];
    for f in &new_faces {
        for n in f.nodes {
            on_boundary[n as usize] = true;
        }
    }
    let slid: HashMap<u32, u32> = new.slid_nodes.iter().copied().collect();
    for f in &old_faces {
        for n in f.nodes {
            match (new.kept_nodes[n as usize], slid.get(&n)) {
                (Some(m), _) | (None, Some(&m)) if on_boundary[m as usize] => {}
                // Merged along its symmetry planes: the boundary area above checks the shape.
                (None, None) if new.merged_nodes.binary_search(&n).is_ok() => {}
                _ => {
                    return Err(fail(format!(
                        "old boundary node {n} is not on the new boundary"
                    )))
                }
            }
        }
    }
    check_slid_nodes(x, new, &old_faces)?;
    Ok((area_before, area_after))
}

/// Every old boundary node that slid lies on the old boundary, to round-off.
fn check_slid_nodes(
    x: &[Vector3<f64>],
    new: &RemeshedRegion,
    old_faces: &[BoundaryFace],
) -> Result<()> {
    let xn = &new.nodes;
    // A node that slid stays on the old boundary (on one of its faces, to round-off of the
    // coordinates), so the boundary keeps its shape.
    let extent = x.iter().map(|p| p.amax()).fold(f64::MIN_POSITIVE, f64::max);
    let distance_to = |p: &Vector3<f64>, faces: &mut dyn Iterator<Item = &BoundaryFace>| {
        faces
            .map(|f| {
                let [a, b, c] = f.nodes.map(|i| x[i as usize]);
                (closest_point_on_triangle(p, &a, &b, &c) - p).norm()
            })
            .fold(f64::INFINITY, f64::min)
    };
    // A node slides on its own old faces but for round-off at their edges, so those are searched
    // first and the whole boundary only where they miss (the same verdict; searching every face
    // for every node was a third of a late nail run's CPU).
    let mut fan: HashMap<u32, Vec<&BoundaryFace>> = new
        .slid_nodes
        .iter()
        .map(|&(o, _)| (o, Vec::new()))
        .collect();
    for f in old_faces {
        for n in f.nodes {
            if let Some(faces) = fan.get_mut(&n) {
                faces.push(f);
            }
        }
    }
    for &(o, m) in &new.slid_nodes {
        let p = xn[m as usize];
        let own = fan.get(&o).map(Vec::as_slice).unwrap_or_default();
        let mut distance = distance_to(&p, &mut own.iter().copied());
        if !(distance <= REMESH_TOLERANCE * extent) {
            distance = distance_to(&p, &mut old_faces.iter());
        }
        if !(distance <= REMESH_TOLERANCE * extent) {
            return Err(fail(format!(
                "old boundary node {o} slid off the old boundary (by {distance:.3e} m)"
            )));
        }
    }

    Ok(())
}
