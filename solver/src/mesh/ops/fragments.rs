//! Loose fragments: a few elements joined to each other through their faces but to the rest of
//! the body only through nodes or edges, which erosion (`peel.rs`) can leave behind.
//!
//! Erosion removes a collapsed element whatever its neighbours, so a piece of the body may end
//! up hanging on the rest by a node. A large piece is a chip of the body and stays. A piece of a
//! few elements is not concrete any more but debris carried on the nodes it shares: in the nail
//! run (2026-11-30) an eroded single element, its four faces all on the boundary, overlapped
//! the concrete around one of its nodes, which the body later closed around; that node then
//! looked like a surface node to the elements it shared with the fragment and like an inner
//! node to the rest, and the remeshing at 143 us stopped on it. The remesher erodes such
//! fragments with the collapsed elements, and its check refuses one.

/// A face-joined piece of at most this many elements that touches the rest of the body only
/// through nodes or edges is a loose fragment. An eroded element's neighbours are what such a
/// piece is made of; a larger piece is kept as a part of the body.
pub(crate) const LOOSE_FRAGMENT_ELEMENTS: usize = 8;

/// The loose fragments among the elements `candidates` (ascending): each set of candidates
/// joined through shared faces (`face_neighbours`, the elements sharing a face with one) that
/// holds at most [`LOOSE_FRAGMENT_ELEMENTS`] elements and shares no face with an element that is
/// not a candidate (the rest of the body, which the walk does not enter), but for which `hangs`
/// holds: it shares a node with an element outside it (a body of its own is not a fragment). In
/// the order of their first element, each sorted. Every candidate is visited once.
pub(crate) fn loose_fragments(
    candidates: &[usize],
    face_neighbours: &mut dyn FnMut(usize) -> Vec<usize>,
    hangs: &dyn Fn(&[usize]) -> bool,
) -> Vec<Vec<usize>> {
    let is_candidate = |e: usize| candidates.binary_search(&e).is_ok();
    let mut seen = std::collections::HashSet::new();
    let mut fragments = Vec::new();
    for &start in candidates {
        if !seen.insert(start) {
            continue;
        }
        let (mut piece, mut attached) = (vec![start], false);
        let mut next = 0;
        while next < piece.len() {
            for n in face_neighbours(piece[next]) {
                if !is_candidate(n) {
                    attached = true;
                } else if seen.insert(n) {
                    piece.push(n);
                }
            }
            next += 1;
        }
        if !attached && piece.len() <= LOOSE_FRAGMENT_ELEMENTS {
            piece.sort_unstable();
            if hangs(&piece) {
                fragments.push(piece);
            }
        }
    }
    fragments
}

/// Whether the elements `piece` of `tets` share a node with an element outside them, given
/// `uses(n)`, the number of elements that hold node `n`.
pub(crate) fn shares_a_node(
    tets: &[[u32; 4]],
    piece: &[usize],
    uses: &dyn Fn(u32) -> usize,
) -> bool {
    let mut inside: Vec<u32> = piece.iter().flat_map(|&e| tets[e]).collect();
    inside.sort_unstable();
    inside
        .chunk_by(|a, b| a == b)
        .any(|run| uses(run[0]) > run.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of `n` elements, each joined to the next through a face.
    fn chain(n: usize) -> impl FnMut(usize) -> Vec<usize> {
        move |e| {
            [e.checked_sub(1), (e + 1 < n).then_some(e + 1)]
                .into_iter()
                .flatten()
                .collect()
        }
    }

    #[test]
    fn a_small_piece_is_a_fragment_and_a_large_one_is_not() {
        let all = |n: usize| (0..n).collect::<Vec<_>>();
        assert_eq!(
            loose_fragments(&all(1), &mut chain(1), &|_| true),
            vec![vec![0]]
        );
        let n = LOOSE_FRAGMENT_ELEMENTS;
        assert_eq!(
            loose_fragments(&all(n), &mut chain(n), &|_| true),
            vec![all(n)]
        );
        assert!(loose_fragments(&all(n + 1), &mut chain(n + 1), &|_| true).is_empty());
        // Two pieces: the chain cut between 2 and 3.
        let mut cut = |e: usize| {
            chain(6)(e)
                .into_iter()
                .filter(|&o| e.min(o) != 2 || e.max(o) != 3)
                .collect()
        };
        assert_eq!(
            loose_fragments(&all(6), &mut cut, &|_| true),
            vec![vec![0, 1, 2], vec![3, 4, 5]]
        );
    }

    #[test]
    fn a_piece_joined_to_the_rest_of_the_body_is_not_a_fragment() {
        // Element 3 of the chain is not a candidate (outside the remeshed region).
        assert!(loose_fragments(&[0, 1, 2], &mut chain(4), &|_| true).is_empty());
        // Nor is 0: 1 and 2 hang on both.
        assert!(loose_fragments(&[1, 2], &mut chain(4), &|_| true).is_empty());
        // A piece that shares no node with the rest is a body of its own.
        assert!(loose_fragments(&[0], &mut chain(1), &|_| false).is_empty());
    }

    #[test]
    fn a_piece_hangs_where_another_element_holds_one_of_its_nodes() {
        let tets = [[0, 1, 2, 3], [1, 2, 3, 4], [4, 5, 6, 7]];
        let uses = |tets: &[[u32; 4]]| {
            let t = tets.to_vec();
            move |n: u32| t.iter().filter(|e| e.contains(&n)).count()
        };
        // Elements 0 and 1 share a face; 2 hangs on 1 by node 4.
        assert!(shares_a_node(&tets, &[0, 1], &uses(&tets)));
        assert!(shares_a_node(&tets, &[2], &uses(&tets)));
        assert!(!shares_a_node(&tets, &[0, 1, 2], &uses(&tets)));
        assert!(!shares_a_node(&tets[..2], &[0, 1], &uses(&tets[..2])));
    }
}
