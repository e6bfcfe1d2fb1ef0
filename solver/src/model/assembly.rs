//! Deterministic, parallel assembly of element forces into nodal forces.
//!
//! The force on every node is the serial left fold `((0 + f_e1) + f_e2) + ...` over its elements
//! in ascending id, whatever the number of threads, so results are bitwise reproducible.
//!
//! Elements are cut into chunks of consecutive ids (never crossing a body, so each chunk has one
//! material); chunks run in parallel, each over its elements in ascending order. A node is *owned*
//! by the chunk that holds its first (lowest) element: that chunk starts the node's fold with
//! `0 + f_e1` and adds all of its own contributions to the node directly. Another chunk may not
//! add to the node before the owner is done, so it writes its contributions to *slots* of a
//! buffer; after the parallel loop each such *shared* node folds its slots, in ascending element
//! order, onto the owner's partial sum. Chunks are ranges of consecutive ids, so the owner's
//! contributions come before every slotted one: the fold is exactly the serial one, for any
//! chunking.
//!
//! The chunking therefore decides only the speed, and it is chosen for the thread count. Every
//! chunk boundary sends the contributions of the nodes around it through the slots (a store and
//! a reload each), and that band is as wide as the element-id bandwidth of the mesh: a whole cell
//! layer of a box mesh: fixed chunks of 2048 elements sent 93 % of the nodes of the benchmark's
//! 480 000-tetrahedron box through the buffer. Hence only [`CHUNKS_PER_THREAD`] chunks per thread, and one
//! chunk per body on one thread, which is a plain serial scatter without slots. The layout is
//! rebuilt, in O(elements), when the thread count changes.
//!
//! Each chunk runs the element loop of its body's material ([`chunk_forces`], compiled per model
//! through `BodyMaterial`). For a material with a history the loop also reads the nodal
//! velocities and commits each element's update to the history. The history of element `e` is
//! written only by the chunk that holds `e`, and the update of an element depends on nothing but
//! its own nodes and history, so this too is race-free and bitwise independent of the chunking.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::element::{element_forces, element_forces_carried, ElementForces};
use super::history::MaterialHistory;
use super::{Connectivity, Model};
use crate::material::{ElementState, Material};
use crate::nodal::{NodeIndexer, NodeView, NodeViewMut};

/// Chunks per thread (on more than one thread). More chunks let rayon move work off a thread that
/// runs slow (a busy core, a preempted vCPU); each extra boundary costs slot traffic. Linear
/// elastic, 480 000 tetrahedra, two threads, ns per element (best, median of 40 steps): 1 chunk
/// per thread 10.5, 13.2; 2: 10.7, 11.0-13.3; 4: 10.9, 11.2; 8: 11.4, 11.7. The medians of 1 and
/// 2 jump to 13 ns whenever one thread runs slow, as it often does on the 2-vCPU test machine.
const CHUNKS_PER_THREAD: usize = 4;
/// Chunks per thread, over each body, in a model with a body whose elements cost more than an
/// elastic one ([`crate::material::Material::relative_cost`]): a material with a history, whose
/// work per element varies with the element's state (microplane concrete: an update on the
/// elastic path, one unloading, one on the Hordijk tail differ by a factor of ten, and the
/// costly ones gather where the load is). Four chunks per thread left a thread idle while the
/// other finished the last chunk: the 2 m/s drop test's internal forces on two threads took
/// 9.0-9.4 s with 4 chunks per thread over the beam and the hammer, 8.7-8.9 s with the beam in
/// 32 chunks and the hammer in two, and 8.1-8.5 s with the hammer in nine as well (`cargo run
/// --release -p impact-solver --example drop_test_cost`, alternating rounds). A chunk boundary's slot traffic is a
/// few microseconds against the milliseconds of such a chunk.
const VARYING_CHUNKS_PER_THREAD: usize = 16;
/// Smallest chunk in such a model, in elastic elements: a body of relative cost `c` has chunks of
/// at least `VARYING_MIN_CHUNK / c` elements.
const VARYING_MIN_CHUNK: f64 = 512.0;
/// Smallest chunk worth a task of its own where every element costs about the same.
const MIN_CHUNK: usize = 4096;
/// `first_element` of a node that belongs to no element.
pub(crate) const NO_ELEMENT: u32 = u32::MAX;

