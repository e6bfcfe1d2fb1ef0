//! Structured box meshes: each hexahedral cell split into six tetrahedra.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::Mesh;
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
/// `i + (nx + 1) * (j + (ny + 1) * k)`; elements run cell by cell in the same order.
pub fn box_mesh(spec: &BoxSpec) -> Mesh {
    let [nx, ny, nz] = spec.divisions;
    assert!(
        nx > 0 && ny > 0 && nz > 0,
        "a box needs at least one cell per axis"
    );
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
    let mut tets = Vec::with_capacity(6 * nx * ny * nz);
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
