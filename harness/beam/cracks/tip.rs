//! The bending-crack tip: its height in one state, from the elements' crack openings, and its
//! speed over the snapshots of a run.
//!
//! The smeared crack indicator `eps_1 / eps_r` is no tip: a column of elements strained
//! elastically ahead of the crack crosses `eps_r` almost at once, and its front moved faster
//! than the Rayleigh speed. The tip here follows the crack *opening* `w` of each element (the
//! crack band's inelastic strain times its width, `Model::crack_openings`), which an element
//! only has once it softens.

use impact_solver::model::Problem;

use super::{beam_elements, BeamElement, BeamFrame, BeamSpec};

/// The opening that makes an element part of the open crack, as a fraction of the critical
/// opening `w_cr` of the crack indicator: with `w_cr` = 0.2 mm, 0.1 mm, where the calibrated
/// concrete's MC2010 law keeps about 11 % of `f_t` (the same level as the damage zones'
/// `eps_1 / eps_r` = 0.5, `crate::beam::cracks::DAMAGE_LEVEL`).
pub const TIP_OPENING_FRACTION: f64 = 0.5;

/// Time on each side of a snapshot in the tip speed's least-squares line (s): an 80 us window,
/// five of the drop tests' 20 us snapshots. A time, not a count of snapshots, so that finer
/// snapshots sample the same smoothing instead of a shorter one.
pub const TIP_SPEED_HALF_WINDOW: f64 = 4e-5;

/// Height of the bending-crack tip above the bottom face (m) from the elements' openings `w`
/// (m), along the crack path at mid-span:
///
/// 1. the elements within one cell of the loaded strip (`|x - x_load| <= a + c`) and outside
///    the loading region are binned in layers of one cell height by their centroid;
/// 2. each layer's opening is the largest of its elements (the crack path is where the strip
///    opens most, wherever it wanders within the strip);
/// 3. from the bottom layer up, the tip is where the layer openings first fall below `w_tip`,
///    interpolated linearly between the centres of the last open layer and the next (so a
///    crack whose opening falls linearly with height, as a hinge's does, is located exactly);
///    0 when the bottom layer is not open, the top layer's centre when every layer is.
pub fn tip_height(frame: &BeamFrame, elements: &[BeamElement], opening: &[f64], w_tip: f64) -> f64 {
    let layers = ((frame.height / frame.cell).round() as usize).max(1);
    let layer_height = frame.height / layers as f64;
    let mut w_layer = vec![f64::NEG_INFINITY; layers];
    for (e, &w) in elements.iter().zip(opening) {
        let c = &e.centroid;
        if (c.x - frame.x_load).abs() > frame.load_half_width + frame.cell
            || frame.in_loading_region(c)
        {
            continue;
        }
        let j = (((c.y - frame.y_bottom) / layer_height).floor().max(0.0) as usize).min(layers - 1);
        w_layer[j] = w_layer[j].max(w);
    }
    let centre = |j: usize| (j as f64 + 0.5) * layer_height;
    if !(w_layer[0] >= w_tip) {
        return 0.0;
    }
    for j in 1..layers {
        let (below, here) = (w_layer[j - 1], w_layer[j]);
        if !(here >= w_tip) {
            // A layer with no element in the strip (the loading region) closes the path.
            let f = if here.is_finite() {
                (below - w_tip) / (below - here)
            } else {
                0.0
            };
            return centre(j - 1) + f * layer_height;
        }
    }
    centre(layers - 1)
}

/// `(t, height, speed)` from tip heights at times: `height` is the highest the tip has reached
/// so far (the running maximum, so that a crack closing elastically does not count as a tip
/// moving back), `speed` the slope of the least-squares line through the heights reached at the
/// snapshots within [`TIP_SPEED_HALF_WINDOW`] of it (the window cut at the ends).
///
/// A tip exists from the first snapshot with a crack (height above 0, the *initiation*) on: the
/// window is cut there too and the speed before it is 0. A crack that appears over several cell
/// layers within one snapshot (the drop tests' lowest 0.1-0.15 m at mid-span, strained past the
/// strength all at once) has no tip moving across that length: a line through the zeros before
/// it would turn the length it appears with into a speed (0.15 m within 20 us reads 2250 m/s,
/// above c_R, whatever the crack does after). The thesis' Fig. 10.19 likewise starts its speeds
/// "after crack initiation"; the length the crack appears with is [`initiation`]'s.
pub fn tip_speeds(times: &[f64], heights: &[f64]) -> Vec<(f64, f64, f64)> {
    let mut reached = Vec::with_capacity(heights.len());
    let mut best: f64 = 0.0;
    for h in heights {
        best = best.max(*h);
        reached.push(best);
    }
    let n = times.len();
    let start = reached.iter().position(|&h| h > 0.0).unwrap_or(n);
    (0..n)
        .map(|i| {
            if i < start {
                return (times[i], reached[i], 0.0);
            }
            // Snapshot times carry the step's rounding: a 1e-9 relative margin keeps the
            // snapshots 2 x 20 us away inside.
            let reach = TIP_SPEED_HALF_WINDOW * (1.0 + 1e-9);
            // The times ascend: both ends by bisection.
            let first = start + times[start..i].partition_point(|&t| times[i] - t > reach);
            let last = i + times[i + 1..].partition_point(|&t| t - times[i] <= reach);
            let window = first..last + 1;
            let m = window.len() as f64;
            let t_mean = times[window.clone()].iter().sum::<f64>() / m;
            let h_mean = reached[window.clone()].iter().sum::<f64>() / m;
            let (mut sth, mut stt) = (0.0, 0.0);
            for k in window {
                sth += (times[k] - t_mean) * (reached[k] - h_mean);
                stt += (times[k] - t_mean) * (times[k] - t_mean);
            }
            let speed = if stt > 0.0 { sth / stt } else { 0.0 };
            (times[i], reached[i], speed)
        })
        .collect()
}