/// Assembles element forces into nodal forces in parallel with a result bitwise independent of
/// the thread count (module doc): node ownership by first element, and the chunk layout for the
/// thread count last used.
#[derive(Debug)]
pub struct ForceAssembler {
    /// Lowest element id of each node (`NO_ELEMENT` if none): the chunk holding it owns the node.
    first_element: Vec<u32>,
    /// Nodes without elements, whose force is zero.
    orphans: Vec<u32>,
    /// Chunks and slots for the thread count last used, with the slot buffer reused from step to
    /// step.
    layout: Mutex<Layout>,
}

#[derive(Debug)]
struct Chunk {
    body: usize,
    elements: Range<usize>,
    /// The chunk's slotted contributions, in the order of its element loop (element, then
    /// corner).
    slots: Range<usize>,
}

#[derive(Debug)]
struct Layout {
    /// Thread count the layout was built for.
    threads: usize,
    /// The elements assembled: all of them, or one rank's range in a distributed run
    /// (`crate::distributed`).
    range: Range<usize>,
    chunks: Vec<Chunk>,
    /// Nodes that receive slotted contributions.
    shared_nodes: Vec<u32>,
    /// Slots of shared node `i`, in ascending element order, are
    /// `shared_slots[shared_offsets[i]..shared_offsets[i + 1]]`.
    shared_offsets: Vec<u32>,
    shared_slots: Vec<u32>,
    /// Slots of the nodes whose first element lies before `range` (in a lower rank's range),
    /// by node and then element: not folded here but handed to the other ranks
    /// ([`ForceAssembler::append_foreign_contributions`]).
    foreign_slots: Vec<u32>,
    buffer: Vec<Vector3<f64>>,
}

/// A raw pointer that may cross threads: every index written through it is written by exactly one
/// chunk (a node by its owner chunk, a slot by its element, an element's history by the chunk
/// that holds the element), so the writes never race.
struct DisjointWrites<T>(*mut T);
impl<T> Clone for DisjointWrites<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for DisjointWrites<T> {}
unsafe impl<T> Send for DisjointWrites<T> {}
unsafe impl<T> Sync for DisjointWrites<T> {}

/// What the assembly needs for materials with history: the nodal velocities of the half step
/// before, the time step and the history it advances.
pub(super) struct Stateful<'a> {
    pub v: NodeView<'a, Vector3<f64>>,
    pub dt: f64,
    pub history: &'a mut MaterialHistory,
}

/// Where the chunks of one body write its history: the values of its elements one after the
/// other, `len` each, and their Cauchy stresses.
#[derive(Clone, Copy)]
struct HistoryWrites {
    values: DisjointWrites<f32>,
    len: usize,
    cauchy: DisjointWrites<[f64; 6]>,
    /// The body's local ids of the elements whose history is held (a rank's own part),
    /// `held.0..held.1`.
    held: (usize, usize),
}

/// Adds the force `fa` of element `e` (in the chunk over `elements`) on the node whose first
/// element is `first`, stored at `at` behind `nodal`: directly when the chunk owns the node, else
/// to the chunk's next slot.
///
/// # Safety
/// `at` lies inside the storage `nodal` points into, and the slots `next_slot..slots_end` of the
/// buffer behind `slot_out` belong to this chunk alone; `first_element` is that of the model's
/// elements, so that exactly one chunk owns each node.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn scatter(
    elements: &Range<usize>,
    e: usize,
    first: u32,
    fa: Vector3<f64>,
    nodal: DisjointWrites<Vector3<f64>>,
    at: usize,
    slot_out: DisjointWrites<Vector3<f64>>,
    next_slot: &mut usize,
    slots_end: usize,
) {
    debug_assert!(first as usize <= e, "first elements out of date");
    if owns(elements, first) {
        // SAFETY: only the chunk holding `first` writes node `n` (see the caller's contract).
        unsafe {
            let node = nodal.0.add(at);
            // The owner starts the fold at the node's first element.
            let sum = if first as usize == e {
                Vector3::zeros()
            } else {
                *node
            };
            *node = sum + fa;
        }
    } else {
        assert!(*next_slot < slots_end, "slot layout out of date");
        // SAFETY: the slots of this chunk lie inside the buffer and belong to it alone.
        unsafe { *slot_out.0.add(*next_slot) = fa };
        *next_slot += 1;
    }
}

