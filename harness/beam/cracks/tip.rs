//! The bending-crack tip: its height in one state and its speed over the snapshots of a run.

use impact_solver::model::Problem;

use super::{cracked_at, zones, BeamElement, BeamFrame, BeamSpec};

/// Snapshots on each side of a snapshot used for the tip speed (a 5-snapshot central
/// difference).
pub const TIP_SPEED_HALF_WINDOW: usize = 2;

/// Height of the bending-crack tip from one state's flags: the highest centroid (above the
/// bottom face) of the cracked elements within one cell of the loaded strip
/// (`|x - x_load| <= a + c`), outside the loading region, connected (by shared nodes, through
/// such elements) to an element of the bottom layer of cells; 0 when there is none.
pub fn tip_height(frame: &BeamFrame, elements: &[BeamElement], cracked: &[bool]) -> f64 {
    let near: Vec<bool> = elements
        .iter()
        .zip(cracked)
        .map(|(e, &f)| {
            f && (e.centroid.x - frame.x_load).abs() <= frame.load_half_width + frame.cell
                && !frame.in_loading_region(&e.centroid)
        })
        .collect();
    zones(elements, &near)
        .iter()
        .filter(|z| {
            z.iter()
                .any(|&e| elements[e].centroid.y - frame.y_bottom < frame.cell)
        })
        .flat_map(|z| z.iter().map(|&e| elements[e].centroid.y - frame.y_bottom))
        .fold(0.0, f64::max)
}

/// `(t, height, speed)` from tip heights at times: `height` is the highest the tip has reached
/// so far (the running maximum, so that a crack closing elastically does not count as a tip
/// moving back), `speed = (h_{i+k} - h_{i-k}) / (t_{i+k} - t_{i-k})` with
/// `k = TIP_SPEED_HALF_WINDOW`, the window shrinking to one side at the ends.
pub fn tip_speeds(times: &[f64], heights: &[f64]) -> Vec<(f64, f64, f64)> {
    let mut reached = Vec::with_capacity(heights.len());
    let mut best: f64 = 0.0;
    for h in heights {
        best = best.max(*h);
        reached.push(best);
    }
    let n = times.len();
    (0..n)
        .map(|i| {
            let (a, b) = (
                i.saturating_sub(TIP_SPEED_HALF_WINDOW),
                (i + TIP_SPEED_HALF_WINDOW).min(n - 1),
            );
            let speed = if b > a && times[b] > times[a] {
                (reached[b] - reached[a]) / (times[b] - times[a])
            } else {
                0.0
            };
            (times[i], reached[i], speed)
        })
        .collect()
}

/// The bending-crack tip over the snapshots of a run: `(t, height reached (m), speed (m/s))`
/// (see [`tip_height`] and [`tip_speeds`]).
pub fn crack_tip_history(
    problem: &Problem,
    snapshots: &[impact_solver::dynamics::Snapshot],
    spec: &BeamSpec,
) -> Result<Vec<(f64, f64, f64)>, String> {
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    let mut times = Vec::with_capacity(snapshots.len());
    let mut heights = Vec::with_capacity(snapshots.len());
    for s in snapshots {
        let cracked = cracked_at(problem, spec, &s.u)?;
        times.push(s.time);
        heights.push(tip_height(&frame, &elements, &cracked));
    }
    Ok(tip_speeds(&times, &heights))
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::{flag, frame, grid, vertical};
    use super::*;

    #[test]
    fn tip_follows_the_mid_span_zone_connected_to_the_bottom() {
        let e = grid(60, 12, 0.05);
        let f = frame();
        assert_eq!(tip_height(&f, &e, &vec![false; e.len()]), 0.0);
        assert!((tip_height(&f, &e, &flag(&e, &vertical(6))) - 0.275).abs() < 1e-12);
        // A cracked patch in the middle of the height, not connected to the bottom, and a
        // crack at the bottom far from mid-span do not count.
        let mut cells = vertical(3);
        cells.extend([(29, 6), (29, 7), (10, 0), (10, 1), (10, 2), (10, 3)]);
        assert!((tip_height(&f, &e, &flag(&e, &cells)) - 0.125).abs() < 1e-12);
    }

    #[test]
    fn tip_speed_from_a_steady_crack_and_a_closing_one() {
        // Tip rising at 1000 m/s, sampled every 20 us: every window gives 1000 m/s.
        let t: Vec<f64> = (0..10).map(|i| i as f64 * 2e-5).collect();
        let h: Vec<f64> = t.iter().map(|t| 1000.0 * t).collect();
        for (_, _, v) in tip_speeds(&t, &h) {
            assert!((v - 1000.0).abs() < 1e-6);
        }
        // A crack that reaches 0.3 m then closes: the height reached stays 0.3, speed 0.
        let h = [0.0, 0.1, 0.2, 0.3, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        let s = tip_speeds(&t, &h);
        assert!(s[4..].iter().all(|&(_, h, _)| h == 0.3));
        assert_eq!(s[9].2, 0.0);
        // Central 5-point difference at i = 2: (0.3 - 0.0) / 80 us.
        assert!((s[2].2 - 0.3 / 8e-5).abs() < 1e-6);
    }
}
