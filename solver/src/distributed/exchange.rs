//! The nodal forces of a distributed step, completed across ranks in the one-process fold order.

use std::ops::{IndexMut, Range};

use nalgebra::Vector3;

use super::Communicator;
use crate::model::{first_elements, NO_ELEMENT};

/// How the ranks complete each other's nodal forces (module doc of `distributed`).
///
/// Only the *exchanged* nodes ([`super::NodePlan`]) take part: every node that two ranks use is
/// one, and every other node's forces are complete where they are assembled.
/// After its element loop, rank `r` holds for each exchanged node it *owns* (whose first element
/// lies in its range) the fold of its own contributions, which is the start of the node's one-process
/// fold `((0 + f_e1) + f_e2) + ...`, and for each node owned by a lower rank its single
/// contributions, in ascending element order (the assembler's *foreign* slots). Every rank sends
/// both; every rank then folds, for every node, the owner's partial sum followed by the higher
/// ranks' contributions in rank order, which is ascending element order: the one-process fold,
/// bit for bit, on every rank.
#[derive(Debug)]
pub struct ForceExchange {
    /// Exchanged nodes owned by this rank, ascending: their partial sums open this rank's
    /// message.
    owned: Vec<u32>,
    /// The exchanged nodes this rank integrates, ascending: the nodes whose forces
    /// [`Self::complete`] sets.
    exchanged: Vec<u32>,
    /// This rank's foreign contributions (the rest of its message), to check the assembler's.
    foreign_len: usize,
    /// Values (`f64`) each rank sends.
    counts: Vec<usize>,
    /// The gathered vectors the `i`-th of those nodes folds, in fold order:
    /// `sources[offsets[i]..offsets[i + 1]]` (empty for a node without elements). Indexed by
    /// exchanged node, not by mesh node: a rank holds no table over the whole mesh.
    offsets: Vec<u32>,
    sources: Vec<u32>,
    send: Vec<f64>,
    gathered: Vec<f64>,
}