/// The lowest element of each of `node_count` nodes (`NO_ELEMENT` for a node without one): the
/// element whose contribution starts the node's fold.
pub(crate) fn first_elements(tets: &[[u32; 4]], node_count: usize) -> Vec<u32> {
    let mut first_element = vec![NO_ELEMENT; node_count];
    for (e, tet) in tets.iter().enumerate().rev() {
        for &n in tet {
            first_element[n as usize] = e as u32;
        }
    }
    first_element
}

/// Whether the chunk over `elements`, visiting an element of a node whose first element is
/// `first`, owns that node. The visited element is at least `first` and lies in the chunk, so
/// `first >= start` means that the chunk holds `first`; exactly one chunk does. The element loop
/// and the slot layout both decide with this function, so that they agree. (The full
/// `elements.contains(&first)` made the linear-elastic loop 1.5 ns per element slower.)
#[inline(always)]
fn owns(elements: &Range<usize>, first: u32) -> bool {
    first as usize >= elements.start
}

impl ForceAssembler {
    /// Prepares the assembly of the elements `tets` over `node_count` nodes, with the elements of
    /// each body in `bodies`, for the current rayon thread count; every element costs what an
    /// elastic one does (see [`Self::with_costs`]).
    pub fn new(tets: &Connectivity, node_count: usize, bodies: &[Range<usize>]) -> Self {
        Self::with_costs(tets, node_count, bodies, &vec![1.0; bodies.len()])
    }

    /// [`Self::new`] with each body's cost per element relative to an elastic element
    /// ([`crate::material::Material::relative_cost`]), which sets how finely its elements are cut
    /// into chunks (16 per thread over each body where a body is costlier than elastic).
    pub fn with_costs(
        tets: &Connectivity,
        node_count: usize,
        bodies: &[Range<usize>],
        costs: &[f64],
    ) -> Self {
        assert!(
            tets.len() < NO_ELEMENT as usize,
            "element ids must fit in u32"
        );
        let first_element = first_elements(tets, node_count);
        let orphans = (0..node_count as u32)
            .filter(|&n| first_element[n as usize] == NO_ELEMENT)
            .collect();
        let bodies: Vec<BodyElements> = bodies
            .iter()
            .zip(costs)
            .map(|(elements, &cost)| BodyElements {
                elements: elements.clone(),
                cost,
            })
            .collect();
        let layout = Layout::for_threads(
            &first_element,
            tets,
            &bodies,
            rayon::current_num_threads(),
            0..tets.len(),
        );
        Self {
            first_element,
            orphans,
            layout: Mutex::new(layout),
        }
    }

    /// Bytes the assembler holds on the heap (ownership arrays, chunk layout, slot buffer), for
    /// the memory report.
    pub fn heap_bytes(&self) -> usize {
        let layout = self.layout.lock().unwrap_or_else(|e| e.into_inner());
        4 * (self.first_element.len() + self.orphans.len())
            + layout.chunks.len() * std::mem::size_of::<Chunk>()
            + 4 * (layout.shared_nodes.len()
                + layout.shared_offsets.len()
                + layout.shared_slots.len()
                + layout.foreign_slots.len())
            + std::mem::size_of::<Vector3<f64>>() * layout.buffer.len()
    }

    /// Fraction of nodes whose force goes partly through the slot buffer, for the chunking of the
    /// thread count last used (at first, the one current at construction).
    pub fn shared_fraction(&self, node_count: usize) -> f64 {
        let layout = self.layout.lock().unwrap_or_else(|e| e.into_inner());
        layout.shared_nodes.len() as f64 / node_count.max(1) as f64
    }

    /// Assembles only the elements of `range` from now on (one rank's elements in a distributed
    /// run, `crate::distributed`): the nodes whose first element lies in `range` get the fold of
    /// its contributions, the nodes of lower ranks' elements none (their contributions are
    /// [`Self::append_foreign_contributions`]), the other nodes are left as they were.
    pub fn restrict_to(&self, model: &Model, range: Range<usize>) {
        let mut layout = self.layout.lock().unwrap_or_else(|e| e.into_inner());
        let bodies = BodyElements::of(model);
        let threads = layout.threads;
        *layout = Layout::for_threads(&self.first_element, &model.tets, &bodies, threads, range);
    }

