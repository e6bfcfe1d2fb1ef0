//! Structured box meshes: each hexahedral cell split into six tetrahedra.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::Mesh;
use crate::error::{Result, SolverError};
use crate::kinematics::signed_volume;
use crate::rng::SplitMix64;

/// An axis-aligned box `origin + [0, size]` divided into `divisions` cells per axis.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Corner of the box with the smallest coordinates (m).
    pub origin: [f64; 3],
    /// Edge lengths along `x, y, z` (m), positive.
    pub size: [f64; 3],
    /// Number of cells along `x, y, z`, at least 1; each cell holds six tetrahedra.
    pub divisions: [usize; 3],
    /// Axes about whose mid-plane the split of the cells is mirror-symmetric (`[x, z]`), each
    /// with an even number of divisions; empty (the default) for the plain Kuhn split of every
    /// cell. See [`box_mesh`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mirror: Vec<Axis>,
}

/// A coordinate axis, written `x`, `y` or `z`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// The `x` axis (index 0).
    X,
    /// The `y` axis (index 1).
    Y,
    /// The `z` axis (index 2).
    Z,
}

impl Axis {
    /// The axis's name as written in a scene.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

impl BoxSpec {
    /// Whether [`box_mesh`] can mesh the box: at least one cell per axis, and an even number of
    /// cells along every mirrored axis. The error names the field at fault (`divisions` or
    /// `mirror`) and the fix.
    pub fn check(&self) -> Result<()> {
        let invalid = |field: &str, message: String| SolverError::InvalidScene {
            entity: format!("mesh.box.{field}"),
            message,
        };
        if self.divisions.contains(&0) {
            return Err(invalid(
                "divisions",
                "a box needs at least one cell per axis".to_string(),
            ));
        }
        for axis in &self.mirror {
            let n = self.divisions[*axis as usize];
            if n % 2 != 0 {
                let a = axis.name();
                return Err(invalid(
                    "mirror",
                    format!(
                        "the split is mirrored about the mid-plane along {a}, but the box has {n} \
                         divisions along {a}, an odd number: the mid-plane cuts the middle cell. \
                         Fix: use an even number of divisions along {a}, or leave {a} out of \
                         `mirror`"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Freudenthal-Kuhn subdivision: the six tetrahedra of the unit cube that share the diagonal
/// from corner `(0,0,0)` to `(1,1,1)`, one per order in which the axes are walked. Neighbouring
/// cells split their shared face along the same diagonal, so the mesh is conforming.
const KUHN_AXIS_ORDERS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The box meshed with `6 * nx * ny * nz` positively oriented tetrahedra. Node `(i, j, k)` has id
/// `i + (nx + 1) * (j + (ny + 1) * k)`; elements run cell by cell in the same order, six per cell.
///
/// Without `mirror` every cell takes the Kuhn split (`KUHN_AXIS_ORDERS`), which is not
/// mirror-symmetric: all diagonals run from the `(0,0,0)` side to the `(1,1,1)` side. For each
/// axis in `mirror`, the cells in the upper half of the box along it (cell index `i >= n / 2`)
/// take the Kuhn split reflected about the box's mid-plane normal to that axis: their six
/// tetrahedra are walked from the cell corner that the reflection maps to `(0,0,0)`, stepping
/// down along that axis. The reflection then maps the mesh onto itself.
///
/// The mesh stays conforming. Inside a cell the split is a reflection of the Kuhn split, itself
/// a triangulation of the cube. A face shared by two cells is normal to the axis `a` along which
/// they are neighbours, and is cut by the diagonal the Kuhn split walks in the other two axes:
/// the cells have the same index, hence the same reflections, along those two axes, so they cut
/// the face alike; they may differ in the reflection along `a` (across a mirror plane), but
/// reflecting along `a` leaves a face normal to `a`, and its diagonal, where they are.
///
/// # Panics
///
/// If [`BoxSpec::check`] fails (no cell along an axis, or an odd number of cells along a
/// mirrored axis); code that builds a box from input calls `check` first.
pub fn box_mesh(spec: &BoxSpec) -> Mesh {
    if let Err(e) = spec.check() {
        panic!("box_mesh: {e}");
    }
    let [nx, ny, nz] = spec.divisions;
    let id = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push(Vector3::new(
                    spec.origin[0] + spec.size[0] * i as f64 / nx as f64,
                    spec.origin[1] + spec.size[1] * j as f64 / ny as f64,
                    spec.origin[2] + spec.size[2] * k as f64 / nz as f64,
                ));
            }
        }
    }
    let mut mirrored = [false; 3];
    for axis in &spec.mirror {
        mirrored[*axis as usize] = true;
    }
    let mut tets = Vec::with_capacity(6 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let cell = [i, j, k];
                // Reflected along `a`: the walk starts on the cell's upper side and steps down.
                let reflected: [bool; 3] =
                    std::array::from_fn(|a| mirrored[a] && 2 * cell[a] >= spec.divisions[a]);
                let start: [usize; 3] = std::array::from_fn(|a| cell[a] + reflected[a] as usize);
                for order in KUHN_AXIS_ORDERS {
                    let mut c = start;
                    let mut tet = [id(c[0], c[1], c[2]); 4];
                    for (step, axis) in order.iter().enumerate() {
                        if reflected[*axis] {
                            c[*axis] -= 1;
                        } else {
                            c[*axis] += 1;
                        }
                        tet[step + 1] = id(c[0], c[1], c[2]);
                    }
                    let x = tet.map(|n| nodes[n as usize]);
                    if signed_volume(&x) < 0.0 {
                        tet.swap(2, 3);
                    }
                    tets.push(tet);
                }
            }
        }
    }
    Mesh {
        nodes,
        tets,
        ..Default::default()
    }
}

/// Moves every node that is not on the boundary of the box `[lo, hi]` by a uniform random offset
/// of at most `fraction` times the smallest cell size per axis, reproducibly from `seed`. Used to
/// make patch-test meshes irregular; boundary nodes stay on their faces.
pub fn perturb_interior(mesh: &mut Mesh, spec: &BoxSpec, fraction: f64, seed: u64) {
    let (lo, hi) = mesh.bounding_box();
    let h = (0..3)
        .map(|a| spec.size[a] / spec.divisions[a] as f64)
        .fold(f64::INFINITY, f64::min);
    let tol = 1e-9 * h;
    let mut rng = SplitMix64::new(seed);
    for x in &mut mesh.nodes {
        let on_boundary = (0..3).any(|a| (x[a] - lo[a]).abs() < tol || (hi[a] - x[a]).abs() < tol);
        let offset = Vector3::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        ) * (fraction * h);
        if !on_boundary {
            *x += offset;
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    use super::*;

    fn spec(divisions: [usize; 3], mirror: &[Axis]) -> BoxSpec {
        BoxSpec {
            origin: [0.25, -0.5, 1.0],
            size: [3.0, 0.6, 0.3],
            divisions,
            mirror: mirror.to_vec(),
        }
    }

    /// The generator as it was before `mirror`: the Kuhn split in every cell.
    fn kuhn_reference(spec: &BoxSpec) -> Mesh {
        let [nx, ny, nz] = spec.divisions;
        let id = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
        let mut nodes = Vec::new();
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push(Vector3::new(
                        spec.origin[0] + spec.size[0] * i as f64 / nx as f64,
                        spec.origin[1] + spec.size[1] * j as f64 / ny as f64,
                        spec.origin[2] + spec.size[2] * k as f64 / nz as f64,
                    ));
                }
            }
        }
        let mut tets = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    for order in KUHN_AXIS_ORDERS {
                        let mut c = [i, j, k];
                        let mut tet = [id(i, j, k); 4];
                        for (step, axis) in order.iter().enumerate() {
                            c[*axis] += 1;
                            tet[step + 1] = id(c[0], c[1], c[2]);
                        }
                        let x = tet.map(|n| nodes[n as usize]);
                        if signed_volume(&x) < 0.0 {
                            tet.swap(2, 3);
                        }
                        tets.push(tet);
                    }
                }
            }
        }
        Mesh {
            nodes,
            tets,
            ..Default::default()
        }
    }

    const DIVISIONS: [[usize; 3]; 5] = [[2, 2, 2], [2, 1, 2], [4, 3, 2], [6, 2, 4], [60, 12, 6]];

    const MIRRORS: [&[Axis]; 5] = [
        &[],
        &[Axis::X],
        &[Axis::Z],
        &[Axis::X, Axis::Z],
        &[Axis::X, Axis::Y, Axis::Z],
    ];

    fn sorted(mut face: [u32; 3]) -> [u32; 3] {
        face.sort_unstable();
        face
    }

    /// Every element positive, interior faces shared by exactly two elements and faces on the
    /// box's surface by one, the volumes summing to the box's.
    #[test]
    fn mirrored_meshes_are_valid_and_conforming() {
        for divisions in DIVISIONS {
            for mirror in MIRRORS {
                if mirror.iter().any(|a| divisions[*a as usize] % 2 != 0) {
                    continue;
                }
                let s = spec(divisions, mirror);
                let mesh = box_mesh(&s);
                let [nx, ny, nz] = divisions;
                assert_eq!(mesh.tets.len(), 6 * nx * ny * nz);
                let box_volume = s.size.iter().product::<f64>();
                let mut volume = 0.0;
                let mut faces: BTreeMap<[u32; 3], usize> = BTreeMap::new();
                for tet in &mesh.tets {
                    let v = signed_volume(&tet.map(|n| mesh.nodes[n as usize]));
                    assert!(v > 0.0, "{divisions:?} {mirror:?}: {tet:?} has volume {v}");
                    volume += v;
                    for f in super::super::TET_FACES {
                        *faces.entry(sorted(f.map(|l| tet[l]))).or_default() += 1;
                    }
                }
                assert!(
                    (volume - box_volume).abs() <= 1e-12 * box_volume,
                    "{divisions:?} {mirror:?}: volume {volume} against {box_volume}"
                );
                let (lo, hi) = mesh.bounding_box();
                let tol = 1e-9;
                let on_surface = |f: &[u32; 3]| {
                    (0..3).any(|a| {
                        f.iter()
                            .all(|n| (mesh.nodes[*n as usize][a] - lo[a]).abs() < tol)
                            || f.iter()
                                .all(|n| (mesh.nodes[*n as usize][a] - hi[a]).abs() < tol)
                    })
                };
                let mut boundary = 0;
                for (f, count) in &faces {
                    let expected = if on_surface(f) { 1 } else { 2 };
                    assert_eq!(*count, expected, "{divisions:?} {mirror:?}: face {f:?}");
                    boundary += (expected == 1) as usize;
                }
                assert_eq!(boundary, 4 * (nx * ny + ny * nz + nz * nx));
                mesh.validate("box", super::super::DEFAULT_MIN_ALTITUDE_RATIO)
                    .expect("a valid mesh");
            }
        }
    }

    /// The mesh's tetrahedra as sets of nodes after the reflection of the box about its
    /// mid-planes along `axes`, each image node found by its coordinates.
    fn reflected(mesh: &Mesh, s: &BoxSpec, axes: &[Axis]) -> BTreeSet<[u32; 4]> {
        let [nx, ny, _] = s.divisions;
        let h: [f64; 3] = std::array::from_fn(|a| s.size[a] / s.divisions[a] as f64);
        let image = |n: u32| {
            let mut x = mesh.nodes[n as usize];
            for a in axes {
                let a = *a as usize;
                x[a] = 2.0 * s.origin[a] + s.size[a] - x[a];
            }
            let c: [usize; 3] =
                std::array::from_fn(|a| ((x[a] - s.origin[a]) / h[a]).round() as usize);
            let m = c[0] + (nx + 1) * (c[1] + (ny + 1) * c[2]);
            assert!((mesh.nodes[m] - x).norm() < 1e-12, "{x} has no node");
            m as u32
        };
        mesh.tets
            .iter()
            .map(|t| {
                let mut t = t.map(image);
                t.sort_unstable();
                t
            })
            .collect()
    }

    fn tet_set(mesh: &Mesh) -> BTreeSet<[u32; 4]> {
        mesh.tets
            .iter()
            .map(|t| {
                let mut t = *t;
                t.sort_unstable();
                t
            })
            .collect()
    }

    /// A mirrored mesh maps onto itself under the reflection about each mirrored mid-plane;
    /// the Kuhn split does not, along any axis.
    #[test]
    fn a_mirrored_split_maps_onto_itself_under_the_reflection() {
        for divisions in [[2, 2, 2], [4, 3, 2], [60, 12, 6]] {
            let kuhn = box_mesh(&spec(divisions, &[]));
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                if divisions[axis as usize] % 2 == 0 {
                    assert_ne!(
                        reflected(&kuhn, &spec(divisions, &[]), &[axis]),
                        tet_set(&kuhn),
                        "{divisions:?}: the Kuhn split is symmetric along {axis:?}"
                    );
                }
            }
            for mirror in [&[Axis::X][..], &[Axis::Z], &[Axis::X, Axis::Z]] {
                let s = spec(divisions, mirror);
                let mesh = box_mesh(&s);
                let tets = tet_set(&mesh);
                assert_eq!(tets.len(), mesh.tets.len());
                for axis in mirror {
                    assert_eq!(
                        reflected(&mesh, &s, &[*axis]),
                        tets,
                        "{divisions:?} mirror {mirror:?}: not symmetric along {axis:?}"
                    );
                }
                if mirror.len() == 2 {
                    assert_eq!(reflected(&mesh, &s, mirror), tets);
                }
                // Along an axis left out of `mirror` the split stays the Kuhn one.
                assert_ne!(reflected(&mesh, &s, &[Axis::Y]), tets);
            }
        }
    }

    /// Without `mirror` the generator gives the same nodes and elements, in the same order, as
    /// it did before the option existed.
    #[test]
    fn without_mirror_the_kuhn_mesh_is_unchanged() {
        for divisions in [[1, 1, 1], [3, 2, 5], [60, 12, 6], [7, 14, 7]] {
            let s = spec(divisions, &[]);
            let (mesh, reference) = (box_mesh(&s), kuhn_reference(&s));
            assert_eq!(mesh.nodes, reference.nodes);
            assert_eq!(mesh.tets, reference.tets);
        }
        // And mirroring changes only the elements of the upper halves.
        let (plain, mirrored) = (
            box_mesh(&spec([4, 2, 2], &[])),
            box_mesh(&spec([4, 2, 2], &[Axis::X])),
        );
        assert_eq!(plain.nodes, mirrored.nodes);
        for (e, (a, b)) in plain.tets.iter().zip(&mirrored.tets).enumerate() {
            let upper = (e / 6) % 4 >= 2;
            assert_eq!(a != b, upper, "element {e}: {a:?} {b:?}");
        }
    }

    #[test]
    fn an_odd_division_along_a_mirrored_axis_is_refused() {
        let err = spec([60, 12, 5], &[Axis::X, Axis::Z])
            .check()
            .expect_err("5 cells along z");
        let msg = err.to_string();
        assert!(
            msg.contains("mesh.box.mirror")
                && msg.contains("use an even number of divisions along z"),
            "{msg}"
        );
        assert!(spec([60, 12, 5], &[Axis::X]).check().is_ok());
        assert!(spec([60, 0, 6], &[]).check().is_err());
    }
}
