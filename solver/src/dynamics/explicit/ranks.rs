//! The explicit run over several ranks (`crate::distributed`): each rank computes the forces of
//! its elements and integrates their nodes; the nodes two ranks share, the contact surfaces and
//! the probed and prescribed nodes are completed and integrated on every rank alike.

use std::borrow::Cow;
use std::ops::Range;

use nalgebra::Vector3;

use super::contact_phase::ContactScratch;
use super::ExplicitSolver;
use super::{ExplicitSettings, OutputSettings};
use crate::distributed::{element_ranges_by_cost, Communicator, ForceExchange, NodePlan};
use crate::error::{Result, SolverError};
use crate::model::{body_of, body_part, Body, MaterialHistory, Model, NodeArray, ELEMENT_LEAF};
use crate::nodal::{NodeField, NodeSlots};
use crate::problem::Problem;

/// Why a field of a run on one process has a slice: it stores every node at its id.
const ONE_PROCESS: &str = "one process stores every node";

/// The element ranges of `size` ranks over `model` ([`element_ranges_by_cost`], by the
/// materials' relative cost): those of [`ExplicitSolver::new_rank`].
fn rank_ranges(model: &Model, size: usize) -> Vec<Range<usize>> {
    rank_ranges_of(&model.bodies, size)
}

/// The element ranges of `size` ranks over the elements of `bodies`, by the materials' relative
/// cost: the ranges the solver distributes, computed before the model exists while it is built
/// for one rank (`Model::with_regions_keeping`).
pub fn rank_ranges_of(bodies: &[Body], size: usize) -> Vec<Range<usize>> {
    let cost: Vec<f64> = bodies.iter().map(|b| b.material.relative_cost()).collect();
    let elements = bodies.last().map_or(0, |b| b.elements.end);
    element_ranges_by_cost(elements, size, |e| cost[body_of(bodies, e)])
}

/// Gives `model` the per-element data of this rank's elements only, kept from what it holds or
/// computed ([`Model::keep_or_compute_element_data`]), when `comm` runs more than one rank and
/// the run can be distributed: before a solver that shares the problem is built
/// ([`ExplicitSolver::new_rank`]), so that the whole model's data is freed before the rank
/// allocates its history. [`ExplicitSolver::new_rank_keeping_own_elements`] does it itself.
pub fn keep_rank_element_data(model: &mut Model, comm: Option<&dyn Communicator>) {
    if let Some(comm) = comm.filter(|c| c.size() > 1 && model.carried.is_none()) {
        let mine = rank_ranges(model, comm.size())[comm.rank()].clone();
        model.keep_or_compute_element_data(mine);
    }
}

/// The part of `history` that holds the elements of `elements` (global ids) only: a copy of
/// that part where `history` holds more, `history` itself where it holds exactly that.
fn history_part(
    model: &Model,
    history: MaterialHistory,
    elements: &Range<usize>,
) -> MaterialHistory {
    let bodies = model
        .bodies
        .iter()
        .zip(history.bodies)
        .map(|(body, h)| {
            h.map(|h| {
                let part = body_part(&body.elements, elements);
                if h.held() == part {
                    return h;
                }
                h.part(part)
            })
        })
        .collect();
    MaterialHistory { bodies }
}

/// A rank's part of a distributed run.
pub(super) struct RankShare<'p> {
    comm: &'p dyn Communicator,
    ranges: Vec<Range<usize>>,
    exchange: ForceExchange,
}

impl<'p> RankShare<'p> {
    /// The ranks' collectives.
    pub(super) fn comm(&self) -> &'p dyn Communicator {
        self.comm
    }

    /// This rank's elements.
    pub(super) fn own_elements(&self) -> Range<usize> {
        self.ranges[self.comm.rank()].clone()
    }
}