    /// Appends to `out` the contributions of the last assembly to nodes whose first element
    /// precedes the assembled range, node by node in ascending order and for each in ascending
    /// element order, three components each: straight into the message a rank sends, with no
    /// copy of its own.
    pub fn append_foreign_contributions(&self, out: &mut Vec<f64>) {
        let layout = self.layout.lock().unwrap_or_else(|e| e.into_inner());
        for &s in &layout.foreign_slots {
            out.extend(layout.buffer[s as usize].iter());
        }
    }

    /// Internal forces at `u` into `f`, with the velocities, time step and history the materials
    /// with a history need (`stateful`; a model without such materials may pass `None`). Returns
    /// the lowest inverted element, if any. `u` and `f` store the same nodes alike.
    pub(super) fn assemble(
        &self,
        model: &Model,
        u: NodeView<'_, Vector3<f64>>,
        stateful: Option<Stateful<'_>>,
        f: NodeViewMut<'_, Vector3<f64>>,
    ) -> Option<usize> {
        let mut layout = self.layout.lock().unwrap_or_else(|e| e.into_inner());
        let threads = rayon::current_num_threads();
        if layout.threads != threads {
            let bodies = BodyElements::of(model);
            let range = layout.range.clone();
            *layout =
                Layout::for_threads(&self.first_element, &model.tets, &bodies, threads, range);
        }
        self.assemble_with(&mut layout, model, u, stateful, f)
    }

    fn assemble_with(
        &self,
        layout: &mut Layout,
        model: &Model,
        u: NodeView<'_, Vector3<f64>>,
        stateful: Option<Stateful<'_>>,
        mut f: NodeViewMut<'_, Vector3<f64>>,
    ) -> Option<usize> {
        // Every write below goes to a node whose displacement was read at the same position.
        assert!(u.indexer().same_as(&f.indexer()), "u and f stored alike");
        assert_eq!(u.storage().len(), f.storage_mut().len());
        for &n in &self.orphans {
            f[n as usize] = Vector3::zeros();
        }
        let inverted = AtomicUsize::new(usize::MAX);
        let indexer = f.indexer();
        let nodal = DisjointWrites(f.storage_mut().as_mut_ptr());
        let slot_out = DisjointWrites(layout.buffer.as_mut_ptr());
        let first_element = &self.first_element[..];
        let (velocity, dt, histories): (
            NodeView<'_, Vector3<f64>>,
            f64,
            Vec<Option<HistoryWrites>>,
        ) = match stateful {
            Some(s) => {
                let writes = s
                    .history
                    .bodies
                    .iter_mut()
                    .zip(&model.bodies)
                    .map(|(h, body)| {
                        h.as_mut().map(|h| {
                            assert_eq!(h.values.len(), h.state_len * h.cauchy.len());
                            assert!(h.held().end <= body.elements.len());
                            HistoryWrites {
                                values: DisjointWrites(h.values.as_mut_ptr()),
                                len: h.state_len,
                                cauchy: DisjointWrites(h.cauchy.as_mut_ptr()),
                                held: (h.held().start, h.held().end),
                            }
                        })
                    })
                    .collect();
                // The velocities are read at the displacements' positions.
                assert!(s.v.indexer().same_as(&u.indexer()), "u and v stored alike");
                assert_eq!(s.v.storage().len(), u.storage().len());
                (s.v, s.dt, writes)
            }
            None => (NodeView::from(&[][..]), 0.0, Vec::new()),
        };
        layout.chunks.par_iter().for_each(|chunk| {
            let body = &model.bodies[chunk.body];
            let job = ChunkJob {
                model,
                u,
                velocity,
                dt,
                elements: chunk.elements.clone(),
                body_start: body.elements.start,
                first_element,
                indexer,
                nodal,
                slot_out,
                slots: chunk.slots.clone(),
                history: histories.get(chunk.body).copied().flatten(),
            };
            let first_inverted = body.material.assemble_chunk(&job);
            if first_inverted != usize::MAX {
                inverted.fetch_min(first_inverted, Ordering::Relaxed);
            }
        });
        let buffer = &layout.buffer;
        let (offsets, slots) = (&layout.shared_offsets, &layout.shared_slots);
        layout
            .shared_nodes
            .par_iter()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, &n)| {
                // The whole wrapper, as above (a closure would capture only its pointer field).
                #[allow(clippy::redundant_locals)]
                let nodal = nodal;
                let range = offsets[i] as usize..offsets[i + 1] as usize;
                // SAFETY: `n` is stored in `f` (an element of this range wrote it), each shared
                // node appears once in `shared_nodes`, and the element loop that also wrote it
                // has finished.
                unsafe {
                    let node = nodal.0.add(indexer.slot(n as usize));
                    *node = slots[range]
                        .iter()
                        .fold(*node, |acc, &s| acc + buffer[s as usize]);
                }
            });
        match inverted.into_inner() {
            usize::MAX => None,
            e => Some(e),
        }
    }
}

