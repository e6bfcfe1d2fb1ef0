//! Values at nodes, indexed by global node id, stored for the nodes a rank keeps only.
//!
//! On one process a [`NodeField`] is a plain vector over every node. On a rank of a distributed
//! run it stores the *pages* of [`NODE_PAGE`] consecutive node ids that hold at least one of the
//! rank's active nodes (`crate::distributed::NodePlan::active`): its elements' nodes and the
//! exchanged ones, about `1 / P` of the mesh plus a halo. Ids stay global everywhere (contact,
//! probes, the exchange), only the storage is the rank's; reading a node of a page the rank does
//! not store is a bug and panics.

use std::ops::{Index, IndexMut, Range};
use std::sync::Arc;

/// Node ids per page of a rank's [`NodeField`]: a page is stored whole as soon as one of its
/// nodes is active. Small because the exchanged nodes may be scattered over the whole id range
/// (the pushed end face of a box numbered with x fastest has one node in every 101: pages of 64
/// stored 82 % of the nodes on each of two ranks), large enough that the page table stays
/// small (4 bytes per 8 nodes, against 24 bytes per node of each vector field).
pub const NODE_PAGE: usize = 8;
const PAGE_SHIFT: u32 = NODE_PAGE.trailing_zeros();
const ABSENT: u32 = u32::MAX;

/// Where each node's value lies in the storage of the [`NodeField`]s that share this layout.
#[derive(Debug, Clone)]
pub struct NodeSlots {
    node_count: usize,
    /// Storage offset of each page's first node (`ABSENT` for a page not stored), or `None`
    /// when every node is stored at its own id.
    pages: Option<Arc<[u32]>>,
    stored: usize,
}

impl NodeSlots {
    /// Every one of `node_count` nodes, at its own id (one process).
    pub fn dense(node_count: usize) -> Self {
        Self {
            node_count,
            pages: None,
            stored: node_count,
        }
    }

    /// The pages of `node_count` nodes that hold a node of the ascending `runs`.
    pub fn paged(node_count: usize, runs: &[Range<usize>]) -> Self {
        let mut pages = vec![ABSENT; node_count.div_ceil(NODE_PAGE)];
        for run in runs.iter().filter(|r| !r.is_empty()) {
            let (first, last) = (run.start >> PAGE_SHIFT, (run.end - 1) >> PAGE_SHIFT);
            pages[first..=last].iter_mut().for_each(|p| *p = 0);
        }
        let mut stored = 0usize;
        for (k, page) in pages.iter_mut().enumerate() {
            if *page != ABSENT {
                *page = u32::try_from(stored).expect("a rank stores fewer than 2^32 nodes");
                stored += NODE_PAGE.min(node_count - k * NODE_PAGE);
            }
        }
        Self {
            node_count,
            pages: Some(pages.into()),
            stored,
        }
    }

    /// Number of values stored.
    pub fn stored(&self) -> usize {
        self.stored
    }

    /// Whether every node is stored at its own id.
    pub fn is_dense(&self) -> bool {
        self.pages.is_none()
    }

    /// Storage position of node `a`, if it is stored.
    #[inline(always)]
    pub fn slot(&self, a: usize) -> Option<usize> {
        if a >= self.node_count {
            return None;
        }
        match &self.pages {
            None => Some(a),
            Some(pages) => {
                let base = *pages.get(a >> PAGE_SHIFT)?;
                (base != ABSENT).then(|| base as usize + (a & (NODE_PAGE - 1)))
            }
        }
    }

    /// Storage position of node `a`, which must be stored.
    #[inline(always)]
    fn slot_of(&self, a: usize) -> usize {
        match &self.pages {
            None => a,
            Some(pages) => {
                let base = pages[a >> PAGE_SHIFT];
                debug_assert!(base != ABSENT, "node {a} is not stored on this rank");
                // An absent page gives a position past the storage: the access panics.
                (base as usize).wrapping_add(a & (NODE_PAGE - 1))
            }
        }
    }

