//! A value per node of the model, indexed by global node id: every node's on one process, one
//! rank's own nodes only once a distributed run has planned them ([`NodeArray::keep`]), and every
//! node's again after the run ([`NodeArray::restore`], gathered from the ranks). The model's
//! reference coordinates and masses and the problem's initial velocities are such arrays.

use std::ops::{Deref, DerefMut, Index, IndexMut, Range, RangeFrom, RangeFull, RangeTo};

use crate::nodal::{NodeField, NodeSlots};

/// Values at nodes: `self[a]` is node `a`'s.
///
/// Whole, it reads as a slice (`iter`, `&x[range]`, passing `&model.reference` where a slice is
/// asked). Kept for a rank's nodes (the pages of its [`NodeSlots`]), it holds and indexes those
/// only, by their global ids; reading it as a whole slice, or a node it does not store, panics
/// with the node named: a rank that read another rank's node would compute with a value it was
/// never meant to hold.
#[derive(Debug, Clone)]
pub struct NodeArray<T> {
    values: NodeField<T>,
}

impl<T> From<Vec<T>> for NodeArray<T> {
    fn from(values: Vec<T>) -> Self {
        Self {
            values: NodeField::dense(values),
        }
    }
}

impl<T> FromIterator<T> for NodeArray<T> {
    fn from_iter<I: IntoIterator<Item = T>>(values: I) -> Self {
        values.into_iter().collect::<Vec<T>>().into()
    }
}

impl<'a, T> IntoIterator for &'a NodeArray<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;

    /// Every node's value, in id order (a whole array).
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<T> Default for NodeArray<T> {
    fn default() -> Self {
        Vec::new().into()
    }
}

impl<T: PartialEq> PartialEq for NodeArray<T> {
    /// The same nodes stored, with the same values.
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len()
            && self.stored() == other.stored()
            && self
                .values
                .slots()
                .stored_ids()
                .eq(other.values.slots().stored_ids())
    }
}

impl<T> NodeArray<T> {
    /// Number of nodes of the whole model, stored or not.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the model has no node.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Whether every node is stored at its id.
    pub fn is_whole(&self) -> bool {
        self.values.slots().is_dense()
    }

    /// The stored values, in ascending node id ([`NodeSlots::stored_ids`]).
    pub fn stored(&self) -> &[T] {
        self.values.stored()
    }

    /// The stored values as a field of the solver's kind (whole: every node).
    pub fn field(&self) -> &NodeField<T> {
        &self.values
    }

    /// Every node's value again (`whole`, gathered from the ranks that kept parts of it).
    pub fn restore(&mut self, whole: Vec<T>) {
        assert_eq!(whole.len(), self.len(), "a whole node array restored");
        self.values = NodeField::dense(whole);
    }

    #[cold]
    #[inline(never)]
    fn not_stored(&self, a: usize) -> ! {
        panic!(
            "node {a} is not stored here ({} of {} nodes are)",
            self.values.stored().len(),
            self.len()
        )
    }

    #[cold]
    #[inline(never)]
    fn not_stored_run(&self, run: Range<usize>) -> ! {
        panic!("nodes {run:?} are not all stored here")
    }

    #[cold]
    #[inline(never)]
    fn not_whole(&self) -> ! {
        panic!(
            "a node array kept for one rank's nodes ({} of {}) read whole",
            self.values.stored().len(),
            self.len()
        )
    }
}

impl<T: Clone> NodeArray<T> {
    /// Keeps the values of the nodes `slots` stores only (a rank's, once its plan is made) and
    /// frees the others; dense slots keep all.
    pub fn keep(&mut self, slots: &NodeSlots) {
        assert!(
            self.is_whole(),
            "a node array is kept for a rank's nodes once"
        );
        if slots.is_dense() {
            return;
        }
        self.values = NodeField::from_whole(slots, self.values.stored());
    }
}

impl<T> Deref for NodeArray<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        match self.values.as_slice() {
            Some(all) => all,
            None => self.not_whole(),
        }
    }
}

impl<T> DerefMut for NodeArray<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        if !self.is_whole() {
            self.not_whole();
        }
        self.values.run_mut(0..self.values.len())
    }
}

impl<T> Index<usize> for NodeArray<T> {
    type Output = T;

