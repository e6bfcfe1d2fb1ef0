//! How a model with one body remeshed relates to the model before: the other bodies' nodes and
//! elements are copied in order, the remeshed body's come from [`RemeshedRegion`] (kept ones
//! copied, new ones transferred). The model's bodies are consecutive ranges of global ids, so
//! the bodies after the remeshed one shift by the change in its node and element counts.

use std::ops::Range;

use nalgebra::Vector3;

use super::transfer::transfer_nodal_vectors;
use crate::mesh::ops::locate::Location;
use crate::mesh::ops::mesher::RemeshedRegion;

/// The old and new global numbering around one remeshed body.
#[derive(Debug)]
pub(super) struct Splice<'a> {
    /// The remeshed body's old node ids.
    pub old_nodes: Range<usize>,
    /// The remeshed body's old element ids.
    pub old_elements: Range<usize>,
    /// The body's old connectivity in its own node ids.
    pub local_tets: Vec<[u32; 4]>,
    /// The body's new mesh, in its own ids.
    pub new: &'a RemeshedRegion,
    /// Where each of the body's new nodes lies in its old mesh (own ids).
    pub locations: &'a [Location],
    /// Old node count of the model.
    pub old_node_count: usize,
    /// Old element count of the model.
    pub old_element_count: usize,
}

impl Splice<'_> {
    /// Nodes of the new model.
    pub fn node_count(&self) -> usize {
        self.old_node_count - self.old_nodes.len() + self.new.nodes.len()
    }

    /// Elements of the new model.
    pub fn element_count(&self) -> usize {
        self.old_element_count - self.old_elements.len() + self.new.tets.len()
    }

    /// The remeshed body's new node ids.
    pub fn new_nodes(&self) -> Range<usize> {
        self.old_nodes.start..self.old_nodes.start + self.new.nodes.len()
    }

    /// The remeshed body's new element ids.
    pub fn new_elements(&self) -> Range<usize> {
        self.old_elements.start..self.old_elements.start + self.new.tets.len()
    }

    /// The new id of old node `o`: shifted outside the body, mapped through the kept nodes
    /// inside it; `None` for a node the remeshing replaced.
    pub fn node(&self, o: usize) -> Option<usize> {
        if o < self.old_nodes.start {
            Some(o)
        } else if o < self.old_nodes.end {
            self.new.kept_nodes[o - self.old_nodes.start].map(|k| k as usize + self.old_nodes.start)
        } else {
            Some(o - self.old_nodes.len() + self.new.nodes.len())
        }
    }

    /// A nodal vector field on the new model: copied outside the remeshed body and at its kept
    /// nodes, T3 (8.10) at its new ones.
    pub fn nodal(&self, old: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        let body = &old[self.old_nodes.clone()];
        let mut inside = transfer_nodal_vectors(body, &self.local_tets, self.locations);
        for (o, k) in self.new.kept_nodes.iter().enumerate() {
            if let Some(k) = k {
                inside[*k as usize] = body[o];
            }
        }
        let mut out = Vec::with_capacity(self.node_count());
        out.extend_from_slice(&old[..self.old_nodes.start]);
        out.extend(inside);
        out.extend_from_slice(&old[self.old_nodes.end..]);
        out
    }

    /// An element field on the new model: copied where the element is a copy, `region(e)` (the
    /// body's new element `e` in its own ids) where it is new.
    pub fn elements<T: Clone>(&self, old: &[T], mut region: impl FnMut(usize) -> T) -> Vec<T> {
        let first = self.old_elements.start;
        let mut out = Vec::with_capacity(self.element_count());
        out.extend_from_slice(&old[..first]);
        for (e, origin) in self.new.element_origin.iter().enumerate() {
            out.push(match origin {
                Some(o) => old[first + *o as usize].clone(),
                None => region(e),
            });
        }
        out.extend_from_slice(&old[self.old_elements.end..]);
        out
    }

    /// The new ids of a node set given in old ids: each old node mapped where kept, and each new
    /// node of the remeshed body that lies on its new outer boundary with every old node of its
    /// support in the set. The support of a new node is the old nodes with a barycentric
    /// weight above 1e-9 in the old element that holds it: a midpoint of an old boundary edge has
    /// the edge's two ends, a point inside an old boundary face its three nodes. So a node
    /// inserted on a constrained face joins the face's set, and one inside the body or on
    /// another face does not. (An edge whose ends are both in the set but which does not lie on
    /// the set's faces would wrongly add its midpoint; this cannot happen for a set that is all
    /// the nodes of a planar face.) `on_boundary` flags the body's new nodes (own ids).
    pub fn node_set(&self, set: &[u32], on_boundary: &[bool]) -> Vec<u32> {
        let mut out: Vec<u32> = set
            .iter()
            .filter_map(|&n| self.node(n as usize).map(|k| k as u32))
            .collect();
        let first = self.old_nodes.start;
        let member: Vec<bool> = {
            let mut m = vec![false; self.old_nodes.len()];
            for &n in set {
                if self.old_nodes.contains(&(n as usize)) {
                    m[n as usize - first] = true;
                }
            }
            m
        };
        if member.iter().any(|&m| m) {
            for n in self.new.new_nodes() {
                let l = &self.locations[n as usize];
                let mut support = self.local_tets[l.element]
                    .iter()
                    .zip(l.barycentric)
                    .filter(|(_, w)| *w > 1e-9);
                if on_boundary[n as usize] && support.all(|(&o, _)| member[o as usize]) {
                    out.push(n + first as u32);
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// The new ids of the nodes of `nodes` that are kept (a probe or a load keeps only the
    /// nodes it was given).
    pub fn kept(&self, nodes: &[u32]) -> Vec<u32> {
        nodes
            .iter()
            .filter_map(|&n| self.node(n as usize).map(|k| k as u32))
            .collect()
    }
}