    /// The stored node ids, ascending, with their storage positions (also ascending).
    pub fn stored_ids(&self) -> impl Iterator<Item = usize> + '_ {
        let pages = self.pages.as_deref();
        let n = self.node_count;
        (0..n.div_ceil(NODE_PAGE))
            .filter(move |&k| pages.is_none_or(|p| p[k] != ABSENT))
            .flat_map(move |k| k * NODE_PAGE..((k + 1) * NODE_PAGE).min(n))
    }
}

/// A value at every node a rank stores ([`NodeSlots`]), indexed by global node id.
#[derive(Debug, Clone)]
pub struct NodeField<T> {
    slots: NodeSlots,
    data: Vec<T>,
}

impl<T: Clone> NodeField<T> {
    /// `value` at every stored node.
    pub fn filled(slots: &NodeSlots, value: T) -> Self {
        Self {
            data: vec![value; slots.stored],
            slots: slots.clone(),
        }
    }

    /// The stored nodes' values of the whole-mesh `values`.
    pub fn from_whole(slots: &NodeSlots, values: &[T]) -> Self {
        assert_eq!(values.len(), slots.node_count, "one value per node");
        let data = if slots.is_dense() {
            values.to_vec()
        } else {
            slots.stored_ids().map(|a| values[a].clone()).collect()
        };
        Self {
            slots: slots.clone(),
            data,
        }
    }

    /// Sets every stored value to `value`.
    pub fn fill(&mut self, value: T) {
        self.data.fill(value);
    }
}

impl<T> NodeField<T> {
    /// A dense field of the whole-mesh `values` (one process).
    pub fn dense(values: Vec<T>) -> Self {
        Self {
            slots: NodeSlots::dense(values.len()),
            data: values,
        }
    }

    /// Number of nodes of the mesh (not the number stored).
    pub fn len(&self) -> usize {
        self.slots.node_count
    }

    /// Whether the mesh has no node.
    pub fn is_empty(&self) -> bool {
        self.slots.node_count == 0
    }

    /// The layout of the storage.
    pub fn slots(&self) -> &NodeSlots {
        &self.slots
    }

    /// The value at node `a`, if this field stores it.
    #[inline]
    pub fn get(&self, a: usize) -> Option<&T> {
        self.slots.slot(a).map(|s| &self.data[s])
    }

    /// The value at node `a`, if this field stores it.
    #[inline]
    pub fn get_mut(&mut self, a: usize) -> Option<&mut T> {
        self.slots.slot(a).map(|s| &mut self.data[s])
    }

    /// Every node's value, when every node is stored at its id (one process).
    pub fn as_slice(&self) -> Option<&[T]> {
        self.slots.is_dense().then_some(&self.data[..])
    }

    /// The values of the stored nodes, in ascending id ([`NodeSlots::stored_ids`]).
    pub fn stored(&self) -> &[T] {
        &self.data
    }

    /// The values of every node, taken out when the field is dense.
    pub fn into_dense(self) -> Option<Vec<T>> {
        self.slots.is_dense().then_some(self.data)
    }

    /// The values of the consecutive nodes `run`, all stored.
    pub fn run(&self, run: Range<usize>) -> &[T] {
        if run.is_empty() {
            return &[];
        }
        let start = self.slots.slot_of(run.start);
        // Every page between two stored nodes of a run is stored, and stored in id order.
        debug_assert_eq!(self.slots.slot(run.end - 1), Some(start + run.len() - 1));
        &self.data[start..start + run.len()]
    }

    /// The values of the consecutive nodes `run`, all stored.
    pub fn run_mut(&mut self, run: Range<usize>) -> &mut [T] {
        if run.is_empty() {
            return &mut [];
        }
        let start = self.slots.slot_of(run.start);
        debug_assert_eq!(self.slots.slot(run.end - 1), Some(start + run.len() - 1));
        &mut self.data[start..start + run.len()]
    }

    /// A view for readers that index by node id without owning the field.
    pub fn view(&self) -> NodeView<'_, T> {
        NodeView {
            pages: self.slots.pages.as_deref(),
            data: &self.data,
        }
    }

    /// A view for a writer that indexes by node id without owning the field.
    pub fn view_mut(&mut self) -> NodeViewMut<'_, T> {
        NodeViewMut {
            pages: self.slots.pages.as_deref(),
            data: &mut self.data,
        }
    }
}