/// Rank `comm.rank()`'s part of a distributed run on `problem` (`comm.size() > 1`): the nodes it
/// integrates ([`NodePlan`]) and its share (element ranges by the materials' relative cost,
/// [`element_ranges_by_cost`], and the force exchange), with the part of `history` that holds
/// its elements. It then computes the forces and advances the history of its elements only,
/// completes the forces of the shared nodes with the other ranks and integrates its nodes; the
/// other ranks make the same call on the same problem. A run that remeshes cannot be
/// distributed.
pub(super) fn rank_share<'p>(
    problem: &Problem,
    contact: Option<&ContactScratch>,
    history: MaterialHistory,
    comm: &'p dyn Communicator,
) -> Result<(NodePlan, RankShare<'p>, MaterialHistory)> {
    let model = &problem.model;
    if model.carried.is_some() {
        return Err(SolverError::InvalidScene {
            entity: "analysis.explicit.remeshing".into(),
            message: "a run that remeshes runs on one rank (no mpirun)".into(),
        });
    }
    let ranges = rank_ranges(model, comm.size());
    let mine = ranges[comm.rank()].clone();
    model.restrict_assembly(mine.clone());
    let history = history_part(model, history, &mine);
    // Every rank integrates what contact reads and moves and the probes' nodes; the
    // conditions' nodes only where used, their reactions gathered for the history rows.
    let mut replicated = contact.map(|c| c.replicated_nodes()).unwrap_or_default();
    for probe in &problem.probes {
        replicated.extend(&probe.nodes);
    }
    let nodes = NodePlan::new(
        &model.tets,
        model.node_count(),
        &ranges,
        comm.rank(),
        &replicated,
    );
    let exchange = ForceExchange::new(
        &model.tets,
        model.node_count(),
        &ranges,
        comm.rank(),
        nodes.exchanged(),
        nodes.active(),
    );
    let share = RankShare {
        comm,
        ranges,
        exchange,
    };
    Ok((nodes, share, history))
}

impl<'p> ExplicitSolver<'p> {
    /// [`Self::new`] as rank `comm.rank()` of `comm.size()`: from the first step
    /// on it computes the forces and advances the history of its elements only, completes the
    /// forces of the shared nodes with the other ranks and integrates its nodes, allocating the
    /// material history of its own elements and the nodal values of its own nodes only, never
    /// the whole model's. The other ranks must make the same call on the same problem. One rank
    /// is [`Self::new`].
    pub fn new_rank(
        problem: &'p Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
        comm: &'p dyn Communicator,
    ) -> Result<Self> {
        Self::rank_of(Lent::Shared(problem), settings, output, comm)
    }

    /// [`Self::new_rank`] that also frees, once the rank's plan is made, what the run never
    /// reads of the other ranks' part ([`keeps_own_elements`]: no contact, no remeshed model):
    /// their elements' connectivity ([`crate::model::Connectivity::keep_range`]), and the
    /// reference coordinates, masses and initial velocities of the nodes it does not store
    /// ([`crate::model::NodeArray::keep`]). [`restore_whole_problem`] gathers them back after
    /// the run, on every rank alike.
    pub fn new_rank_keeping_own_elements(
        problem: &'p mut Problem,
        settings: ExplicitSettings,
        output: OutputSettings,
        comm: &'p dyn Communicator,
    ) -> Result<Self> {
        Self::rank_of(Lent::KeepingOwnElements(problem), settings, output, comm)
    }

    fn rank_of(
        lent: Lent<'p>,
        settings: ExplicitSettings,
        output: OutputSettings,
        comm: &'p dyn Communicator,
    ) -> Result<Self> {
        let model = &lent.problem().model;
        let elements = if comm.size() > 1 && model.carried.is_none() {
            rank_ranges(model, comm.size())[comm.rank()].clone()
        } else {
            0..model.element_count()
        };
        let history = model.initial_history_of(elements);
        Self::with_history(lent, settings, output, history, Some(comm))
    }

    /// The rank and the number of ranks (0 and 1 for a run on one process).
    pub fn rank(&self) -> (usize, usize) {
        self.ranks
            .as_ref()
            .map_or((0, 1), |r| (r.comm.rank(), r.comm.size()))
    }

    /// The elements of this rank in a distributed run (`None` on one process).
    pub fn rank_elements(&self) -> Option<Range<usize>> {
        self.ranks.as_ref().map(|r| r.ranges[r.comm.rank()].clone())
    }

