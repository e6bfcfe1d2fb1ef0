//! Ranks as threads of one process: the collectives of [`Communicator`] over shared memory, so the
//! distributed run is tested without an MPI installation.

use std::sync::{Arc, Barrier, Mutex};

use super::Communicator;

/// One rank of a group of threads that play the ranks of a distributed run
/// ([`ThreadGroup::new`]). Each rank's thread calls the collectives in the same order.
#[derive(Debug, Clone)]
pub struct ThreadGroup {
    rank: usize,
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    size: usize,
    barrier: Barrier,
    f64s: Mutex<Vec<Vec<f64>>>,
    f32s: Mutex<Vec<Vec<f32>>>,
    u32s: Mutex<Vec<Vec<u32>>>,
    u64s: Mutex<Vec<u64>>,
}

impl ThreadGroup {
    /// The `size` ranks of a new group, rank `r` at index `r`: hand each to its own thread.
    pub fn new(size: usize) -> Vec<ThreadGroup> {
        let shared = Arc::new(Shared {
            size,
            barrier: Barrier::new(size),
            f64s: Mutex::new(vec![Vec::new(); size]),
            f32s: Mutex::new(vec![Vec::new(); size]),
            u32s: Mutex::new(vec![Vec::new(); size]),
            u64s: Mutex::new(vec![0; size]),
        });
        (0..size)
            .map(|rank| ThreadGroup {
                rank,
                shared: Arc::clone(&shared),
            })
            .collect()
    }

    /// Posts `mine` in `slots`, waits for every rank, concatenates, and waits again so that no
    /// rank posts the next collective's values before all have read these.
    fn gather<T: Copy>(&self, slots: &Mutex<Vec<Vec<T>>>, mine: &[T], out: &mut [T]) {
        {
            let mut s = slots.lock().unwrap_or_else(|e| e.into_inner());
            s[self.rank].clear();
            s[self.rank].extend_from_slice(mine);
        }
        self.shared.barrier.wait();
        {
            let s = slots.lock().unwrap_or_else(|e| e.into_inner());
            let mut at = 0;
            for part in s.iter() {
                out[at..at + part.len()].copy_from_slice(part);
                at += part.len();
            }
            assert_eq!(at, out.len(), "gathered length");
        }
        self.shared.barrier.wait();
    }
}

impl Communicator for ThreadGroup {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_gather_f64(&self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        assert_eq!(
            mine.len(),
            counts[self.rank],
            "rank {} sends its count",
            self.rank
        );
        self.gather(&self.shared.f64s, mine, out);
    }

    fn all_gather_f32(&self, mine: &[f32], counts: &[usize], out: &mut [f32]) {
        assert_eq!(
            mine.len(),
            counts[self.rank],
            "rank {} sends its count",
            self.rank
        );
        self.gather(&self.shared.f32s, mine, out);
    }

    fn all_gather_u32(&self, mine: &[u32], counts: &[usize], out: &mut [u32]) {
        assert_eq!(
            mine.len(),
            counts[self.rank],
            "rank {} sends its count",
            self.rank
        );
        self.gather(&self.shared.u32s, mine, out);
    }

    fn max_u64(&self, value: u64) -> u64 {
        self.shared.u64s.lock().unwrap_or_else(|e| e.into_inner())[self.rank] = value;
        self.shared.barrier.wait();
        let max = self
            .shared
            .u64s
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .iter()
            .copied()
            .max()
            .unwrap_or(value);
        self.shared.barrier.wait();
        max
    }
}
