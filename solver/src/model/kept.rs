//! The per-element data that an element's own force computation reads, kept for one range of
//! elements: every element's on one process, a rank's own in a distributed run
//! (`crate::distributed`). Another element's, which only the run's setup (the stable step), the
//! output and error messages read, is computed again from the reference coordinates by the same
//! functions that computed the kept values, so it is the same bits.

use std::ops::Range;

use nalgebra::Vector3;

use super::{Connectivity, NodeArray};
use crate::kinematics::shape_gradients;
use crate::mesh::element_quality;

/// Shape-function gradients, reference volumes and smallest altitudes of the elements
/// `first..first + grad_n.len()` (112 bytes per element: 96 of gradients, 8 each of volume and
/// altitude).
#[derive(Debug)]
pub(super) struct KeptElementData {
    first: usize,
    /// Reference shape-function gradients `grad_X N_a` (3.44).
    grad_n: Vec<[Vector3<f64>; 4]>,
    /// Reference volumes `V` (m^3).
    volume: Vec<f64>,
    /// Smallest altitude `3 V / A_max` (m), the length of the stable step.
    min_altitude: Vec<f64>,
}

/// The reference gradients and volume of the tetrahedron with corners `x` (validated meshes
/// have positive volumes).
fn gradients_and_volume(x: &[Vector3<f64>; 4]) -> ([Vector3<f64>; 4], f64) {
    shape_gradients(x).expect("validated meshes have positive volumes")
}

impl KeptElementData {
    /// The data of the elements `range` of `tets` over `reference`, the volumes and altitudes
    /// taken from `volume` and `min_altitude` (every element's).
    pub(super) fn new(
        tets: &[[u32; 4]],
        reference: &[Vector3<f64>],
        range: Range<usize>,
        volume: Vec<f64>,
        min_altitude: Vec<f64>,
    ) -> Self {
        let part = |all: Vec<f64>| {
            if range == (0..all.len()) {
                all
            } else {
                all[range.clone()].to_vec()
            }
        };
        // The parts first: every element's volumes and altitudes are freed before the
        // gradients, the largest of the three, are allocated (a rank's peak during the setup).
        let volume = part(volume);
        let min_altitude = part(min_altitude);
        let grad_n = tets[range.clone()]
            .iter()
            .map(|tet| gradients_and_volume(&tet.map(|n| reference[n as usize])).0)
            .collect();
        Self {
            first: range.start,
            grad_n,
            volume,
            min_altitude,
        }
    }

    /// The data of the elements `range` of `tets` over `reference`, every value computed from
    /// the corners (by the functions that compute the whole model's, so the same bits).
    pub(super) fn compute(
        tets: &Connectivity,
        reference: &NodeArray<Vector3<f64>>,
        range: Range<usize>,
    ) -> Self {
        let elements = &tets[range.clone()];
        let mut data = Self {
            first: range.start,
            grad_n: Vec::with_capacity(elements.len()),
            volume: Vec::with_capacity(elements.len()),
            min_altitude: Vec::with_capacity(elements.len()),
        };
        for tet in elements {
            let x = tet.map(|n| reference[n as usize]);
            let (grad_n, volume) = gradients_and_volume(&x);
            data.grad_n.push(grad_n);
            data.volume.push(volume);
            data.min_altitude.push(element_quality(&x).min_altitude);
        }
        data
    }

    /// The elements whose data is kept.
    pub(super) fn range(&self) -> Range<usize> {
        self.first..self.first + self.grad_n.len()
    }

    /// The position of element `e` in the kept arrays, if it is kept.
    #[inline]
    fn slot(&self, e: usize) -> Option<usize> {
        e.checked_sub(self.first)
            .filter(|&at| at < self.grad_n.len())
    }

    /// The gradients of element `e` with corners `x` (read only where `e` is not kept).
    #[inline]
    pub(super) fn grad_n(
        &self,
        e: usize,
        x: impl FnOnce() -> [Vector3<f64>; 4],
    ) -> [Vector3<f64>; 4] {
        match self.slot(e) {
            Some(at) => self.grad_n[at],
            None => gradients_and_volume(&x()).0,
        }
    }

