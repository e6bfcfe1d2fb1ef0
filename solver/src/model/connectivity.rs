//! The elements' corner nodes, indexed by global element id: every element's on one process, one
//! rank's own elements only once a distributed run has planned its exchange
//! ([`Connectivity::keep_range`]), and every element's again after the run
//! ([`Connectivity::restore`], gathered from the ranks).

use std::ops::{Deref, DerefMut, Index, Range};

/// Global connectivity: element `e`'s four node ids at `self[e]`.
///
/// Whole, it reads as a slice (`iter`, `&tets[..]`, passing `&model.tets` where a slice is
/// asked). Kept to a range, it holds and indexes the elements of that range only, by their
/// global ids; reading it as a whole slice, or an element outside the range, panics with the
/// element named, since a rank that read another rank's element would compute with nodes it
/// does not integrate.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Connectivity {
    /// Global id of `stored[0]`.
    first: usize,
    /// Number of elements of the whole model.
    count: usize,
    stored: Vec<[u32; 4]>,
}

impl From<Vec<[u32; 4]>> for Connectivity {
    fn from(tets: Vec<[u32; 4]>) -> Self {
        Self {
            first: 0,
            count: tets.len(),
            stored: tets,
        }
    }
}

impl Connectivity {
    /// Number of elements of the whole model, stored or not.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the model has no element.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether every element is stored.
    pub fn is_whole(&self) -> bool {
        self.stored.len() == self.count
    }

    /// The global ids of the stored elements.
    pub fn stored_range(&self) -> Range<usize> {
        self.first..self.first + self.stored.len()
    }

    /// The stored elements, `stored()[i]` being element `stored_range().start + i`.
    pub fn stored(&self) -> &[[u32; 4]] {
        &self.stored
    }

    /// Keeps the elements of `range` only (a rank's own, once its plan is made) and frees the
    /// others; a whole range keeps all.
    pub fn keep_range(&mut self, range: Range<usize>) {
        assert!(
            self.is_whole() && range.end <= self.count && range.start <= range.end,
            "keep elements {range:?} of a whole connectivity of {} elements",
            self.count
        );
        if range.len() == self.count {
            return;
        }
        // In place: the whole connectivity is the largest array of a rank's setup, and a copy
        // of the part beside it would raise the rank's peak by the part (a large block's
        // shrinking realloc returns its tail without a copy).
        self.stored.truncate(range.end);
        self.stored.drain(..range.start);
        self.stored.shrink_to_fit();
        self.first = range.start;
    }

    /// Every element again (`whole`, gathered from the ranks that kept ranges of it).
    pub fn restore(&mut self, whole: Vec<[u32; 4]>) {
        assert_eq!(whole.len(), self.count, "a whole connectivity restored");
        self.stored = whole;
        self.first = 0;
    }

    fn local(&self, e: usize) -> usize {
        match e.checked_sub(self.first) {
            Some(i) if i < self.stored.len() => i,
            _ => self.not_stored(e),
        }
    }

    #[cold]
    #[inline(never)]
    fn not_stored(&self, e: usize) -> ! {
        panic!(
            "element {e} is not stored here (elements {:?} of {})",
            self.stored_range(),
            self.count
        )
    }
}

impl Index<usize> for Connectivity {
    type Output = [u32; 4];

    /// As a vector's index, with one subtraction more (an element before the stored range
    /// wraps around past its end).
    #[inline]
    fn index(&self, e: usize) -> &[u32; 4] {
        match self.stored.get(e.wrapping_sub(self.first)) {
            Some(tet) => tet,
            None => self.not_stored(e),
        }
    }
}

impl Index<Range<usize>> for Connectivity {
    type Output = [[u32; 4]];

    fn index(&self, range: Range<usize>) -> &[[u32; 4]] {
        if range.is_empty() {
            return &[];
        }
        let start = self.local(range.start);
        let end = self.local(range.end - 1) + 1;
        &self.stored[start..end]
    }
}

impl Deref for Connectivity {
    type Target = [[u32; 4]];

    fn deref(&self) -> &[[u32; 4]] {
        assert!(
            self.is_whole(),
            "the whole connectivity is read where only elements {:?} of {} are stored",
            self.stored_range(),
            self.count
        );
        &self.stored
    }
}

impl<'a> IntoIterator for &'a Connectivity {
    type Item = &'a [u32; 4];
    type IntoIter = std::slice::Iter<'a, [u32; 4]>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl DerefMut for Connectivity {
    fn deref_mut(&mut self) -> &mut [[u32; 4]] {
        assert!(
            self.is_whole(),
            "the whole connectivity is written where part is stored"
        );
        &mut self.stored
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tets(n: u32) -> Vec<[u32; 4]> {
        (0..n).map(|e| [e, e + 1, e + 2, e + 3]).collect()
    }

    #[test]
    fn a_kept_range_indexes_by_global_id() {
        let mut c = Connectivity::from(tets(10));
        c.keep_range(3..7);
        assert_eq!(c.len(), 10);
        assert!(!c.is_whole());
        assert_eq!(c[3], [3, 4, 5, 6]);
        assert_eq!(c[6], [6, 7, 8, 9]);
        assert_eq!(&c[4..6], &tets(10)[4..6]);
    }

    #[test]
    #[should_panic(expected = "element 7 is not stored here")]
    fn an_element_outside_the_kept_range_panics() {
        let mut c = Connectivity::from(tets(10));
        c.keep_range(3..7);
        let _ = c[7];
    }

    #[test]
    #[should_panic(expected = "the whole connectivity is read")]
    fn a_kept_range_is_not_a_whole_slice() {
        let mut c = Connectivity::from(tets(10));
        c.keep_range(0..5);
        let _ = c.iter().count();
    }
}