/// One chunk of the assembly, as its material's element loop sees it.
pub struct ChunkJob<'a> {
    model: &'a Model,
    u: NodeView<'a, Vector3<f64>>,
    /// Nodal velocities of the half step before (empty without materials with a history).
    velocity: NodeView<'a, Vector3<f64>>,
    dt: f64,
    elements: Range<usize>,
    /// Global id of the first element of the chunk's body.
    body_start: usize,
    first_element: &'a [u32],
    /// Where each node's force lies behind `nodal`.
    indexer: NodeIndexer<'a>,
    nodal: DisjointWrites<Vector3<f64>>,
    slot_out: DisjointWrites<Vector3<f64>>,
    slots: Range<usize>,
    /// Where the chunk writes the histories of its elements, for a material with a history.
    history: Option<HistoryWrites>,
}

// SAFETY: the raw pointers of a job are written only as `DisjointWrites` allows.
unsafe impl Send for ChunkJob<'_> {}
unsafe impl Sync for ChunkJob<'_> {}

/// The element loop of one chunk for the material `M` of its body: each element's forces from
/// [`element_forces`], its history committed in place, the forces scattered to the nodes the
/// chunk owns or to its slots. Returns the lowest inverted element (`usize::MAX` if none).
///
/// The branches on a carried deformation (a remeshed model, [`super::CarriedState`]) and on the
/// storage of the nodal values (every node at its id, or a rank's pages) are taken once per
/// chunk: a model that was never remeshed, on one process, runs the same loop as before, bit for
/// bit, and at its speed (a page lookup per node read cost the elastic drop test 5 % of its
/// internal forces).
#[inline]
pub(super) fn chunk_forces<M: Material>(material: &M, job: &ChunkJob<'_>) -> usize {
    if job.indexer.is_dense() {
        chunk_forces_on(material, job, AtId)
    } else {
        chunk_forces_on(material, job, job.indexer)
    }
}

/// Where a node's value lies in the chunk's nodal storage.
trait NodeSlot: Copy {
    fn at(self, a: usize) -> usize;
}

/// Every node at its own id (one process).
#[derive(Clone, Copy)]
struct AtId;

impl NodeSlot for AtId {
    #[inline(always)]
    fn at(self, a: usize) -> usize {
        a
    }
}

impl NodeSlot for NodeIndexer<'_> {
    #[inline(always)]
    fn at(self, a: usize) -> usize {
        self.slot(a)
    }
}

#[inline(always)]
fn chunk_forces_on<M: Material, S: NodeSlot>(material: &M, job: &ChunkJob<'_>, slots: S) -> usize {
    match &job.model.carried {
        None => chunk_loop(
            material,
            job,
            slots,
            |local, _, grad_n, volume, ue, rate, state| {
                element_forces(material, local, grad_n, volume, ue, rate, state)
            },
        ),
        Some(c) => chunk_loop(
            material,
            job,
            slots,
            |local, e, grad_n, volume, ue, rate, state| {
                let carried = (&c.deformation[e], &c.pull_back[e]);
                element_forces_carried(material, local, grad_n, volume, ue, rate, state, carried)
            },
        ),
    }
}