    /// Nodes whose forces every rank completes and integrates: shared by two ranks' elements or
    /// replicated (contact, probes, prescribed motions); 0 on one process.
    pub fn exchanged_nodes(&self) -> usize {
        self.nodes.exchanged().iter().filter(|&&x| x).count()
    }

    /// Nodes used by the elements of two ranks or more ([`NodePlan::shared_nodes`]); 0 on one
    /// process.
    pub fn shared_nodes(&self) -> usize {
        self.nodes.shared_nodes()
    }

    /// `f64` values each rank sends per step to complete the forces (empty on one process).
    pub fn exchange_counts(&self) -> &[usize] {
        self.ranks.as_ref().map_or(&[], |r| r.exchange.counts())
    }

    /// Completes the internal forces after this rank's element loop and agrees on the lowest
    /// inverted element of all ranks (collective; nothing on one process).
    pub(super) fn complete_forces(&mut self, inverted: Option<usize>) -> Option<usize> {
        let Some(share) = self.ranks.as_mut() else {
            return inverted;
        };
        let model = &self.problem.model;
        share.exchange.complete(
            share.comm,
            |send| model.append_foreign_contributions(send),
            &mut self.f_int,
        );
        // The lowest element is the largest `u64::MAX - e`; 0 for none.
        let lowest = share
            .comm
            .max_u64(inverted.map_or(0, |e| u64::MAX - e as u64));
        (lowest != 0).then(|| (u64::MAX - lowest) as usize)
    }

    /// `det F` of element `e`, computed by the rank that owns it and sent to all (collective;
    /// computed here on one process): another rank stores neither its nodes nor, when it keeps
    /// its own elements' only, its connectivity.
    pub(super) fn element_jacobian(&self, e: usize) -> f64 {
        let model = &self.problem.model;
        let Some(share) = &self.ranks else {
            return model.deformation_gradient(e, &self.u).determinant();
        };
        let mine = if share.own_elements().contains(&e) {
            model.deformation_gradient(e, &self.u).determinant()
        } else {
            0.0
        };
        let size = share.comm.size();
        let mut all = vec![0.0; size];
        share.comm.all_gather_f64(&[mine], &vec![1; size], &mut all);
        all[share.ranges.partition_point(|r| r.end <= e)]
    }

    /// Whether `mine` holds on any rank (collective; `mine` on one process): a decision every
    /// rank takes alike, such as a checkpoint falling due by one rank's clock.
    pub fn on_any_rank(&self, mine: bool) -> bool {
        match &self.ranks {
            Some(share) => share.comm.max_u64(u64::from(mine)) != 0,
            None => mine,
        }
    }