    /// The reference volume of element `e` with corners `x` (read only where `e` is not kept).
    #[inline]
    pub(super) fn volume(&self, e: usize, x: impl FnOnce() -> [Vector3<f64>; 4]) -> f64 {
        match self.slot(e) {
            Some(at) => self.volume[at],
            None => gradients_and_volume(&x()).1,
        }
    }

    /// The smallest altitude of element `e` with corners `x` (read only where `e` is not kept).
    #[inline]
    pub(super) fn min_altitude(&self, e: usize, x: impl FnOnce() -> [Vector3<f64>; 4]) -> f64 {
        match self.slot(e) {
            Some(at) => self.min_altitude[at],
            None => element_quality(&x()).min_altitude,
        }
    }

    /// The gradients of the kept elements of `range`.
    pub(super) fn grad_n_of(&self, range: Range<usize>) -> &[[Vector3<f64>; 4]] {
        &self.grad_n[range.start - self.first..range.end - self.first]
    }

    /// The volumes of the kept elements of `range`.
    pub(super) fn volumes_of(&self, range: Range<usize>) -> &[f64] {
        &self.volume[range.start - self.first..range.end - self.first]
    }

    /// Keeps the elements of `elements` only, which must be kept now.
    pub(super) fn keep(&mut self, elements: Range<usize>) {
        let kept = self.range();
        assert!(kept.start <= elements.start && elements.end <= kept.end);
        if kept == elements {
            return;
        }
        let at = elements.start - kept.start..elements.end - kept.start;
        self.grad_n = self.grad_n[at.clone()].to_vec();
        self.volume = self.volume[at.clone()].to_vec();
        self.min_altitude = self.min_altitude[at].to_vec();
        self.first = elements.start;
    }

    /// Heap bytes held.
    pub(super) fn heap_bytes(&self) -> usize {
        self.grad_n.len() * (std::mem::size_of::<[Vector3<f64>; 4]>() + 2 * 8)
    }
}

#[cfg(test)]
mod tests {
    use super::{gradients_and_volume, KeptElementData};
    use crate::mesh::element_quality;
    use nalgebra::Vector3;

    /// Four tetrahedra of different shapes sharing nodes.
    fn mesh() -> (Vec<[u32; 4]>, Vec<Vector3<f64>>) {
        let reference = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.1, 0.9, 0.0),
            Vector3::new(0.2, 0.3, 0.7),
            Vector3::new(1.1, 1.0, 0.4),
            Vector3::new(0.4, 0.2, -0.6),
        ];
        let tets = vec![[0, 1, 2, 3], [1, 4, 2, 3], [0, 2, 1, 5], [1, 2, 4, 5]];
        (tets, reference)
    }

    /// A part keeps the slices of the whole, and an element outside the part reads, computed
    /// again from its corners, the bits the build stored for it.
    #[test]
    fn an_element_outside_the_part_reads_the_bits_of_the_whole() {
        let (tets, reference) = mesh();
        let corners = |e: usize| tets[e].map(|n| reference[n as usize]);
        let volume: Vec<f64> = (0..4)
            .map(|e| gradients_and_volume(&corners(e)).1)
            .collect();
        let altitude: Vec<f64> = (0..4)
            .map(|e| element_quality(&corners(e)).min_altitude)
            .collect();
        let whole = KeptElementData::new(&tets, &reference, 0..4, volume.clone(), altitude.clone());
        let mut part = KeptElementData::new(&tets, &reference, 0..4, volume, altitude);
        part.keep(1..3);
        assert_eq!(part.range(), 1..3);
        assert_eq!(part.grad_n_of(1..3), whole.grad_n_of(1..3));
        assert_eq!(part.volumes_of(1..3), whole.volumes_of(1..3));
        for e in 0..4 {
            let x = || corners(e);
            assert_eq!(part.grad_n(e, x), whole.grad_n(e, x), "gradients of {e}");
            assert_eq!(
                part.volume(e, x).to_bits(),
                whole.volume(e, x).to_bits(),
                "volume of {e}"
            );
            assert_eq!(
                part.min_altitude(e, x).to_bits(),
                whole.min_altitude(e, x).to_bits(),
                "altitude of {e}"
            );
        }
        assert_eq!(part.heap_bytes(), 2 * 112);
    }
}
