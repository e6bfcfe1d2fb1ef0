//! Deterministic, parallel assembly of element forces into nodal forces.
//!
//! Elements are cut into fixed chunks of consecutive ids (never crossing a body, so each chunk
//! has one material). A node whose elements all lie in one chunk is *private*: that chunk adds
//! into it directly, in ascending element order. Any other node is *shared*: its element
//! contributions go to their own slots of a buffer, laid out per node in ascending element order,
//! and a second pass sums each node's slots in that order. Either way a node's force is
//! `((0 + f_e1) + f_e2) + ...` over its elements in ascending id, exactly what a serial scatter
//! gives, for any number of threads. The chunking does not depend on the thread count.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::{element_internal_forces, Model};
use crate::with_material;

/// Elements per chunk: large enough that shared nodes are few, small enough to balance two cores.
const CHUNK: usize = 2048;
const PRIVATE: u32 = u32::MAX;

#[derive(Debug)]
pub struct ForceAssembler {
    chunks: Vec<(usize, Range<usize>)>,
    /// Per element corner `4 e + a`: `PRIVATE`, or its slot in the shared buffer.
    corner_slot: Vec<u32>,
    shared_nodes: Vec<u32>,
    /// Slots of shared node `i` are `shared_offsets[i]..shared_offsets[i + 1]`.
    shared_offsets: Vec<u32>,
    /// Element contributions to shared nodes, reused from step to step.
    buffer: Mutex<Vec<Vector3<f64>>>,
}

/// A raw pointer that may cross threads: every index written through it is written by exactly one
/// chunk (private nodes by their owner chunk, slots by their element), so the writes never race.
#[derive(Clone, Copy)]
struct DisjointWrites(*mut Vector3<f64>);
unsafe impl Send for DisjointWrites {}
unsafe impl Sync for DisjointWrites {}

impl ForceAssembler {
    pub fn new(tets: &[[u32; 4]], node_count: usize, bodies: &[Range<usize>]) -> Self {
        let mut chunks = Vec::new();
        for (body, range) in bodies.iter().enumerate() {
            let mut start = range.start;
            while start < range.end {
                let end = (start + CHUNK).min(range.end);
                chunks.push((body, start..end));
                start = end;
            }
        }
        let mut chunk_of_element = vec![0u32; tets.len()];
        for (c, (_, range)) in chunks.iter().enumerate() {
            chunk_of_element[range.clone()].fill(c as u32);
        }
        // A node is shared when its elements span more than one chunk.
        let mut first_chunk = vec![u32::MAX; node_count];
        let mut shared = vec![false; node_count];
        let mut incidence = vec![0u32; node_count];
        for (e, tet) in tets.iter().enumerate() {
            for &n in tet {
                let n = n as usize;
                let c = chunk_of_element[e];
                if first_chunk[n] == u32::MAX {
                    first_chunk[n] = c;
                } else if first_chunk[n] != c {
                    shared[n] = true;
                }
                incidence[n] += 1;
            }
        }
        let shared_nodes: Vec<u32> = (0..node_count as u32)
            .filter(|&n| shared[n as usize])
            .collect();
        let mut shared_offsets = Vec::with_capacity(shared_nodes.len() + 1);
        let mut next_slot = vec![0u32; node_count];
        let mut total = 0u32;
        shared_offsets.push(0);
        for &n in &shared_nodes {
            next_slot[n as usize] = total;
            total += incidence[n as usize];
            shared_offsets.push(total);
        }
        // Walking elements in ascending order fills each node's slots in ascending element order.
        let mut corner_slot = vec![PRIVATE; 4 * tets.len()];
        for (e, tet) in tets.iter().enumerate() {
            for (a, &n) in tet.iter().enumerate() {
                if shared[n as usize] {
                    corner_slot[4 * e + a] = next_slot[n as usize];
                    next_slot[n as usize] += 1;
                }
            }
        }
        Self {
            chunks,
            corner_slot,
            shared_nodes,
            shared_offsets,
            buffer: Mutex::new(vec![Vector3::zeros(); total as usize]),
        }
    }

    pub fn heap_bytes(&self) -> usize {
        4 * (self.corner_slot.len() + self.shared_nodes.len() + self.shared_offsets.len())
            + 24 * *self.shared_offsets.last().unwrap_or(&0) as usize
    }

    /// Fraction of nodes whose force goes through the shared buffer.
    pub fn shared_fraction(&self, node_count: usize) -> f64 {
        self.shared_nodes.len() as f64 / node_count.max(1) as f64
    }

    pub(super) fn assemble(
        &self,
        model: &Model,
        u: &[Vector3<f64>],
        f: &mut [Vector3<f64>],
    ) -> Option<usize> {
        assert_eq!(u.len(), f.len());
        f.par_iter_mut().for_each(|x| *x = Vector3::zeros());
        let mut buffer = self.buffer.lock().unwrap_or_else(|e| e.into_inner());
        let inverted = AtomicUsize::new(usize::MAX);
        let nodal = DisjointWrites(f.as_mut_ptr());
        let slot_out = DisjointWrites(buffer.as_mut_ptr());
        self.chunks.par_iter().for_each(|(body, range)| {
            let (nodal, slot_out) = (nodal, slot_out);
            with_material!(&model.bodies[*body].material, |m| {
                for e in range.clone() {
                    let tet = model.tets[e];
                    let ue = tet.map(|n| u[n as usize]);
                    let (fe, det) =
                        element_internal_forces(&m, &model.grad_n[e], model.volume[e], &ue);
                    if !(det > 0.0) {
                        inverted.fetch_min(e, Ordering::Relaxed);
                    }
                    for a in 0..4 {
                        let slot = self.corner_slot[4 * e + a];
                        // SAFETY: a private node is written only by the chunk that owns all of
                        // its elements, and a slot only by its element: no two threads write
                        // the same index, and both pointers outlive the parallel loop.
                        unsafe {
                            if slot == PRIVATE {
                                *nodal.0.add(tet[a] as usize) += fe[a];
                            } else {
                                *slot_out.0.add(slot as usize) = fe[a];
                            }
                        }
                    }
                }
            });
        });
        let buffer = &*buffer;
        self.shared_nodes
            .par_iter()
            .enumerate()
            .for_each(|(i, &n)| {
                let nodal = nodal;
                let range = self.shared_offsets[i] as usize..self.shared_offsets[i + 1] as usize;
                let sum = buffer[range]
                    .iter()
                    .fold(Vector3::zeros(), |acc, x| acc + x);
                // SAFETY: each shared node appears once in `shared_nodes`.
                unsafe { *nodal.0.add(n as usize) = sum };
            });
        match inverted.into_inner() {
            usize::MAX => None,
            e => Some(e),
        }
    }
}