impl ForceExchange {
    /// The exchange of rank `rank` when the ranks hold the element `ranges` (consecutive, in rank
    /// order, covering every element) of a mesh of `tets` over `node_count` nodes, for the nodes
    /// flagged in `exchanged` (which must hold every node two ranks use), completing those among
    /// the ascending runs `held` (the nodes this rank integrates, which hold its elements' nodes).
    /// Every rank builds the same message plan: the mesh is known everywhere.
    pub fn new(
        tets: &[[u32; 4]],
        node_count: usize,
        ranges: &[Range<usize>],
        rank: usize,
        exchanged: &[bool],
        held: &[Range<usize>],
    ) -> Self {
        assert!(rank < ranges.len(), "rank {rank} of {} ranks", ranges.len());
        assert_eq!(
            ranges.first().map_or(0, |r| r.start),
            0,
            "ranges start at 0"
        );
        assert_eq!(
            ranges.last().map_or(0, |r| r.end),
            tets.len(),
            "ranges cover the mesh"
        );
        let first_element = first_elements(tets, node_count);
        let owner_of = |e: u32| ranges.partition_point(|r| r.end <= e as usize);
        // Per rank: owned nodes ascending, and foreign contributions `(node, element)` sorted,
        // which is the order the assembler keeps its slots in (node, then element).
        let mut owned: Vec<Vec<u32>> = vec![Vec::new(); ranges.len()];
        for (n, &first) in first_element.iter().enumerate() {
            if first != NO_ELEMENT && exchanged[n] {
                owned[owner_of(first)].push(n as u32);
            }
        }
        let foreign: Vec<Vec<(u32, u32)>> = ranges
            .iter()
            .map(|range| {
                let mut list: Vec<(u32, u32)> = range
                    .clone()
                    .flat_map(|e| tets[e].iter().map(move |&n| (n, e as u32)))
                    .filter(|&(n, _)| (first_element[n as usize] as usize) < range.start)
                    .collect();
                list.sort_unstable();
                list
            })
            .collect();
        // This rank completes the exchanged nodes it integrates only: its fold table holds those.
        let is_held = |n: u32| {
            let i = held.partition_point(|run| run.end <= n as usize);
            held.get(i).is_some_and(|run| run.contains(&(n as usize)))
        };
        let held_ids: Vec<u32> = (0..node_count as u32)
            .filter(|&n| exchanged[n as usize] && is_held(n))
            .collect();
        let position = |n: u32| held_ids.binary_search(&n).ok();
        let mut offsets = vec![0u32; held_ids.len() + 1];
        for (i, &n) in held_ids.iter().enumerate() {
            offsets[i + 1] = u32::from(first_element[n as usize] != NO_ELEMENT);
        }
        for list in &foreign {
            for &(n, _) in list {
                assert!(exchanged[n as usize], "node {n} is used by two ranks");
                if let Some(p) = position(n) {
                    offsets[p + 1] += 1;
                }
            }
        }
        for i in 0..held_ids.len() {
            offsets[i + 1] += offsets[i];
        }
        let mut sources = vec![0u32; offsets[held_ids.len()] as usize];
        let mut next: Vec<u32> = offsets[..held_ids.len()].to_vec();
        let mut base = 0u32;
        let mut counts = Vec::with_capacity(ranges.len());
        // Owners first (a node's owner precedes every rank that sends it a contribution), then
        // the ranks' contributions in rank order.
        let mut bases = Vec::with_capacity(ranges.len());
        for (own, list) in owned.iter().zip(&foreign) {
            bases.push(base);
            for (i, &n) in own.iter().enumerate() {
                if let Some(p) = position(n) {
                    sources[next[p] as usize] = base + i as u32;
                    next[p] += 1;
                }
            }
            counts.push(3 * (own.len() + list.len()));
            base += (own.len() + list.len()) as u32;
        }
        for ((own, list), &base) in owned.iter().zip(&foreign).zip(&bases) {
            for (j, &(n, _)) in list.iter().enumerate() {
                if let Some(p) = position(n) {
                    sources[next[p] as usize] = base + (own.len() + j) as u32;
                    next[p] += 1;
                }
            }
        }
        let total = 3 * base as usize;
        let mine = owned.swap_remove(rank);
        assert!(
            mine.iter().all(|&n| is_held(n)),
            "rank {rank} integrates the nodes of its elements"
        );
        Self {
            send: Vec::with_capacity(counts[rank]),
            foreign_len: foreign[rank].len(),
            owned: mine,
            exchanged: held_ids,
            counts,
            offsets,
            sources,
            gathered: vec![0.0; total],
        }
    }

    /// Values sent per rank per step (`f64`), in rank order: the communication volume.
    pub fn counts(&self) -> &[usize] {
        &self.counts
    }

    /// Completes the nodal forces `f` of every exchanged node from this rank's partial sums (in
    /// `f`, for the nodes it owns) and foreign contributions (which `append_foreign` appends to
    /// the message, three components each in the assembler's order), and those of the other
    /// ranks. Collective: every rank calls it at the same step.
    pub fn complete(
        &mut self,
        comm: &dyn Communicator,
        append_foreign: impl FnOnce(&mut Vec<f64>),
        f: &mut (impl IndexMut<usize, Output = Vector3<f64>> + ?Sized),
    ) {
        self.send.clear();
        for &n in &self.owned {
            self.send.extend(f[n as usize].iter());
        }
        append_foreign(&mut self.send);
        assert_eq!(
            self.send.len(),
            3 * (self.owned.len() + self.foreign_len),
            "foreign contributions out of date"
        );
        comm.all_gather_f64(&self.send, &self.counts, &mut self.gathered);
        let g = &self.gathered;
        let vector = |s: u32| {
            let i = 3 * s as usize;
            Vector3::new(g[i], g[i + 1], g[i + 2])
        };
        for (i, &n) in self.exchanged.iter().enumerate() {
            let range = self.offsets[i] as usize..self.offsets[i + 1] as usize;
            f[n as usize] = match self.sources[range].split_first() {
                None => Vector3::zeros(),
                Some((&owner, rest)) => rest.iter().fold(vector(owner), |acc, &s| acc + vector(s)),
            };
        }
    }
}
