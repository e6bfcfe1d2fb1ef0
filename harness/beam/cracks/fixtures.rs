//! Side-view grids of elements and crack patterns shared by the tests of the classification and
//! of the tip.

use impact_solver::Vector3;

use super::{BeamElement, BeamFrame};

/// A side-view grid of `nx x ny` unit-less cells of size `c`, one element per cell whose
/// nodes are the cell's corners (as a tetrahedron would share them), `nz = 1`.
pub(super) fn grid(nx: usize, ny: usize, c: f64) -> Vec<BeamElement> {
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut out = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            out.push(BeamElement {
                centroid: Vector3::new((i as f64 + 0.5) * c, (j as f64 + 0.5) * c, 0.0),
                nodes: [id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)],
            });
        }
    }
    out
}

/// Beam 3.0 x 0.6 in cells of 0.05 (60 x 12), load at 1.5, supports at 0.1 and 2.9.
pub(super) fn frame() -> BeamFrame {
    BeamFrame {
        x_load: 1.5,
        load_half_width: 0.15,
        y_bottom: 0.0,
        height: 0.6,
        cell: 0.05,
        supports: vec![[0.05, 0.15], [2.85, 2.95]],
        min_elements: 4,
    }
}

/// Crack indicators of a 60-column grid: 1 (cracked) in `cells`, 0 elsewhere.
pub(super) fn flag(elements: &[BeamElement], cells: &[(usize, usize)]) -> Vec<f64> {
    let mut f = vec![0.0; elements.len()];
    raise(&mut f, cells, 1.0);
    f
}

/// Sets the indicator of `cells` of a 60-column grid to `level`.
pub(super) fn raise(indicator: &mut [f64], cells: &[(usize, usize)], level: f64) {
    for &(i, j) in cells {
        indicator[j * 60 + i] = level;
    }
}

/// A vertical crack at mid-span, from the bottom up to row `rows - 1`.
pub(super) fn vertical(rows: usize) -> Vec<(usize, usize)> {
    (0..rows).map(|j| (29, j)).collect()
}

/// A 45-degree crack on the left rising towards the load: columns 16..24 over rows 0..8.
pub(super) fn shear_left() -> Vec<(usize, usize)> {
    (0..8).map(|k| (16 + k, k)).collect()
}
