//! The two tips over the snapshots of a run: when each element opens, when it joins the
//! connected crack, which joins are coalescence, and how high each tip has reached.

use super::path::CrackPath;
use crate::beam::cracks::CrackError;

/// Per-snapshot heights of the two tips and the coalescence along them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TipTrack {
    /// Snapshot times (s).
    pub times: Vec<f64>,
    /// Height of the cohesive tip (the highest centroid of the connected set at `w >= w_p`)
    /// above the bottom face (m), `None` before that set exists.
    pub cohesive: Vec<Option<f64>>,
    /// Height of the traction-free tip (the same at `w >= w_tf`), `None` before that set exists.
    pub traction_free: Vec<Option<f64>>,
    /// Length of the cohesive tip's advance up to each snapshot that went into pre-damaged
    /// elements (coalescence, `coalesced`), the advance with which it appears included (m).
    pub cohesive_coalescence: Vec<f64>,
    /// The same for the traction-free tip (m).
    pub traction_free_coalescence: Vec<f64>,
    /// Which elements are pre-damaged (`coalesced`).
    pub coalesced: Vec<bool>,
    /// Depth below the top face of the pre-damage front in the column under the load
    /// (`damage_front`) at each snapshot (m), `None` before there is any.
    pub damage_front: Vec<Option<f64>>,
    /// Depth of the shallowest element of the pre-damage front at the snapshot it appears (m),
    /// `None` without one: where the front entered the column.
    pub damage_entry: Option<f64>,
    /// Depth of the shallowest pre-damaged element of the column at any snapshot (m), `None`
    /// without one: whether pre-damage reached above the bending neutral axis.
    pub damage_shallowest: Option<f64>,
}

/// Follows the crack over snapshots of the beam's element openings `w` (m): `openings` yields
/// one vector per time of `times`. An element's opening counts as its largest so far, so the
/// connected sets only grow and a crack that closes elastically keeps the height it reached.
pub fn track<I>(
    path: &CrackPath,
    times: &[f64],
    openings: I,
    w_cohesive: f64,
    w_traction_free: f64,
) -> Result<TipTrack, CrackError>
where
    I: IntoIterator<Item = Result<Vec<f64>, CrackError>>,
{
    let n = path.height.len();
    let mut w_max = vec![0.0f64; n];
    // Index of the first snapshot at which each element is past w_p, in the cohesive crack, in
    // the traction-free crack.
    let (mut past_p, mut in_cohesive, mut in_free) = (vec![None; n], vec![None; n], vec![None; n]);
    let mut count = 0;
    for (k, w) in openings.into_iter().enumerate() {
        let w = w?;
        if w.len() != n {
            return Err(CrackError::OpeningCount {
                openings: w.len(),
                elements: n,
            });
        }
        for (m, x) in w_max.iter_mut().zip(&w) {
            *m = m.max(*x);
        }
        let open_p: Vec<bool> = w_max.iter().map(|&x| x >= w_cohesive).collect();
        let open_f: Vec<bool> = w_max.iter().map(|&x| x >= w_traction_free).collect();
        mark(&mut past_p, &open_p, k);
        mark(&mut in_cohesive, &path.connected(&open_p), k);
        mark(&mut in_free, &path.connected(&open_f), k);
        count += 1;
    }
    if count != times.len() {
        return Err(CrackError::SnapshotCount {
            snapshots: count,
            times: times.len(),
        });
    }
    let coalesced = coalesced(path, &past_p, &in_cohesive);
    let (cohesive, cohesive_coalescence) = heights(path, &in_cohesive, &coalesced, count);
    let (traction_free, traction_free_coalescence) = heights(path, &in_free, &coalesced, count);
    let DamageFront {
        front: damage_front,
        entry: damage_entry,
        shallowest: damage_shallowest,
    } = damage_front(path, &past_p, &in_cohesive, count);
    Ok(TipTrack {
        times: times.to_vec(),
        cohesive,
        traction_free,
        cohesive_coalescence,
        traction_free_coalescence,
        coalesced,
        damage_front,
        damage_entry,
        damage_shallowest,
    })
}

