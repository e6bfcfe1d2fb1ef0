//! The transfer operators T1, T2 and T3 of the thesis (8.4), from an old mesh to a new one,
//! both at the current coordinates (see the module `remesh` for the configuration and for which
//! field goes through which operator).
//!
//! Fields are plain arrays: a nodal field is `width` values per node, an element field `width`
//! values per element (one Gauss point per linear tetrahedron, at its centroid), row after row.
//! The new mesh's nodes are located in the old mesh once ([`crate::mesh::ops::Locator::locate_all`]); the
//! locations serve T3 and the middle step of T1.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;
use crate::mesh::ops::locate::{centroids, CentroidSearch, Location};

fn length_error(what: &str, got: usize, expected: usize) -> SolverError {
    SolverError::Remesh {
        entity: what.to_string(),
        message: format!("has {got} values where {expected} were expected"),
    }
}

/// The volume of every element of `tets` over the coordinates `nodes` (3.40), m^3.
pub fn element_volumes(nodes: &[Vector3<f64>], tets: &[[u32; 4]]) -> Vec<f64> {
    tets.iter()
        .map(|t| signed_volume(&t.map(|n| nodes[n as usize])))
        .collect()
}

/// T3, the nodal transfer (8.10), Box 8.3: the value of a nodal field at each new node is the
/// old element's interpolation at the node, `u_new = sum_a N_a(xi) u_a^old`, with the
/// barycentric coordinates `xi` of the node in the old element that holds it (`locations`, from
/// [`crate::mesh::ops::Locator::locate_all`]). `old` holds `width` values per old node.
///
/// Exact for every field that is linear in space (the interpolation reproduces linear
/// functions), so constant and linear fields come through to round-off; a new node just outside
/// the old mesh takes the linear extrapolation of its nearest old element, which keeps that
/// property.
pub fn interpolate_nodal(
    old: &[f64],
    width: usize,
    old_tets: &[[u32; 4]],
    locations: &[Location],
) -> Vec<f64> {
    let mut out = vec![0.0; locations.len() * width];
    for (row, l) in out.chunks_exact_mut(width).zip(locations) {
        for (a, &n) in old_tets[l.element].iter().enumerate() {
            let src = &old[n as usize * width..(n as usize + 1) * width];
            for (o, s) in row.iter_mut().zip(src) {
                *o += l.barycentric[a] * s;
            }
        }
    }
    out
}

/// T3 (8.10) for a nodal vector field (displacements, velocities): see [`interpolate_nodal`].
pub fn transfer_nodal_vectors(
    old: &[Vector3<f64>],
    old_tets: &[[u32; 4]],
    locations: &[Location],
) -> Vec<Vector3<f64>> {
    let flat: Vec<f64> = old.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
    interpolate_nodal(&flat, 3, old_tets, locations)
        .chunks_exact(3)
        .map(|c| Vector3::new(c[0], c[1], c[2]))
        .collect()
}

/// Step (i) of T1 (8.9, Fig. 8.5a): an element field (constant per element) projected onto the
/// nodes by the lumped `L2` projection, `q_n = sum_e (V_e/4) q_e / sum_e (V_e/4)` over the
/// elements `e` around node `n`: `int N_n q dV / int N_n dV` with the element integrals
/// `int_e N_n dV = V_e / 4`, i.e. the volume-weighted mean of the elements around the node.
/// `volumes` are the old elements' volumes in the configuration the field lives in (current
/// ones for a Cauchy stress). The weights are positive and sum to one, so a constant field
/// stays constant, and the nodal values stay within the range of the element values (no new
/// extremes). A node in no element gets 0 (it is never interpolated from).
pub fn project_to_nodes(
    values: &[f64],
    width: usize,
    tets: &[[u32; 4]],
    volumes: &[f64],
    node_count: usize,
) -> Vec<f64> {
    let mut sum = vec![0.0; node_count * width];
    let mut weight = vec![0.0; node_count];
    // Elements in ascending order: a fixed summation order, so the result is reproducible.
    for (e, tet) in tets.iter().enumerate() {
        let q = &values[e * width..(e + 1) * width];
        for &n in tet {
            let n = n as usize;
            weight[n] += volumes[e];
            for (s, v) in sum[n * width..(n + 1) * width].iter_mut().zip(q) {
                *s += volumes[e] * v;
            }
        }
    }
    for (row, w) in sum.chunks_exact_mut(width).zip(&weight) {
        if *w > 0.0 {
            row.iter_mut().for_each(|s| *s /= w);
        }
    }
    sum
}

/// Step (iv) of T1 (8.9, Fig. 8.5c): the value at each new element's Gauss point (its
/// centroid, where every `N_a = 1/4`) interpolated from its nodal values: the mean of its four
/// nodes.
pub fn nodes_to_elements(nodal: &[f64], width: usize, tets: &[[u32; 4]]) -> Vec<f64> {
    let mut out = vec![0.0; tets.len() * width];
    for (row, tet) in out.chunks_exact_mut(width).zip(tets) {
        for &n in tet {
            let src = &nodal[n as usize * width..(n as usize + 1) * width];
            for (o, s) in row.iter_mut().zip(src) {
                *o += 0.25 * s;
            }
        }
    }
    out
}