/// The crack's initiation in a tip history of [`tip_speeds`]: the time of the first snapshot
/// with a crack and the height the crack has there, `None` when no crack opens.
pub fn initiation(tip: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    tip.iter().find(|p| p.1 > 0.0).map(|p| (p.0, p.1))
}

/// The bending-crack tip over the snapshots of a run: `(t, height reached (m), speed (m/s))`
/// (see [`tip_height`], with `w_tip = TIP_OPENING_FRACTION w_cr`, and [`tip_speeds`]).
pub fn crack_tip_history(
    problem: &Problem,
    snapshots: &[impact_solver::dynamics::Snapshot],
    spec: &BeamSpec,
) -> Result<Vec<(f64, f64, f64)>, String> {
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    let range = beam_elements(problem, spec)?;
    let w_tip = TIP_OPENING_FRACTION * problem.model.crack_indicator.crack_width;
    let mut times = Vec::with_capacity(snapshots.len());
    let mut heights = Vec::with_capacity(snapshots.len());
    for s in snapshots {
        let Some(w) = s.crack_opening.get(range.clone()) else {
            return Err(format!(
                "the snapshots hold no crack openings for body `{}`: only a body whose \
                 material keeps a history (microplane concrete) can open a crack",
                spec.body
            ));
        };
        let opening: Vec<f64> = w.iter().map(|&w| f64::from(w)).collect();
        times.push(s.time);
        heights.push(tip_height(&frame, &elements, &opening, w_tip));
    }
    Ok(tip_speeds(&times, &heights))
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::{frame, grid};
    use super::*;

    /// Openings of a crack at mid-span (columns 28..32, the strip and its neighbours) falling
    /// linearly with height from `w0` at the bottom face to 0 at `top` (m), as a hinge's do.
    fn hinge_openings(
        e: &[BeamElement],
        w0: f64,
        top: f64,
        columns: std::ops::Range<usize>,
    ) -> Vec<f64> {
        e.iter()
            .map(|el| {
                let column = (el.centroid.x / 0.05) as usize;
                if columns.contains(&column) {
                    (w0 * (1.0 - el.centroid.y / top)).max(0.0)
                } else {
                    0.0
                }
            })
            .collect()
    }

    #[test]
    fn tip_of_a_linear_opening_profile_is_exact() {
        let e = grid(60, 12, 0.05);
        let f = frame();
        assert_eq!(tip_height(&f, &e, &vec![0.0; e.len()], 1e-4), 0.0);
        // w = 0.4 mm (1 - y / 0.35): w = 0.1 mm at y = 0.2625 m.
        let w = hinge_openings(&e, 4e-4, 0.35, 28..32);
        assert!((tip_height(&f, &e, &w, 1e-4) - 0.2625).abs() < 1e-12);
        // An opening outside the strip (column 10) does not count.
        let w = hinge_openings(&e, 4e-4, 0.35, 8..12);
        assert_eq!(tip_height(&f, &e, &w, 1e-4), 0.0);
    }

    #[test]
    fn a_crack_driven_at_a_prescribed_speed_is_tracked_at_that_speed() {
        // The opening profile of a hinge, w = g (top - y), whose zero-opening point rises at
        // 800 m/s from 0.2 m, snapshots every 20 us: the tip at w_tip = 0.1 mm rises at 800 m/s
        // too, from 0.2 - 0.1 mm / g = 0.1125 m.
        let e = grid(60, 12, 0.05);
        let f = frame();
        let slope = 4e-4 / 0.35;
        let times: Vec<f64> = (0..12).map(|i| i as f64 * 2e-5).collect();
        let heights: Vec<f64> = times
            .iter()
            .map(|t| {
                let top = 0.2 + 800.0 * t;
                let w = hinge_openings(&e, slope * top, top, 28..32);
                tip_height(&f, &e, &w, 1e-4)
            })
            .collect();
        for (t, h, v) in tip_speeds(&times, &heights) {
            assert!((h - (0.1125 + 800.0 * t)).abs() < 1e-12, "{t} {h}");
            assert!((v - 800.0).abs() < 1e-6 * 800.0, "{t} {h} {v}");
        }
    }

    #[test]
    fn tip_speed_from_a_steady_crack_and_a_closing_one() {
        // Tip rising at 1000 m/s from 0 at t = 0, sampled every 20 us: no tip at t = 0, every
        // later window gives 1000 m/s.
        let t: Vec<f64> = (0..10).map(|i| i as f64 * 2e-5).collect();
        let h: Vec<f64> = t.iter().map(|t| 1000.0 * t).collect();
        let s = tip_speeds(&t, &h);
        assert_eq!(s[0].2, 0.0);
        for (_, _, v) in &s[1..] {
            assert!((v - 1000.0).abs() < 1e-6);
        }
        // A crack that reaches 0.3 m then closes: the height reached stays 0.3, speed 0.
        let h = [0.0, 0.1, 0.2, 0.3, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        let s = tip_speeds(&t, &h);
        assert!(s[4..].iter().all(|&(_, h, _)| h == 0.3));
        assert_eq!(s[9].2, 0.0);
        // Least-squares slope at i = 2 over heights 0.1, 0.2, 0.3, 0.3 at 20..80 us (the window
        // cut at the initiation, i = 1): t - t_mean = -1.5, -0.5, 0.5, 1.5 snapshots.
        let expected = (-1.5 * 0.1 - 0.5 * 0.2 + 0.5 * 0.3 + 1.5 * 0.3) / (5.0 * 2e-5);
        assert!(
            (s[2].2 - expected).abs() < 1e-6 * expected,
            "{} {expected}",
            s[2].2
        );
    }

    #[test]
    fn the_speed_window_is_a_time_whatever_the_snapshots() {
        // A tip rising as h = a t^3. The least-squares slope over snapshots at offsets u_k
        // symmetric about t is 3 a t^2 + a sum(u^4) / sum(u^2): at 20 us and at 2.5 us the
        // offsets must span the same +-40 us (a window of five 2.5 us snapshots, +-5 us, would
        // read 3 a t^2 + 21 a us^2 instead).
        let a = 1e11;
        let check = |dt: f64, n: usize| {
            let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
            let h: Vec<f64> = t.iter().map(|t| a * t * t * t).collect();
            let s = tip_speeds(&t, &h);
            let half = (TIP_SPEED_HALF_WINDOW / dt).round() as i64;
            let u: Vec<f64> = (-half..=half).map(|k| k as f64 * dt).collect();
            let m4 =
                u.iter().map(|u| u.powi(4)).sum::<f64>() / u.iter().map(|u| u * u).sum::<f64>();
            let centre = half as usize + 1;
            for &(t, _, v) in &s[centre..n - half as usize] {
                let expected = 3.0 * a * t * t + a * m4;
                assert!(
                    (v - expected).abs() < 1e-7 * expected,
                    "dt {dt}: {t} {v} {expected}"
                );
            }
        };
        check(2e-5, 16);
        check(2.5e-6, 121);
    }

    #[test]
    fn a_crack_appearing_over_several_layers_is_an_initiation_not_a_speed() {
        // 0.15 m of crack within one 20 us snapshot, then a tip rising at 600 m/s: the speed is
        // the tip's, 600 m/s, at every snapshot from the initiation on (a line through the
        // zeros before it would read 0.3 * 0.15 m / 20 us = 2250 m/s at the initiation).
        let t: Vec<f64> = (0..10).map(|i| i as f64 * 2e-5).collect();
        let h: Vec<f64> = t
            .iter()
            .map(|&t| {
                if t < 5e-5 {
                    0.0
                } else {
                    0.15 + 600.0 * (t - 6e-5)
                }
            })
            .collect();
        let s = tip_speeds(&t, &h);
        assert!(s[..3].iter().all(|p| p.2 == 0.0));
        for (_, _, v) in &s[3..] {
            assert!((v - 600.0).abs() < 1e-6 * 600.0, "{v}");
        }
        let (t0, h0) = initiation(&s).unwrap();
        assert_eq!(t0, t[3]);
        assert!((h0 - 0.15).abs() < 1e-12);
        assert_eq!(initiation(&tip_speeds(&t, &[0.0; 10])), None);
    }
}
