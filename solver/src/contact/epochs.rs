//! Marks of "computed in this pass" per item that a new pass clears in O(1): an epoch counter and
//! one stamp per item, the item current while its stamp equals the epoch. The contact phase keeps
//! per-face values (facet normals, swept boxes) computed when first asked for in a pass, a few
//! among all the faces of a surface.

/// One stamp per item and the current epoch.
#[derive(Debug, Clone, Default)]
pub struct EpochStamps {
    stamp: Vec<u32>,
    epoch: u32,
}

impl EpochStamps {
    /// Starts a new pass over `len` items: every item becomes stale. Returns whether the number
    /// of items changed, so the caller resizes the values it keeps beside the stamps.
    pub fn next_pass(&mut self, len: usize) -> bool {
        let resized = self.stamp.len() != len;
        if resized {
            self.stamp = vec![0; len];
            self.epoch = 0;
        }
        self.epoch = self.epoch.wrapping_add(1);
        // After 2^32 passes the counter wraps: clear the stamps so none reads as current.
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        resized
    }

    /// Whether item `i` was marked in this pass.
    #[inline]
    pub fn is_current(&self, i: usize) -> bool {
        self.stamp[i] == self.epoch
    }

    /// Marks item `i` as computed in this pass.
    #[inline]
    pub fn mark(&mut self, i: usize) {
        self.stamp[i] = self.epoch;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_pass_makes_every_item_stale() {
        let mut stamps = EpochStamps::default();
        assert!(stamps.next_pass(3));
        assert!(!stamps.is_current(1));
        stamps.mark(1);
        assert!(stamps.is_current(1) && !stamps.is_current(0));
        assert!(!stamps.next_pass(3));
        assert!(!stamps.is_current(1));
        // The wrap of the counter clears the stamps.
        stamps.epoch = u32::MAX;
        stamps.mark(2);
        assert!(!stamps.next_pass(3));
        assert!(!stamps.is_current(2));
    }
}
