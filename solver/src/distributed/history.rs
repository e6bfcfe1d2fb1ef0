//! The material history of every element on every rank, for output.

use std::ops::Range;

use super::Communicator;
use crate::model::{MaterialHistory, Model};

/// The most `f32` values one round of [`gather_in_place`] sends per rank (4 MiB): the rounds'
/// buffers, not a copy of the rank's part, bound the memory the gather adds.
const GATHER_CHUNK: usize = 1 << 20;

/// Copies every rank's part of the material `history` (the elements of its range in `ranges`)
/// to every rank, so that field frames, crack openings and the final stresses read the whole
/// history. Each rank's own part is unchanged. Collective; called at output times only, its cost
/// (the whole history, 1.2 KB per microplane element) is paid per frame, not per step.
pub fn gather_history(
    comm: &dyn Communicator,
    model: &Model,
    ranges: &[Range<usize>],
    history: &mut MaterialHistory,
) {
    for (body, h) in model.bodies.iter().zip(history.bodies.iter_mut()) {
        let Some(h) = h else { continue };
        // The body's elements of each rank, local ids.
        let parts: Vec<Range<usize>> = ranges
            .iter()
            .map(|r| {
                let start = r.start.clamp(body.elements.start, body.elements.end);
                let end = r.end.clamp(body.elements.start, body.elements.end);
                start - body.elements.start..end - body.elements.start
            })
            .collect();
        let mine = parts[comm.rank()].clone();
        let len = h.state_len;
        let spans: Vec<Range<usize>> = parts.iter().map(|p| p.start * len..p.end * len).collect();
        gather_in_place(comm, &spans, &mut h.values, GATHER_CHUNK);
        let counts: Vec<usize> = parts.iter().map(|p| p.len() * 6).collect();
        let own: Vec<f64> = h.cauchy[mine].iter().flatten().copied().collect();
        let mut all = vec![0.0; 6 * h.cauchy.len()];
        comm.all_gather_f64(&own, &counts, &mut all);
        for (stress, values) in h.cauchy.iter_mut().zip(all.chunks_exact(6)) {
            stress.copy_from_slice(values);
        }
    }
}

/// Fills `values` on every rank with every rank's span of it (`spans[r]`, disjoint, rank `r`'s
/// own values already in place), in rounds of at most `chunk` values per rank: round `k` gathers
/// the `k`-th chunk of every span. One all-gather of a copy of the own span would hold that
/// copy (half the history on two ranks) on top of the history at every frame. Collective.
fn gather_in_place(
    comm: &dyn Communicator,
    spans: &[Range<usize>],
    values: &mut [f32],
    chunk: usize,
) {
    let rounds = spans
        .iter()
        .map(|s| s.len().div_ceil(chunk))
        .max()
        .unwrap_or(0);
    let mut received = Vec::new();
    for k in 0..rounds {
        // The k-th chunk of each span, as a range of `values`.
        let pieces: Vec<Range<usize>> = spans
            .iter()
            .map(|s| {
                let start = (s.start + k * chunk).min(s.end);
                start..(start + chunk).min(s.end)
            })
            .collect();
        let counts: Vec<usize> = pieces.iter().map(|p| p.len()).collect();
        let own = values[pieces[comm.rank()].clone()].to_vec();
        received.resize(counts.iter().sum(), 0.0);
        comm.all_gather_f32(&own, &counts, &mut received);
        let mut at = 0;
        for (r, piece) in pieces.iter().enumerate() {
            if r != comm.rank() {
                values[piece.clone()].copy_from_slice(&received[at..at + piece.len()]);
            }
            at += piece.len();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distributed::ThreadGroup;

    #[test]
    fn the_rounds_give_every_rank_every_span_whatever_the_chunk() {
        // Spans of unequal length, one empty, none a multiple of the chunk.
        let spans = [0..7, 7..7, 7..20, 20..23];
        let whole: Vec<f32> = (0..23).map(|i| i as f32 * 0.5 - 3.0).collect();
        for chunk in [1, 2, 3, 5, 100] {
            let group = ThreadGroup::new(spans.len());
            let got: Vec<Vec<f32>> = std::thread::scope(|s| {
                let handles: Vec<_> = group
                    .iter()
                    .map(|c| {
                        let (spans, whole) = (&spans, &whole);
                        s.spawn(move || {
                            // Only the rank's own span is known beforehand.
                            let mut values = vec![f32::NAN; whole.len()];
                            let own = spans[c.rank()].clone();
                            values[own.clone()].copy_from_slice(&whole[own]);
                            gather_in_place(c, spans, &mut values, chunk);
                            values
                        })
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for values in got {
                let same = values
                    .iter()
                    .zip(&whole)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "chunk {chunk}: {values:?}");
            }
        }
    }
}
