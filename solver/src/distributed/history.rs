//! The material history of every element on every rank, for output.

use std::ops::Range;

use super::Communicator;
use crate::model::{MaterialHistory, Model};

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
        let counts: Vec<usize> = parts.iter().map(|p| p.len() * len).collect();
        let own = h.values[mine.start * len..mine.end * len].to_vec();
        comm.all_gather_f32(&own, &counts, &mut h.values);
        let counts: Vec<usize> = parts.iter().map(|p| p.len() * 6).collect();
        let own: Vec<f64> = h.cauchy[mine].iter().flatten().copied().collect();
        let mut all = vec![0.0; 6 * h.cauchy.len()];
        comm.all_gather_f64(&own, &counts, &mut all);
        for (stress, values) in h.cauchy.iter_mut().zip(all.chunks_exact(6)) {
            stress.copy_from_slice(values);
        }
    }
}