    /// Every node's values of `field` (one of this solver's nodal fields): the field itself on
    /// one process; on a rank, gathered from the ranks that sum each node's leaf (collective:
    /// every rank asks for the same fields in the same order).
    pub fn whole<'a>(&self, field: &'a NodeField<Vector3<f64>>) -> Cow<'a, [Vector3<f64>]> {
        match (&self.ranks, field.as_slice()) {
            (None, Some(values)) => Cow::Borrowed(values),
            (Some(share), _) => Cow::Owned(self.nodes.gather(share.comm, field)),
            (None, None) => unreachable!("{ONE_PROCESS}"),
        }
    }

    /// Every node's displacement and full-step velocity at the end of a run, for its caller
    /// ([`Self::whole`]; collective). The run is over: the fields of the step are freed first, so
    /// that the gathered values take their place, and the solver cannot step again.
    pub fn final_nodes(&mut self) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        for field in [
            &mut self.f_int,
            &mut self.f_ext,
            &mut self.du_prev,
            &mut self.v_next,
            &mut self.v_half,
        ] {
            *field = NodeField::dense(Vec::new());
        }
        // One at a time: the gathered displacement takes the place of the stored one before
        // the velocity is gathered.
        let u = std::mem::replace(&mut self.u, NodeField::dense(Vec::new()));
        let u = self.whole_taken(u);
        let v = std::mem::replace(&mut self.v_full, NodeField::dense(Vec::new()));
        (u, self.whole_taken(v))
    }

    /// Every node's values of `field`, taken out ([`Self::whole`] without a copy on one process;
    /// collective).
    fn whole_taken(&self, field: NodeField<Vector3<f64>>) -> Vec<Vector3<f64>> {
        match &self.ranks {
            None => field.into_dense().expect(ONE_PROCESS),
            Some(share) => self.nodes.gather(share.comm, &field),
        }
    }

    /// The elastic energy stored in all elements ([`crate::model::Model::stored_energy`]): each
    /// rank computes the shares of its blocks of elements, and every rank folds all of them in
    /// order (collective).
    pub(super) fn stored_energy(&self) -> f64 {
        let model = &self.problem.model;
        let Some(share) = &self.ranks else {
            // The slice, not the field: the same loop as a plain vector's, at its speed.
            return model.stored_energy(self.u.as_slice().expect(ONE_PROCESS));
        };
        // A rank without elements (a model of fewer leaves than ranks) has no leaf: the leaf
        // around its empty range is the previous rank's.
        let leaves = |r: &Range<usize>| match r.is_empty() {
            true => 0..0,
            false => r.start / ELEMENT_LEAF..r.end.div_ceil(ELEMENT_LEAF),
        };
        let mine =
            model.stored_energy_shares(&self.u.view(), leaves(&share.ranges[share.comm.rank()]));
        let counts: Vec<usize> = share.ranges.iter().map(|r| leaves(r).len()).collect();
        let mut all = vec![0.0; counts.iter().sum()];
        share.comm.all_gather_f64(&mine, &counts, &mut all);
        all.iter().sum()
    }

    /// The crack opening of every element ([`crate::model::Model::crack_openings`]; empty without
    /// a material history): each rank computes its elements' and every rank gathers all of them
    /// (collective), which costs one value per element where gathering the history would cost
    /// its 1.2 KB.
    pub(super) fn crack_openings(&self) -> Vec<f32> {
        let model = &self.problem.model;
        if self.history.is_empty() {
            return Vec::new();
        }
        let Some(share) = &self.ranks else {
            return model.crack_openings(self.u.as_slice().expect(ONE_PROCESS), &self.history);
        };
        let mine = model.crack_openings_of(
            &self.u.view(),
            &self.history,
            share.ranges[share.comm.rank()].clone(),
        );
        let counts: Vec<usize> = share.ranges.iter().map(Range::len).collect();
        let mut all = vec![0.0; model.element_count()];
        share.comm.all_gather_f32(&mine, &counts, &mut all);
        all
    }
}

/// The problem a solver is built on: lent shared, or lent mutably to a rank that keeps only its
/// own elements' connectivity once its plan is made.
pub(super) enum Lent<'p> {
    Shared(&'p Problem),
    KeepingOwnElements(&'p mut Problem),
}

impl<'p> Lent<'p> {
    /// The problem, whole, for the solver's setup.
    pub(super) fn problem(&self) -> &Problem {
        match self {
            Lent::Shared(p) => p,
            Lent::KeepingOwnElements(p) => p,
        }
    }

    /// The problem for the run. Lent to keep a rank's own part: where `nodes` is given (a run
    /// that never reads the rest, [`keeps_own_elements`]) with the connectivity of its
    /// `elements` and the reference coordinates, masses and initial velocities of its `nodes`
    /// only; then, in any case, with the per-element data of its `elements` only, computed
    /// after the rest is freed where the model holds none (a rank's model,
    /// `crate::scene::build_problem_on_rank`), so that the rank never holds both.
    pub(super) fn keep_own_part(
        self,
        elements: Option<Range<usize>>,
        nodes: Option<&NodeSlots>,
    ) -> &'p Problem {
        match self {
            Lent::Shared(p) => p,
            Lent::KeepingOwnElements(p) => {
                let Some(elements) = elements else {
                    return p;
                };
                if let Some(nodes) = nodes {
                    p.model.tets.keep_range(elements.clone());
                    p.model.reference.keep(nodes);
                    p.model.mass.keep(nodes);
                    p.initial_velocity.keep(nodes);
                }
                p.model.keep_or_compute_element_data(elements);
                p
            }
        }
    }
}