    #[inline]
    fn index(&self, a: usize) -> &T {
        match self.values.get(a) {
            Some(value) => value,
            None => self.not_stored(a),
        }
    }
}

impl<T> IndexMut<usize> for NodeArray<T> {
    #[inline]
    fn index_mut(&mut self, a: usize) -> &mut T {
        if self.values.get(a).is_none() {
            self.not_stored(a);
        }
        &mut self.values[a]
    }
}

impl<T> Index<Range<usize>> for NodeArray<T> {
    type Output = [T];

    /// The values of the consecutive nodes `run`, all stored (a kept array: within the pages
    /// its rank stores).
    fn index(&self, run: Range<usize>) -> &[T] {
        match self.values.as_slice() {
            Some(all) => &all[run],
            None if run.is_empty() => &[],
            None => {
                // Stored slots rise with the ids: a run is stored whole when its ends are and
                // lie as far apart in the storage as in the ids.
                let slots = self.values.slots();
                let (first, last) = (slots.slot(run.start), slots.slot(run.end - 1));
                match (first, last) {
                    (Some(f), Some(l)) if l - f == run.len() - 1 => self.values.run(run),
                    (Some(_), Some(_)) => self.not_stored_run(run),
                    (None, _) => self.not_stored(run.start),
                    (_, None) => self.not_stored(run.end - 1),
                }
            }
        }
    }
}

/// The ranges open at an end read the whole array.
macro_rules! index_whole {
    ($($range:ty),*) => {$(
        impl<T> Index<$range> for NodeArray<T> {
            type Output = [T];

            fn index(&self, range: $range) -> &[T] {
                &self.deref()[range]
            }
        }
    )*};
}
index_whole!(RangeFrom<usize>, RangeTo<usize>, RangeFull);

#[cfg(test)]
mod tests {
    use super::*;
    use std::panic::{catch_unwind, AssertUnwindSafe};

    #[test]
    fn a_kept_array_reads_its_nodes_by_global_id_and_names_any_other() {
        let mut x: NodeArray<f64> = (0..40).map(f64::from).collect::<Vec<_>>().into();
        assert_eq!(x[..3], [0.0, 1.0, 2.0]);
        // Nodes 17..20 live in the third page of eight (16..24).
        x.keep(&NodeSlots::paged(40, std::slice::from_ref(&(17..20))));
        assert!(!x.is_whole());
        assert_eq!(x.len(), 40);
        assert_eq!((x[16], x[19], x[23]), (16.0, 19.0, 23.0));
        assert_eq!(x[17..19], [17.0, 18.0]);
        assert!(catch_unwind(AssertUnwindSafe(|| x[20..25].len())).is_err());
        x[18] = -1.0;
        assert_eq!(x.stored().len(), 8);
        let err = catch_unwind(AssertUnwindSafe(|| x[30])).unwrap_err();
        let message = err.downcast_ref::<String>().unwrap();
        assert!(message.contains("node 30 is not stored here"), "{message}");
        assert!(catch_unwind(AssertUnwindSafe(|| x.iter().count())).is_err());
        let whole: Vec<f64> = (0..40).map(f64::from).collect();
        x.restore(whole.clone());
        assert_eq!(&x[..], &whole[..]);
    }

    #[test]
    fn a_run_over_a_page_not_stored_is_refused() {
        let mut x: NodeArray<f64> = (0..40).map(f64::from).collect::<Vec<_>>().into();
        // Pages 0..8 and 16..24 stored, 8..16 not.
        x.keep(&NodeSlots::paged(40, &[1..2, 17..18]));
        assert_eq!(x[6..8], [6.0, 7.0]);
        assert_eq!(x[16..18], [16.0, 17.0]);
        let err = catch_unwind(AssertUnwindSafe(|| x[5..20].len())).unwrap_err();
        let message = err.downcast_ref::<String>().unwrap();
        assert!(
            message.contains("nodes 5..20 are not all stored"),
            "{message}"
        );
    }

    #[test]
    fn dense_slots_keep_every_node() {
        let mut x: NodeArray<u8> = vec![1, 2, 3].into();
        x.keep(&NodeSlots::dense(3));
        assert!(x.is_whole());
        assert_eq!(&x[..], &[1, 2, 3]);
    }
}