impl<T> Index<usize> for NodeField<T> {
    type Output = T;
    #[inline(always)]
    fn index(&self, a: usize) -> &T {
        &self.data[self.slots.slot_of(a)]
    }
}

impl<T> IndexMut<usize> for NodeField<T> {
    #[inline(always)]
    fn index_mut(&mut self, a: usize) -> &mut T {
        let s = self.slots.slot_of(a);
        &mut self.data[s]
    }
}

/// Storage position of node `a` under the page table `pages` ([`NodeSlots`]); past the storage
/// for a node not stored, so that the access panics.
#[inline(always)]
fn slot_in(pages: Option<&[u32]>, a: usize) -> usize {
    match pages {
        None => a,
        Some(pages) => (pages[a >> PAGE_SHIFT] as usize).wrapping_add(a & (NODE_PAGE - 1)),
    }
}

/// The page table of a [`NodeField`]'s storage, apart from the values: where each node lies.
#[derive(Debug, Clone, Copy)]
pub struct NodeIndexer<'a> {
    pages: Option<&'a [u32]>,
}

impl NodeIndexer<'_> {
    /// Storage position of node `a`: past the storage for a node not stored.
    #[inline(always)]
    pub fn slot(&self, a: usize) -> usize {
        slot_in(self.pages, a)
    }

    /// Whether every node lies at its own id.
    pub fn is_dense(&self) -> bool {
        self.pages.is_none()
    }

    /// Whether `other` lays values out as this one does.
    pub fn same_as(&self, other: &NodeIndexer<'_>) -> bool {
        match (self.pages, other.pages) {
            (None, None) => true,
            (Some(a), Some(b)) => std::ptr::eq(a, b),
            _ => false,
        }
    }
}

/// Values at nodes borrowed for reading by node id: a [`NodeField`]'s storage, or a slice over
/// every node.
#[derive(Debug, Clone, Copy)]
pub struct NodeView<'a, T> {
    pages: Option<&'a [u32]>,
    data: &'a [T],
}

impl<'a, T> NodeView<'a, T> {
    /// Where each node lies in [`Self::storage`].
    pub fn indexer(&self) -> NodeIndexer<'a> {
        NodeIndexer { pages: self.pages }
    }

    /// The stored values.
    pub fn storage(&self) -> &'a [T] {
        self.data
    }
}

impl<T> Index<usize> for NodeView<'_, T> {
    type Output = T;
    #[inline(always)]
    fn index(&self, a: usize) -> &T {
        &self.data[slot_in(self.pages, a)]
    }
}

impl<'a, T> From<&'a [T]> for NodeView<'a, T> {
    fn from(data: &'a [T]) -> Self {
        Self { pages: None, data }
    }
}

impl<'a, T> From<&'a Vec<T>> for NodeView<'a, T> {
    fn from(data: &'a Vec<T>) -> Self {
        Self { pages: None, data }
    }
}

impl<'a, T> From<&'a NodeField<T>> for NodeView<'a, T> {
    fn from(field: &'a NodeField<T>) -> Self {
        field.view()
    }
}

/// Values at nodes borrowed for writing by node id ([`NodeView`]'s counterpart).
#[derive(Debug)]
pub struct NodeViewMut<'a, T> {
    pages: Option<&'a [u32]>,
    data: &'a mut [T],
}

impl<'a, T> NodeViewMut<'a, T> {
    /// Where each node lies in [`Self::storage_mut`].
    pub fn indexer(&self) -> NodeIndexer<'a> {
        NodeIndexer { pages: self.pages }
    }

    /// The stored values.
    pub fn storage_mut(&mut self) -> &mut [T] {
        self.data
    }
}

impl<T> Index<usize> for NodeViewMut<'_, T> {
    type Output = T;
    #[inline(always)]
    fn index(&self, a: usize) -> &T {
        &self.data[slot_in(self.pages, a)]
    }
}

impl<T> IndexMut<usize> for NodeViewMut<'_, T> {
    #[inline(always)]
    fn index_mut(&mut self, a: usize) -> &mut T {
        &mut self.data[slot_in(self.pages, a)]
    }
}