/// Whether a distributed run on `problem` keeps each rank's own elements' connectivity only
/// ([`ExplicitSolver::new_rank_keeping_own_elements`]): every rank decides alike.
pub fn keeps_own_elements(problem: &Problem, comm: &dyn Communicator) -> bool {
    comm.size() > 1 && problem.contact.is_empty() && problem.model.carried.is_none()
}

/// The whole problem again on every rank, after a run that kept each rank's own part
/// ([`keeps_own_elements`]; collective): every element's connectivity, and every node's
/// reference coordinates, mass and initial velocity. Nothing where every rank holds it whole
/// (an analysis that did not keep its part).
pub fn restore_whole_problem(problem: &mut Problem, comm: &dyn Communicator) {
    restore_connectivity(problem, comm);
    restore_node_arrays(problem, comm);
}

/// Every element's connectivity: each rank sends the consecutive range it kept.
fn restore_connectivity(problem: &mut Problem, comm: &dyn Communicator) {
    let tets = &problem.model.tets;
    let mine = tets.stored().as_flattened();
    let counts = posted_counts(comm, mine.len());
    if counts.iter().all(|&c| c == 4 * tets.len()) {
        return;
    }
    // Straight into the whole connectivity: one copy of it, none of the parts.
    let mut whole = vec![[0u32; 4]; tets.len()];
    comm.all_gather_u32(mine, &counts, whole.as_flattened_mut());
    problem.model.tets.restore(whole);
}

/// How many values each rank sends, from each rank's `mine`.
fn posted_counts(comm: &dyn Communicator, mine: usize) -> Vec<usize> {
    let mut posted = vec![0; comm.size()];
    let mine = u32::try_from(mine).expect("a rank sends fewer than 2^32 values");
    comm.all_gather_u32(&[mine], &vec![1; comm.size()], &mut posted);
    posted.iter().map(|&c| c as usize).collect()
}

/// Every node's reference coordinates, mass and initial velocity: each rank sends the ids of
/// the nodes it kept and their values. A node two ranks kept has the same values on both (each
/// kept them from the same whole array), so the order of the writes does not matter; every node
/// is kept by at least one rank (the one that integrates it).
fn restore_node_arrays(problem: &mut Problem, comm: &dyn Communicator) {
    let model = &problem.model;
    let n = model.node_count();
    let ids: Vec<u32> = match model.reference.field().slots().is_dense() {
        true => Vec::new(),
        false => (model.reference.field().slots().stored_ids())
            .map(|a| a as u32)
            .collect(),
    };
    let counts = posted_counts(comm, ids.len());
    if counts.iter().all(|&c| c == 0) {
        return;
    }
    let mut all_ids = vec![0u32; counts.iter().sum()];
    comm.all_gather_u32(&ids, &counts, &mut all_ids);
    let gather = |mine: Vec<f64>, width: usize| {
        let counts: Vec<usize> = counts.iter().map(|c| c * width).collect();
        let mut all = vec![0.0; counts.iter().sum()];
        comm.all_gather_f64(&mine, &counts, &mut all);
        all
    };
    let vectors = |field: &NodeArray<Vector3<f64>>| {
        let mine = field
            .stored()
            .iter()
            .flat_map(|x| x.iter().copied())
            .collect();
        let all = gather(mine, 3);
        let mut whole = vec![Vector3::from_element(f64::NAN); n];
        for (&a, x) in all_ids.iter().zip(all.chunks_exact(3)) {
            whole[a as usize] = Vector3::new(x[0], x[1], x[2]);
        }
        whole
    };
    let reference = vectors(&model.reference);
    let initial_velocity = vectors(&problem.initial_velocity);
    let mut mass = vec![f64::NAN; n];
    for (&a, &m) in all_ids.iter().zip(&gather(model.mass.stored().to_vec(), 1)) {
        mass[a as usize] = m;
    }
    // The nodes nobody kept would be NaN; there are none (see above).
    debug_assert!(reference.iter().all(|x| !x.x.is_nan()));
    problem.model.reference.restore(reference);
    problem.model.mass.restore(mass);
    problem.initial_velocity.restore(initial_velocity);
}
