//! Subdividing elements and faces at the midpoints of their split edges: the regular 1:8
//! refinement of a tetrahedron (Bey 1995) and the cut of a boundary triangle, each depending on
//! the element or face alone so that neighbours cut a shared face alike.

use nalgebra::Vector3;

use crate::kinematics::signed_volume;

/// The regular 1:8 refinement of the tetrahedron `v` (new ids) with edge midpoints `m(i, j)`
/// (Bey 1995): four corner children and the inner octahedron cut along its shortest diagonal.
pub(crate) fn red_refinement(
    v: [u32; 4],
    m: impl Fn(usize, usize) -> u32,
    nodes: &[Vector3<f64>],
    out: &mut Vec<[u32; 4]>,
) {
    out.push([v[0], m(0, 1), m(0, 2), m(0, 3)]);
    out.push([m(0, 1), v[1], m(1, 2), m(1, 3)]);
    out.push([m(0, 2), m(1, 2), v[2], m(2, 3)]);
    out.push([m(0, 3), m(1, 3), m(2, 3), v[3]]);
    // The octahedron's vertices are the midpoints of the edges; two are opposite (a diagonal)
    // when their edges share no node.
    let diagonals = [[[0, 1], [2, 3]], [[0, 2], [1, 3]], [[0, 3], [1, 2]]];
    let length = |d: &[[usize; 2]; 2]| {
        (nodes[m(d[0][0], d[0][1]) as usize] - nodes[m(d[1][0], d[1][1]) as usize]).norm_squared()
    };
    let mut best = 0;
    for k in 1..3 {
        if length(&diagonals[k]) < length(&diagonals[best]) {
            best = k;
        }
    }
    let [a, b] = diagonals[best];
    // The other two diagonals give the ring around it: p, q, p', q'.
    let [p, p2] = diagonals[(best + 1) % 3];
    let [q, q2] = diagonals[(best + 2) % 3];
    let ring = [p, q, p2, q2].map(|[i, j]| m(i, j));
    let (da, db) = (m(a[0], a[1]), m(b[0], b[1]));
    for k in 0..4 {
        let mut t = [da, db, ring[k], ring[(k + 1) % 4]];
        if signed_volume(&t.map(|n| nodes[n as usize])) < 0.0 {
            t.swap(2, 3);
        }
        out.push(t);
    }
}

/// The triangles of the face `f` (old ids, counter-clockwise seen from outside) cut by its split
/// edges, as new ids in the same orientation. The cut depends on the face only (not on which
/// element asks), so the two elements of a face cut it alike.
pub(crate) fn face_triangles(
    f: [u32; 3],
    mid: &impl Fn(u32, u32) -> Option<u32>,
    new_id: &[u32],
    nodes: &[Vector3<f64>],
) -> Vec<[u32; 3]> {
    let split = |k: usize| mid(f[k], f[(k + 1) % 3]);
    let count = (0..3).filter(|&k| split(k).is_some()).count();
    let n = f.map(|o| new_id[o as usize]);
    // Rotation r: local edge k becomes edge (k + r) % 3.
    match count {
        0 => vec![n],
        3 => {
            let [mab, mbc, mca] = [0, 1, 2].map(|k| split(k).expect("three splits"));
            vec![
                [n[0], mab, mca],
                [mab, n[1], mbc],
                [mca, mbc, n[2]],
                [mab, mbc, mca],
            ]
        }
        1 => {
            let r = (0..3).find(|&k| split(k).is_some()).expect("one split");
            let (a, b, c) = (n[r], n[(r + 1) % 3], n[(r + 2) % 3]);
            let m = split(r).expect("the split edge");
            vec![[a, m, c], [m, b, c]]
        }
        _ => {
            // The edge (c, a) is whole; (a, b) and (b, c) are split.
            let r = (0..3)
                .find(|&k| split((k + 2) % 3).is_none())
                .expect("one whole edge");
            let (a, b, c) = (n[r], n[(r + 1) % 3], n[(r + 2) % 3]);
            let (mab, mbc) = (split(r).expect("split"), split((r + 1) % 3).expect("split"));
            let d1 = (nodes[a as usize] - nodes[mbc as usize]).norm_squared();
            let d2 = (nodes[c as usize] - nodes[mab as usize]).norm_squared();
            // Old nodes have lower ids than midpoints: the lowest id is `a` or `c`.
            let through_a = d1 < d2 || (d1 == d2 && a < c);
            let corner = [mab, b, mbc];
            if through_a {
                vec![corner, [a, mab, mbc], [a, mbc, c]]
            } else {
                vec![corner, [a, mab, c], [mab, mbc, c]]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron and its six edge midpoints, nodes 4..10 in the edge order
    /// (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
    fn with_midpoints(x: [Vector3<f64>; 4]) -> (Vec<Vector3<f64>>, impl Fn(usize, usize) -> u32) {
        let edges = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];
        let mut nodes = x.to_vec();
        nodes.extend(edges.iter().map(|[i, j]| 0.5 * (x[*i] + x[*j])));
        let mid = move |i: usize, j: usize| {
            let (a, b) = (i.min(j), i.max(j));
            4 + edges.iter().position(|e| *e == [a, b]).expect("an edge") as u32
        };
        (nodes, mid)
    }

    #[test]
    fn the_eight_children_fill_the_parent_with_positive_volumes() {
        let x = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(2.0, 0.1, 0.0),
            Vector3::new(0.3, 1.5, 0.2),
            Vector3::new(0.4, 0.2, 1.1),
        ];
        let parent = signed_volume(&x);
        assert!(parent > 0.0);
        let (nodes, mid) = with_midpoints(x);
        let mut children = Vec::new();
        red_refinement([0, 1, 2, 3], mid, &nodes, &mut children);
        assert_eq!(children.len(), 8);
        let volumes: Vec<f64> = children
            .iter()
            .map(|t| signed_volume(&t.map(|n| nodes[n as usize])))
            .collect();
        assert!(volumes.iter().all(|v| *v > 0.0), "{volumes:?}");
        // Each child is an eighth of the parent (Bey 1995: the red refinement is volume-regular).
        for v in &volumes {
            assert!((v / parent - 0.125).abs() < 1e-12, "{v} of {parent}");
        }
    }

    #[test]
    fn a_face_is_cut_into_triangles_of_its_area_whatever_edges_split() {
        let nodes = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.2, 0.9, 0.0),
            Vector3::new(0.5, 0.0, 0.0),
            Vector3::new(0.6, 0.45, 0.0),
            Vector3::new(0.1, 0.45, 0.0),
        ];
        let area = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|n| nodes[n as usize]);
            0.5 * (b - a).cross(&(c - a)).z
        };
        let whole = area(&[0, 1, 2]);
        let identity: Vec<u32> = (0..6).collect();
        for mask in 0..8u32 {
            let mid = |a: u32, b: u32| {
                let k = match (a.min(b), a.max(b)) {
                    (0, 1) => 0,
                    (1, 2) => 1,
                    _ => 2,
                };
                (mask >> k & 1 == 1).then_some(3 + k)
            };
            let triangles = face_triangles([0, 1, 2], &mid, &identity, &nodes);
            assert_eq!(
                triangles.len(),
                1 + mask.count_ones() as usize,
                "mask {mask}"
            );
            let total: f64 = triangles.iter().map(area).sum();
            assert!(
                triangles.iter().all(|t| area(t) > 0.0),
                "mask {mask}: {triangles:?}"
            );
            assert!((total - whole).abs() < 1e-14, "mask {mask}");
        }
    }
}