impl<'a, T> From<&'a mut [T]> for NodeViewMut<'a, T> {
    fn from(data: &'a mut [T]) -> Self {
        Self { pages: None, data }
    }
}

impl<'a, T> From<&'a mut Vec<T>> for NodeViewMut<'a, T> {
    fn from(data: &'a mut Vec<T>) -> Self {
        Self { pages: None, data }
    }
}

impl<'a, T> From<&'a mut NodeField<T>> for NodeViewMut<'a, T> {
    fn from(field: &'a mut NodeField<T>) -> Self {
        field.view_mut()
    }
}

/// Values at nodes written node by node: a slice over every node or a [`NodeField`].
pub trait NodeStoreMut<T> {
    /// Calls `f` with each stored node's id and value, ascending.
    fn for_each_stored(&mut self, f: impl FnMut(usize, &mut T));
    /// The value at node `a`, if it is stored.
    fn stored_mut_at(&mut self, a: usize) -> Option<&mut T>;
}

impl<T> NodeStoreMut<T> for [T] {
    fn for_each_stored(&mut self, mut f: impl FnMut(usize, &mut T)) {
        self.iter_mut().enumerate().for_each(|(a, x)| f(a, x));
    }
    fn stored_mut_at(&mut self, a: usize) -> Option<&mut T> {
        self.get_mut(a)
    }
}

impl<T> NodeStoreMut<T> for Vec<T> {
    fn for_each_stored(&mut self, f: impl FnMut(usize, &mut T)) {
        self.as_mut_slice().for_each_stored(f);
    }
    fn stored_mut_at(&mut self, a: usize) -> Option<&mut T> {
        self.get_mut(a)
    }
}

impl<T> NodeStoreMut<T> for NodeField<T> {
    fn for_each_stored(&mut self, mut f: impl FnMut(usize, &mut T)) {
        let Self { slots, data } = self;
        slots
            .stored_ids()
            .zip(data.iter_mut())
            .for_each(|(a, x)| f(a, x));
    }
    fn stored_mut_at(&mut self, a: usize) -> Option<&mut T> {
        self.get_mut(a)
    }
}

/// Values at nodes readable by node id: a slice over every node, a [`NodeField`] or a view.
pub trait NodeValues<T>: Index<usize, Output = T> + Sync {}
impl<T, S: Index<usize, Output = T> + Sync + ?Sized> NodeValues<T> for S {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_paged_field_stores_the_pages_of_its_runs_and_reads_them_by_id() {
        let n = 1000;
        let runs = [3..5, 130..400, 999..1000];
        let slots = NodeSlots::paged(n, &runs);
        // Pages of 8: 0 (ids 0..8), 16-49 (128..400) and 124 (992..1000).
        assert_eq!(slots.stored(), 8 + 34 * 8 + 8);
        let whole: Vec<u64> = (0..n as u64).map(|a| a * a).collect();
        let field = NodeField::from_whole(&slots, &whole);
        for run in &runs {
            for a in run.clone() {
                assert_eq!(field[a], whole[a]);
            }
            assert_eq!(field.run(run.clone()), &whole[run.clone()]);
        }
        assert_eq!(field.get(64), None, "page 8 holds no active node");
        assert_eq!(field.get(n), None);
        assert_eq!(field.get(200), Some(&whole[200]));
        let ids: Vec<usize> = slots.stored_ids().collect();
        assert_eq!(ids.len(), slots.stored());
        assert!(ids.iter().zip(field.stored()).all(|(&a, &x)| x == whole[a]));
    }

    #[test]
    #[should_panic]
    fn reading_a_node_of_a_page_not_stored_panics() {
        let runs = [0..10, 20..30];
        let slots = NodeSlots::paged(1000, &runs);
        let field = NodeField::filled(&slots, 1.0);
        let _ = field[500];
    }

    #[test]
    fn a_dense_field_is_the_whole_vector() {
        let whole = vec![1.0, 2.0, 3.0];
        let field = NodeField::dense(whole.clone());
        assert_eq!(field.as_slice(), Some(&whole[..]));
        assert_eq!(field.run(1..3), &whole[1..3]);
        assert_eq!(field.get(3), None);
    }
}
