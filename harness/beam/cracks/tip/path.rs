//! The bending crack's path: which elements touch which, where the crack starts, and the
//! face-connected set of open elements grown from there.
//!
//! A per-layer maximum over a strip stacks every opening in the strip into one "tip": inclined
//! bands under the hammer's edges, twin cracks, a splitting column. The path here is one
//! connected body of elements instead: an opening counts only if it is joined to the crack at
//! mid-span's bottom through open elements that share faces.

use std::collections::HashMap;

use super::super::{BeamElement, BeamFrame};

/// The elements a bending crack can grow through, and how they connect.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackPath {
    /// Face neighbours of each element (indices into the beam's elements, ascending).
    pub neighbours: Vec<Vec<usize>>,
    /// Where the bending crack starts: the elements of the bottom cell layer (centroid less than
    /// one cell above the bottom face) within one cell of mid-span (`|x - x_load| <= c`).
    pub seeds: Vec<usize>,
    /// Whether an element may belong to the crack: every element but those of the loading
    /// region (the crushing under the impactor, [`BeamFrame::in_loading_region`]).
    pub allowed: Vec<bool>,
    /// Height of each element's centroid above the bottom face (m).
    pub height: Vec<f64>,
    /// Whether an element is in the column under the load that the compressive wave runs down:
    /// allowed, and within one cell of the load's centre line (`|x - x_load| <= c`), the seeds'
    /// strip.
    pub column: Vec<bool>,
    /// Depth of each element's centroid below the top face (m).
    pub depth: Vec<f64>,
    /// The elements that share a node with each element, itself excluded (ascending): those
    /// next to it across a face, an edge or a corner.
    pub touching: Vec<Vec<usize>>,
}

/// The elements sharing at least one node with each element (itself excluded, ascending).
pub fn node_neighbours(elements: &[BeamElement]) -> Vec<Vec<usize>> {
    let mut by_node: HashMap<u32, Vec<usize>> = HashMap::with_capacity(elements.len());
    for (e, el) in elements.iter().enumerate() {
        for &v in &el.nodes {
            by_node.entry(v).or_default().push(e);
        }
    }
    elements
        .iter()
        .enumerate()
        .map(|(e, el)| {
            let mut near: Vec<usize> = el
                .nodes
                .iter()
                .flat_map(|v| by_node[v].iter().copied())
                .filter(|&m| m != e)
                .collect();
            near.sort_unstable();
            near.dedup();
            near
        })
        .collect()
}

/// Face neighbours of tetrahedra: two elements are neighbours when they share three nodes.
/// Each face is keyed by its sorted node ids, so the result does not depend on node order.
pub fn face_neighbours(elements: &[BeamElement]) -> Vec<Vec<usize>> {
    let mut first: HashMap<[u32; 3], usize> = HashMap::with_capacity(2 * elements.len());
    let mut neighbours = vec![Vec::new(); elements.len()];
    for (e, el) in elements.iter().enumerate() {
        for skip in 0..4 {
            let mut face = [0u32; 3];
            let mut k = 0;
            for (i, &n) in el.nodes.iter().enumerate() {
                if i != skip {
                    face[k] = n;
                    k += 1;
                }
            }
            face.sort_unstable();
            match first.remove(&face) {
                Some(other) => {
                    neighbours[e].push(other);
                    neighbours[other].push(e);
                }
                None => {
                    first.insert(face, e);
                }
            }
        }
    }
    for n in &mut neighbours {
        n.sort_unstable();
    }
    neighbours
}

impl CrackPath {
    /// The path of a beam with the given element neighbours (from [`face_neighbours`] for a
    /// tetrahedral mesh; any adjacency for a test grid).
    pub fn new(frame: &BeamFrame, elements: &[BeamElement], neighbours: Vec<Vec<usize>>) -> Self {
        let height: Vec<f64> = elements
            .iter()
            .map(|e| e.centroid.y - frame.y_bottom)
            .collect();
        let allowed: Vec<bool> = elements
            .iter()
            .map(|e| !frame.in_loading_region(&e.centroid))
            .collect();
        let seeds = elements
            .iter()
            .enumerate()
            .filter(|(i, e)| {
                height[*i] < frame.cell
                    && (e.centroid.x - frame.x_load).abs() <= frame.cell
                    && allowed[*i]
            })
            .map(|(i, _)| i)
            .collect();
        let column = elements
            .iter()
            .zip(&allowed)
            .map(|(e, &a)| a && (e.centroid.x - frame.x_load).abs() <= frame.cell)
            .collect();
        let depth = height.iter().map(|h| frame.height - h).collect();
        Self {
            neighbours,
            seeds,
            allowed,
            height,
            column,
            depth,
            touching: node_neighbours(elements),
        }
    }

    /// The path of a beam from its tetrahedra's faces.
    pub fn of(frame: &BeamFrame, elements: &[BeamElement]) -> Self {
        Self::new(frame, elements, face_neighbours(elements))
    }

    /// The elements joined to a seed through `open` allowed elements that share faces (flood
    /// fill, breadth first): the crack of the open elements.
    pub fn connected(&self, open: &[bool]) -> Vec<bool> {
        let mut member = vec![false; open.len()];
        let mut queue: Vec<usize> = Vec::new();
        for &s in &self.seeds {
            if open[s] && !member[s] {
                member[s] = true;
                queue.push(s);
            }
        }
        while let Some(e) = queue.pop() {
            for &n in &self.neighbours[e] {
                if !member[n] && open[n] && self.allowed[n] {
                    member[n] = true;
                    queue.push(n);
                }
            }
        }
        member
    }
}