/// T1, the shape-function transfer (SFT) of a state variable (8.9, Fig. 8.5; Wriggers 2002,
/// Gharehbaghi & Khoei 2008): (i) old Gauss points to old nodes ([`project_to_nodes`]),
/// (ii)-(iii) old nodes to new nodes by the old shape functions at the new nodes' locations
/// ([`interpolate_nodal`], as T3), (iv) new nodes to new Gauss points ([`nodes_to_elements`]).
///
/// `values` holds `width` values per old element, `old_volumes` the old elements' volumes,
/// `old_node_count` the number of old nodes, `locations` where the new nodes lie in the old
/// mesh, `new_tets` the new connectivity. Exact for a constant field (every step maps a
/// constant to itself, to round-off). It smooths a field that jumps between elements: the
/// artificial diffusion the thesis accepts for stresses and strains and refuses for damage
/// ([`closest_gauss_point_sources`], T2). The integral (8.8), `sum_e q_e V_e`, is kept only
/// approximately; [`element_integral`] measures it on both meshes.
pub fn shape_function_transfer(
    values: &[f64],
    width: usize,
    old_tets: &[[u32; 4]],
    old_volumes: &[f64],
    old_node_count: usize,
    locations: &[Location],
    new_tets: &[[u32; 4]],
) -> Result<Vec<f64>> {
    if values.len() != old_tets.len() * width {
        return Err(length_error(
            "old element field",
            values.len(),
            old_tets.len() * width,
        ));
    }
    if old_volumes.len() != old_tets.len() {
        return Err(length_error(
            "old element volumes",
            old_volumes.len(),
            old_tets.len(),
        ));
    }
    if let Some(n) = new_tets
        .iter()
        .flatten()
        .find(|&&n| n as usize >= locations.len())
    {
        return Err(SolverError::Remesh {
            entity: format!("new node {n}"),
            message: format!(
                "is used by a new element but only {} new nodes were located",
                locations.len()
            ),
        });
    }
    let old_nodal = project_to_nodes(values, width, old_tets, old_volumes, old_node_count);
    let new_nodal = interpolate_nodal(&old_nodal, width, old_tets, locations);
    Ok(nodes_to_elements(&new_nodal, width, new_tets))
}

/// The integral `sum_e q_e V_e` of an element field (`width` values per element) over a mesh
/// with element volumes `volumes`, per component: the quantity (8.8) asks the old and the new
/// mesh to share.
pub fn element_integral(values: &[f64], width: usize, volumes: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; width];
    for (row, v) in values.chunks_exact(width).zip(volumes) {
        for (o, q) in out.iter_mut().zip(row) {
            *o += q * v;
        }
    }
    out
}

/// T2, the closest-point transfer of damage variables (thesis 8.4.1.2, Fig. 8.6): "taking the
/// data from the closest Gauss point to the new one". The Gauss point of the linear tetrahedron
/// is its centroid, so each new element takes its data from the old element whose centroid is
/// closest (Euclidean distance, current coordinates) to the new element's centroid; among
/// equally close old centroids (frequent in structured meshes), the lowest old id. Returns that
/// old element for every new element; [`copy_rows`] then copies any element data with it.
///
/// We follow the thesis' wording rather than taking the old element that contains the new
/// centroid: the two agree away from element boundaries; near a boundary the closest centroid
/// is the thesis' choice, and it never interpolates, so the copied values are old values, never
/// a mix ("it preserves the size of damage and does not introduce any damage diffusion"). The
/// price the thesis names is some stress oscillation after the restart.
pub fn closest_gauss_point_sources(
    old_nodes: &[Vector3<f64>],
    old_tets: &[[u32; 4]],
    new_nodes: &[Vector3<f64>],
    new_tets: &[[u32; 4]],
) -> Result<Vec<usize>> {
    let search = CentroidSearch::new(centroids(old_nodes, old_tets));
    centroids(new_nodes, new_tets)
        .iter()
        .map(|c| {
            search
                .closest(c)
                .map(|(e, _)| e)
                .ok_or_else(|| SolverError::Remesh {
                    entity: "old mesh".to_string(),
                    message: "has no elements to take damage variables from".to_string(),
                })
        })
        .collect()
}

/// Copies element data row by row: new element `i` takes the `width` values of old element
/// `sources[i]` (T2 with [`closest_gauss_point_sources`]). Works for the `f32` history of a
/// material as for `f64` fields; the values are copied bit for bit.
pub fn copy_rows<T: Copy>(values: &[T], width: usize, sources: &[usize]) -> Vec<T> {
    let mut out = Vec::with_capacity(sources.len() * width);
    for &s in sources {
        out.extend_from_slice(&values[s * width..(s + 1) * width]);
    }
    out
}

/// 3x3 matrices (deformation gradients, stresses) as element rows of nine values, column after
/// column (nalgebra's storage order), for T1 and T2.
pub fn matrices_to_rows(m: &[Matrix3<f64>]) -> Vec<f64> {
    m.iter().flat_map(|a| a.iter().copied()).collect()
}

/// The inverse of [`matrices_to_rows`]: rows of nine values, column after column, as matrices.
pub fn rows_to_matrices(rows: &[f64]) -> Vec<Matrix3<f64>> {
    rows.chunks_exact(9)
        .map(Matrix3::from_column_slice)
        .collect()
}