/// The pre-damage front in the column under the load: at each snapshot, the greatest depth
/// below the top face of a column element that went past `w_p` while neither it nor an element
/// touching it was in the connected cohesive crack (opened by the compressive wave's splitting,
/// not by the crack's own tip; an element that passes `w_p` in the snapshot the crack reaches it
/// or a node-sharing neighbour is the crack's). The front only deepens. A damage front triggered
/// by a passing wave cannot outrun the wave that triggers it: top-down in the column, the
/// dilatational wave `c_p` (`../shared/research/drop-test-physics.md`, section 6 of its
/// recommendations).
pub fn damage_front(
    path: &CrackPath,
    past_p: &[Option<usize>],
    in_cohesive: &[Option<usize>],
    count: usize,
) -> DamageFront {
    // Shallowest and deepest pre-damaged element first past w_p at each snapshot.
    let mut range: Vec<Option<(f64, f64)>> = vec![None; count];
    for e in (0..past_p.len()).filter(|&e| path.column[e]) {
        let Some(p) = past_p[e] else { continue };
        let touched = path.touching[e]
            .iter()
            .any(|&m| in_cohesive[m].is_some_and(|j| j <= p));
        if in_cohesive[e].is_some_and(|j| j <= p) || touched {
            continue;
        }
        let d = path.depth[e];
        range[p] = Some(range[p].map_or((d, d), |(a, b): (f64, f64)| (a.min(d), b.max(d))));
    }
    let entry = range.iter().flatten().next().map(|r| r.0);
    let shallowest = range.iter().flatten().map(|r| r.0).min_by(f64::total_cmp);
    let mut front: Option<f64> = None;
    let front = range
        .into_iter()
        .map(|r| {
            if let Some((_, d)) = r {
                front = Some(front.map_or(d, |f| f.max(d)));
            }
            front
        })
        .collect();
    DamageFront {
        front,
        entry,
        shallowest,
    }
}

/// The pre-damaged elements of the column over a run ([`damage_front`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DamageFront {
    /// Depth of the front below the top face at each snapshot (m), `None` before there is any.
    pub front: Vec<Option<f64>>,
    /// Depth of its shallowest element at the snapshot it appears (m): where it entered.
    pub entry: Option<f64>,
    /// Depth of the shallowest pre-damaged element at any snapshot (m).
    pub shallowest: Option<f64>,
}

fn mark(first: &mut [Option<usize>], now: &[bool], k: usize) {
    for (f, &on) in first.iter_mut().zip(now) {
        if on && f.is_none() {
            *f = Some(k);
        }
    }
}

/// Pre-damaged elements: not a seed, and past `w_p` at a snapshot before any element touching
/// it (sharing a node: across a face, an edge or a corner) was in the connected cohesive crack.
/// Such an element was opened by something other than the crack's own tip (the compressive
/// wave's splitting, another crack), and the front's advance into it is coalescence, not
/// propagation. A tetrahedral crack front advances through edges and corners as much as through
/// faces: on the 2 m/s Gmsh beam, 172 of the 174 elements a face rule takes for pre-damaged had
/// a node-sharing neighbour in the crack when they passed `w_p` (`coalescence_neighbours` in
/// `case_run.rs`). A seed starts the crack, so it is never one; an element that opens in the
/// same snapshot as its neighbour joins is propagation (the snapshot interval is the limit of
/// what this can tell apart).
pub fn coalesced(
    path: &CrackPath,
    past_p: &[Option<usize>],
    in_cohesive: &[Option<usize>],
) -> Vec<bool> {
    let mut seed = vec![false; past_p.len()];
    for &s in &path.seeds {
        seed[s] = true;
    }
    (0..past_p.len())
        .map(|e| {
            let neighbour_joined = path.touching[e]
                .iter()
                .filter_map(|&n| in_cohesive[n])
                .min();
            match (past_p[e], neighbour_joined) {
                (Some(p), Some(a)) => !seed[e] && p < a,
                _ => false,
            }
        })
        .collect()
}

/// The tip height per snapshot of a crack whose elements join at `joined`, and the cumulative
/// length of its advance through pre-damaged elements. The advance of one snapshot is split
/// among the elements that join above the previous tip, bottom up: the rise from the previous
/// element's height (or the previous tip) to each one's belongs to it, and counts as
/// coalescence when it is pre-damaged. The first snapshot rises from the bottom face.
fn heights(
    path: &CrackPath,
    joined: &[Option<usize>],
    coalesced: &[bool],
    count: usize,
) -> (Vec<Option<f64>>, Vec<f64>) {
    let mut by_snapshot: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (e, j) in joined.iter().enumerate() {
        if let Some(k) = j {
            by_snapshot[*k].push(e);
        }
    }
    let (mut tip, mut coalescence) = (Vec::with_capacity(count), Vec::with_capacity(count));
    let (mut top, mut total): (Option<f64>, f64) = (None, 0.0);
    for mut new in by_snapshot {
        new.sort_by(|a, b| path.height[*a].total_cmp(&path.height[*b]));
        let mut level = top.unwrap_or(0.0);
        for e in new {
            let y = path.height[e];
            if y > level {
                if coalesced[e] {
                    total += y - level;
                }
                level = y;
            }
            top = Some(top.map_or(y, |t: f64| t.max(y)));
        }
        tip.push(top);
        coalescence.push(total);
    }
    (tip, coalescence)
}
