//! The history of the materials that keep one (the microplane concrete model), which an analysis
//! owns.
//!
//! The history is not part of [`Model`], which stays immutable: an analysis creates it with
//! [`Model::initial_history`] and hands it to [`Model::advance_internal_forces`] exactly once per
//! step, which computes the forces at the current displacement and commits the update. Anything
//! else that wants forces or stresses of such a body (a second force evaluation at another
//! displacement, a static Newton iteration, an energy) must not advance it: the explicit stepper
//! computes forces once per step, the static solver updates copies of the committed history at
//! each Newton iteration and commits one per converged load step (`statics::path`), and stored
//! energy and field output read the history without changing it.

use std::ops::Range;

use super::Model;

/// The history of one body of a material with history.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyHistory {
    /// `f32` values per element ([`crate::material::Material::history_len`]).
    pub state_len: usize,
    /// The body's local id of the first element held: a rank of a distributed run holds the
    /// elements of its own range only ([`Self::held`]); 0 for a whole body.
    pub first: usize,
    /// The held elements' histories one after the other, in the body's element order.
    pub values: Vec<f32>,
    /// Cauchy stress of each held element at the last update, `[xx, yy, zz, xy, yz, xz]` (Pa),
    /// for the output: zero before the first step.
    pub cauchy: Vec<[f64; 6]>,
}

impl BodyHistory {
    /// A virgin history of the body's elements `held` (local ids), `state_len` values each,
    /// each element's set by `init`.
    pub fn virgin(state_len: usize, held: Range<usize>, init: impl Fn(&mut [f32])) -> Self {
        let n = held.len();
        let mut values = vec![0.0; n * state_len];
        for element in values.chunks_exact_mut(state_len) {
            init(element);
        }
        BodyHistory {
            state_len,
            first: held.start,
            values,
            cauchy: vec![[0.0; 6]; n],
        }
    }

    /// The body's local ids of the elements held.
    pub fn held(&self) -> Range<usize> {
        self.first..self.first + self.cauchy.len()
    }

    /// A copy of the history of the elements `part` (local ids) only, which this one holds.
    pub fn part(&self, part: Range<usize>) -> Self {
        let held = self.held();
        assert!(
            held.start <= part.start && part.end <= held.end,
            "a history of elements {held:?} has no part {part:?}"
        );
        let at = part.start - held.start..part.end - held.start;
        BodyHistory {
            state_len: self.state_len,
            first: part.start,
            values: self.values[at.start * self.state_len..at.end * self.state_len].to_vec(),
            cauchy: self.cauchy[at].to_vec(),
        }
    }

    /// History of element `local` of the body (held: [`Self::held`]).
    pub fn element(&self, local: usize) -> &[f32] {
        let at = local - self.first;
        &self.values[at * self.state_len..(at + 1) * self.state_len]
    }

    /// Stress of element `local` of the body at its last update, `None` when not held.
    pub fn stress(&self, local: usize) -> Option<[f64; 6]> {
        local
            .checked_sub(self.first)
            .and_then(|at| self.cauchy.get(at))
            .copied()
    }

    /// Bytes held per element.
    pub fn bytes_per_element(&self) -> usize {
        self.state_len * std::mem::size_of::<f32>() + std::mem::size_of::<[f64; 6]>()
    }
}

/// The histories of all bodies of a model (`None` for bodies without one), owned by an analysis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MaterialHistory {
    /// One entry per body of the model, in body order: its history, or `None` for a material
    /// without one.
    pub bodies: Vec<Option<BodyHistory>>,
}

impl MaterialHistory {
    /// Whether any body has a history.
    pub fn is_empty(&self) -> bool {
        self.bodies.iter().all(Option::is_none)
    }
}

impl Model {
    /// The share of the element updates of bodies whose material has a fast path (the
    /// microplane model's elastic path) that took it, over a run of `steps` steps: `steps + 1`
    /// updates per element, the forces at the start and after each step. `None` when no body
    /// has such a path.
    pub fn fast_update_share(&self, history: &MaterialHistory, steps: usize) -> Option<f64> {
        let updates = steps + 1;
        let (mut fast, mut elements) = (0.0, 0usize);
        for (body, h) in self.bodies.iter().zip(&history.bodies) {
            let Some(h) = h else { continue };
            for local in h.held() {
                if let Some(n) = body.material.fast_updates(h.element(local)) {
                    fast += n;
                    elements += 1;
                }
            }
        }
        (elements > 0).then(|| fast / (elements as f64 * updates as f64))
    }

    /// A virgin history for every body whose material has one.
    pub fn initial_history(&self) -> MaterialHistory {
        self.initial_history_of(0..self.element_count())
    }

    /// A virgin history of the elements of `elements` (global ids; a rank's range in a
    /// distributed run) for every body whose material has one: each body holds its elements in
    /// that range only, so a rank allocates its own part of the history and no other.
    pub fn initial_history_of(&self, elements: Range<usize>) -> MaterialHistory {
        MaterialHistory {
            bodies: self
                .bodies
                .iter()
                .map(|body| {
                    let state_len = body.material.history_len();
                    (state_len > 0).then(|| {
                        let held = body_part(&body.elements, &elements);
                        BodyHistory::virgin(state_len, held, |e| body.material.initial_history(e))
                    })
                })
                .collect(),
        }
    }

    /// Whether some body's material keeps a history.
    pub fn has_history(&self) -> bool {
        self.bodies.iter().any(|b| b.material.history_len() > 0)
    }
}

/// The body's local ids of the elements of `elements` (global ids) that belong to it (a body
/// whose elements are `body_elements`): empty, at the clamped position, when none do.
pub fn body_part(body_elements: &Range<usize>, elements: &Range<usize>) -> Range<usize> {
    let start = elements.start.clamp(body_elements.start, body_elements.end);
    let end = elements.end.clamp(body_elements.start, body_elements.end);
    start - body_elements.start..end - body_elements.start
}