/// The element loop of [`chunk_forces`], with the element kernel `kernel(local id, global id,
/// gradients, volume, displacements, rate, state)`, each node's values at `slots.at(node)` of
/// the storage of `u`, of the velocities and of the forces (stored alike).
#[inline(always)]
fn chunk_loop<M, S, K>(material: &M, job: &ChunkJob<'_>, slots: S, kernel: K) -> usize
where
    M: Material,
    S: NodeSlot,
    K: Fn(
        usize,
        usize,
        &[Vector3<f64>; 4],
        f64,
        &[Vector3<f64>; 4],
        Option<(&[Vector3<f64>; 4], f64)>,
        ElementState<'_>,
    ) -> ElementForces,
{
    // Locals, so that the loop reads them from registers.
    let (model, first_element) = (job.model, job.first_element);
    let (u, velocity) = (job.u.storage(), job.velocity.storage());
    let (nodal, slot_out, dt) = (job.nodal, job.slot_out, job.dt);
    let range = job.elements.clone();
    let mut next_slot = job.slots.start;
    let mut first_inverted = usize::MAX;
    let len = material.history_len();
    let writes = match job.history {
        Some(w) if len > 0 => {
            assert_eq!(w.len, len, "history of another material");
            // Every element of the chunk must be held: the pointer offsets below rely on it.
            let local = range.start - job.body_start..range.end - job.body_start;
            assert!(
                local.is_empty() || (w.held.0 <= local.start && local.end <= w.held.1),
                "elements {local:?} outside the held history {:?}",
                w.held
            );
            Some(w)
        }
        _ => {
            assert!(len == 0, "a history for every material that keeps one");
            None
        }
    };
    let elements = model.tets[range.clone()]
        .iter()
        .zip(model.kept_grad_n(range.clone()))
        .zip(model.kept_volumes(range.clone()));
    // The corner displacements and velocities of each element are written into these in
    // place: `tet.map` built each array elsewhere and moved it with loads that straddled its
    // 24-byte stores, which store forwarding cannot serve (perf: an eighth of this loop's
    // samples on the static beam).
    let mut ue = [Vector3::zeros(); 4];
    let mut ve = [Vector3::zeros(); 4];
    for (e, ((tet, grad_n), &volume)) in range.clone().zip(elements) {
        // Where each corner's values lie, looked up once for the reads and the scatter.
        let at = [0, 1, 2, 3].map(|c| slots.at(tet[c] as usize));
        for (corner, &s) in ue.iter_mut().zip(&at) {
            *corner = u[s];
        }
        let local = e - job.body_start;
        let rate = if material.reads_rate() {
            for (corner, &s) in ve.iter_mut().zip(&at) {
                *corner = velocity[s];
            }
            Some((&ve, dt))
        } else {
            None
        };
        let state = match writes {
            // SAFETY: the body's history holds `len` values and one stress per held element
            // (asserted in `assemble_with`), `local` is a held element of the body (asserted
            // for the chunk above), and only the chunk holding element `e` touches its values
            // and its stress; the history outlives the loop.
            Some(w) => unsafe {
                let at = local - w.held.0;
                ElementState {
                    history: std::slice::from_raw_parts_mut(w.values.0.add(at * len), len),
                    cauchy: Some(&mut *w.cauchy.0.add(at)),
                }
            },
            None => ElementState::stateless(),
        };
        let update = kernel(local, e, grad_n, volume, &ue, rate, state);
        if !(update.det > 0.0) {
            first_inverted = first_inverted.min(e);
        }
        for ((&n, &s), fa) in tet.iter().zip(&at).zip(update.forces) {
            // SAFETY: `n` is stored in `f` (it indexed `u` above, and `u` and `f` are stored
            // alike).
            // `first_element` was computed from the same `model.tets` (the model never changes
            // its elements), so `first <= e` and only the chunk holding `first` writes node `n`:
            // no other thread touches it during this loop. The chunk's slots are its own. `f`
            // and the buffer outlive the loop.
            unsafe {
                scatter(
                    &range,
                    e,
                    first_element[n as usize],
                    fa,
                    nodal,
                    s,
                    slot_out,
                    &mut next_slot,
                    job.slots.end,
                )
            };
        }
    }
    first_inverted
}

/// A body's elements and their cost relative to an elastic element, which set its chunks.
#[derive(Debug, Clone)]
struct BodyElements {
    elements: Range<usize>,
    cost: f64,
}

impl BodyElements {
    /// The bodies of `model` with the relative costs of their materials.
    fn of(model: &Model) -> Vec<Self> {
        model
            .bodies
            .iter()
            .map(|b| Self {
                elements: b.elements.clone(),
                cost: b.material.relative_cost(),
            })
            .collect()
    }
}

impl Layout {
    /// The layout for `threads` threads: about `CHUNKS_PER_THREAD` chunks per thread where every
    /// element costs what an elastic one does, `VARYING_CHUNKS_PER_THREAD` over each body of a
    /// model with a costlier body, and one chunk per body on a single thread, which has nobody
    /// to share work with.
    fn for_threads(
        first_element: &[u32],
        tets: &Connectivity,
        bodies: &[BodyElements],
        threads: usize,
        range: Range<usize>,
    ) -> Self {
        // Each body's part of the assembled range (empty for a body outside it).
        let parts: Vec<Range<usize>> = bodies
            .iter()
            .map(|b| {
                let b = &b.elements;
                b.start.clamp(range.start, range.end)..b.end.clamp(range.start, range.end)
            })
            .collect();
        let total: usize = parts.iter().map(|b| b.len()).sum();
        let lengths: Vec<usize> = if threads <= 1 {
            vec![total; parts.len()]
        } else if bodies.iter().any(|b| b.cost > 1.0) {
            parts
                .iter()
                .zip(bodies)
                .map(|(part, body)| {
                    let smallest = (VARYING_MIN_CHUNK / body.cost.max(1.0)).ceil() as usize;
                    part.len()
                        .div_ceil(VARYING_CHUNKS_PER_THREAD * threads)
                        .max(smallest)
                })
                .collect()
        } else {
            let length = total.div_ceil(CHUNKS_PER_THREAD * threads).max(MIN_CHUNK);
            vec![length; parts.len()]
        };
        Self {
            threads,
            ..Self::with_chunk_lengths(first_element, tets, &parts, &lengths, range)
        }
    }

    /// Chunks of at most `lengths[b]` elements in body `b`, equal within each body, and their
    /// slots; `bodies` are the bodies' parts of `range`, the elements assembled.
    fn with_chunk_lengths(
        first_element: &[u32],
        tets: &Connectivity,
        bodies: &[Range<usize>],
        lengths: &[usize],
        assembled: Range<usize>,
    ) -> Self {
        let mut chunks = Vec::new();
        // Slotted contributions `(node, slot)`, with slots numbered in ascending element order.
        let mut slotted = Vec::new();
        for (body, (range, &length)) in bodies.iter().zip(lengths).enumerate() {
            if range.is_empty() {
                continue;
            }
            // Equal chunks, so that the threads get equal work.
            let count = range.len().div_ceil(length.max(1)).max(1);
            for k in 0..count {
                let elements = range.start + k * range.len() / count
                    ..range.start + (k + 1) * range.len() / count;
                let first_slot = slotted.len();
                for tet in &tets[elements.clone()] {
                    for &n in tet {
                        if !owns(&elements, first_element[n as usize]) {
                            slotted.push((n, slotted.len() as u32));
                        }
                    }
                }
                chunks.push(Chunk {
                    body,
                    elements,
                    slots: first_slot..slotted.len(),
                });
            }
        }
        let buffer = vec![Vector3::zeros(); slotted.len()];
        // Group by node; sorting by (node, slot) keeps each node's slots in element order.
        slotted.sort_unstable();
        // Nodes of lower ranks' elements come first (their ids need not be lower, so split).
        let (foreign, shared): (Vec<_>, Vec<_>) = slotted
            .into_iter()
            .partition(|&(n, _)| (first_element[n as usize] as usize) < assembled.start);
        let group = |slotted: Vec<(u32, u32)>| {
            let mut nodes = Vec::new();
            let mut offsets = vec![0];
            for (i, &(n, _)) in slotted.iter().enumerate() {
                if slotted.get(i + 1).is_none_or(|next| next.0 != n) {
                    nodes.push(n);
                    offsets.push(i as u32 + 1);
                }
            }
            let slots = slotted.into_iter().map(|(_, slot)| slot).collect();
            (nodes, offsets, slots)
        };
        let (shared_nodes, shared_offsets, shared_slots) = group(shared);
        Self {
            threads: 0,
            range: assembled,
            chunks,
            shared_nodes,
            shared_offsets,
            shared_slots,
            foreign_slots: foreign.into_iter().map(|(_, slot)| slot).collect(),
            buffer,
        }
    }
}

#[cfg(test)]
mod tests;
