//! The collectives of [`Collectives`] (the run's `Communicator`) over MPI (rsmpi, the `mpi`
//! feature), for runs under `mpirun`.

use std::thread::ThreadId;

use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::environment::{Threading, Universe};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;

use super::Communicator as Collectives;

/// `MPI_COMM_WORLD`, used from the thread that initialised MPI only.
///
/// MPI is initialised `MPI_THREAD_FUNNELED`: only that thread may call it. The solver calls the
/// collectives from the thread that steps it, never from its rayon workers, but the type system
/// cannot see that (the solver is `Send`, so its communicator must be `Sync`): every collective
/// checks the calling thread and panics on another one, so no other thread ever reaches MPI.
pub struct MpiWorld {
    world: SimpleCommunicator,
    thread: ThreadId,
}

// SAFETY: the handle is a plain value; every method that passes it to MPI first checks that it
// runs on the thread that initialised MPI (`check_thread`), which MPI_THREAD_FUNNELED allows.
unsafe impl Send for MpiWorld {}
// SAFETY: as for `Send`: MPI is only entered from the initialising thread.
unsafe impl Sync for MpiWorld {}

impl MpiWorld {
    /// Initialises MPI (once per process, on the thread that will run the solver) and returns
    /// the environment, which finalises MPI when dropped (keep it until the end of `main`), and
    /// the world; `None` if MPI was initialised before or the library cannot funnel calls.
    pub fn initialize() -> Option<(Universe, Self)> {
        let (universe, threading) = mpi::initialize_with_threading(Threading::Funneled)?;
        if threading < Threading::Funneled {
            return None;
        }
        let world = Self {
            world: universe.world(),
            thread: std::thread::current().id(),
        };
        Some((universe, world))
    }

    fn check_thread(&self) {
        assert_eq!(
            std::thread::current().id(),
            self.thread,
            "MPI is called from the thread that initialised it only"
        );
    }

    /// Displacements of the parts of sizes `counts`, as MPI counts.
    fn partition(counts: &[usize]) -> (Vec<Count>, Vec<Count>) {
        let to_count = |c: usize| Count::try_from(c).expect("a message under 2^31 values");
        let counts: Vec<Count> = counts.iter().map(|&c| to_count(c)).collect();
        let displs = counts
            .iter()
            .scan(0, |at, &c| {
                let d = *at;
                *at += c;
                Some(d)
            })
            .collect();
        (counts, displs)
    }
}

impl Collectives for MpiWorld {
    fn rank(&self) -> usize {
        self.check_thread();
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.check_thread();
        self.world.size() as usize
    }

    fn all_gather_f64(&self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        self.check_thread();
        let (counts, displs) = Self::partition(counts);
        let mut parts = PartitionMut::new(out, counts, displs);
        self.world.all_gather_varcount_into(mine, &mut parts);
    }

    fn all_gather_f32(&self, mine: &[f32], counts: &[usize], out: &mut [f32]) {
        self.check_thread();
        let (counts, displs) = Self::partition(counts);
        let mut parts = PartitionMut::new(out, counts, displs);
        self.world.all_gather_varcount_into(mine, &mut parts);
    }

    fn all_gather_u32(&self, mine: &[u32], counts: &[usize], out: &mut [u32]) {
        self.check_thread();
        let (counts, displs) = Self::partition(counts);
        let mut parts = PartitionMut::new(out, counts, displs);
        self.world.all_gather_varcount_into(mine, &mut parts);
    }

    fn max_u64(&self, value: u64) -> u64 {
        self.check_thread();
        let mut max = 0u64;
        self.world
            .all_reduce_into(&value, &mut max, SystemOperation::max());
        max
    }
}
