//! Synthetic crack histories on a side-view grid of 50 mm cells (60 x 12, the fixtures' beam):
//! each test prescribes when which element opens and checks what the measure reads.

use super::super::fixtures::{frame, grid};
use super::path::face_neighbours;
use super::*;

const CELL: f64 = 0.05;
/// Snapshot interval of the drop tests' refined snapshots (s).
const DT: f64 = 2.5e-6;
/// Openings of the two tips in these tests (m): `w_p` and `w_cr / 2`.
const W_P: f64 = 1e-5;
const W_TF: f64 = 1e-4;
/// Rayleigh and dilatational speeds of the thesis concrete (m/s).
const C_R: f64 = 2134.0;
const C_P: f64 = 3763.0;

/// Row-major index of cell `(i, j)` (column, row) of the 60-column grid.
fn at(i: usize, j: usize) -> usize {
    j * 60 + i
}

/// The four face neighbours of each cell of the grid (a side view of a column of elements).
fn grid_path() -> CrackPath {
    let elements = grid(60, 12, CELL);
    let neighbours = (0..elements.len())
        .map(|e| {
            let (i, j) = (e % 60, e / 60);
            let mut n = Vec::new();
            if i > 0 {
                n.push(at(i - 1, j));
            }
            if i < 59 {
                n.push(at(i + 1, j));
            }
            if j > 0 {
                n.push(at(i, j - 1));
            }
            if j < 11 {
                n.push(at(i, j + 1));
            }
            n
        })
        .collect();
    CrackPath::new(&frame(), &elements, neighbours)
}

/// Height of the centroid of row `j` (m).
fn row(j: usize) -> f64 {
    (j as f64 + 0.5) * CELL
}

/// The report of `n` snapshots every [`DT`] whose openings `w(t, column, row)` are prescribed.
fn report(n: usize, w: impl Fn(f64, usize, usize) -> f64) -> CrackTipReport {
    let path = grid_path();
    let times: Vec<f64> = (0..n).map(|k| k as f64 * DT).collect();
    let openings = times.iter().map(|&t| {
        Ok((0..path.height.len())
            .map(|e| w(t, e % 60, e / 60))
            .collect::<Vec<f64>>())
    });
    let track = track(&path, &times, openings, W_P, W_TF).unwrap();
    let speeds = WaveSpeeds {
        rayleigh: C_R,
        dilatational: C_P,
    };
    CrackTipReport::of(&track, speeds, CELL, W_P, W_TF)
}

/// `v` is within the reading's resolution of every window's speed.
fn assert_speed_within_resolution(r: &TipReading, v: f64) {
    let w = r.fastest.expect("a speed window");
    assert!(
        (w.speed - v).abs() <= w.resolution,
        "fastest {} m/s, resolution {} m/s, expected {v} m/s",
        w.speed,
        w.resolution
    );
}

#[test]
fn face_neighbours_share_three_nodes() {
    use crate::beam::cracks::BeamElement;
    use impact_solver::Vector3;
    let el = |nodes| BeamElement {
        centroid: Vector3::zeros(),
        nodes,
    };
    // 0 and 1 share the face {1, 2, 3}, 0 and 2 the face {0, 1, 2}; 1 and 2 only an edge.
    let n = face_neighbours(&[el([0, 1, 2, 3]), el([3, 2, 1, 4]), el([2, 0, 5, 1])]);
    assert_eq!(n, vec![vec![1, 2], vec![0], vec![0]]);
}

#[test]
fn opening_at_a_fraction_of_the_strength() {
    // A linear law from f_t at w = 0 to 0 at 0.2 mm falls to 0.9 f_t at 0.02 mm; with a
    // plateau up to 5 um first (the pre-peak opening the crack band lumps at f_t), at 5 um +
    // 0.1 of the remaining 0.2 mm.
    let (ft, wc) = (2.7e6, 2e-4);
    let w = [0.0, wc];
    assert!((opening_at_stress_fraction(&w, &[ft, 0.0], 0.9).unwrap() - 0.1 * wc).abs() < 1e-15);
    let w = [0.0, 5e-6, 5e-6 + wc];
    let s = [ft, ft, 0.0];
    assert!((opening_at_stress_fraction(&w, &s, 0.9).unwrap() - (5e-6 + 0.1 * wc)).abs() < 1e-15);
    // A law that never softens gives none.
    assert_eq!(
        opening_at_stress_fraction(&[0.0, 1.0], &[ft, ft], 0.9),
        None
    );
}

#[test]
fn a_tip_at_a_known_speed_is_recovered_within_the_resolution() {
    // A hinge-like profile at mid-span (column 29): w = s (y_f(t) - y), its zero point y_f
    // rising at 800 m/s from 0.05 m. Each tip is a level line of it and moves at 800 m/s.
    let (v, s) = (800.0, 1e-3);
    let r = report(220, |t, i, j| {
        if i == 29 {
            (s * (0.05 + v * t - row(j))).max(0.0)
        } else {
            0.0
        }
    });
    for reading in [&r.cohesive_speed, &r.traction_free_speed] {
        assert_eq!(reading.status, TipStatus::Pass, "{reading:?}");
        assert_speed_within_resolution(reading, v);
        // Windows span three cells: at 800 m/s about 190 us, a resolution near 270 m/s.
        let w = reading.fastest.unwrap();
        assert!(w.advance >= 3.0 * CELL * (1.0 - 1e-9));
        assert!((w.resolution - CELL / (w.end - w.start)).abs() < 1e-9);
    }
    assert_eq!(r.coalescence_length, 0.0);
    // The traction-free crack appears when w at the bottom row reaches w_tf: y_f = 0.125 m.
    // The cohesive tip is then the highest row with y <= y_f - w_p / s = 0.115 m: row 1.
    let i = r.initiation.unwrap();
    assert!((i.length - row(1)).abs() < 1e-12, "{i:?}");
    assert!((i.traction_free_height - row(0)).abs() < 1e-12, "{i:?}");
}

#[test]
fn a_column_opening_at_once_is_coalescence_not_a_fast_tip() {
    // Rows 5..=7 of the mid-span column open (past w_cr / 2) at 20 us, all at once and joined
    // to nothing; the bending crack rises from the bottom at 400 m/s and reaches row 4 at
    // 0.225 / 400 = 562.5 us, where the column joins it within one snapshot: 0.15 m in 2.5 us
    // (60 km/s) if it were read as a tip.
    let v = 400.0;
    let r = report(560, |t, i, j| {
        let column = i == 29 && (5..=7).contains(&j) && t >= 20e-6;
        let crack = i == 29 && t >= row(j) / v;
        if column || crack {
            2e-4
        } else {
            0.0
        }
    });
    assert_eq!(r.coalesced_elements, 3);
    // Three rows of 0.05 m joined by coalescence.
    assert!(
        (r.coalescence_length - 0.15).abs() < 1e-12,
        "{}",
        r.coalescence_length
    );
    for reading in [&r.cohesive_speed, &r.traction_free_speed] {
        let fastest = reading.fastest.unwrap();
        assert!(fastest.speed < C_R, "{reading:?}");
        assert_eq!(reading.status, TipStatus::Pass, "{reading:?}");
    }
    // Both tips reached the top of the column (row 9 opens at 0.475 / 400 s).
    let last = r.cohesive.last().unwrap();
    assert!((last - row(9)).abs() < 1e-12, "{last}");
}

#[test]
fn only_the_crack_connected_to_mid_span_bottom_counts() {
    // The bending crack in column 29 rises at 600 m/s; a second crack in column 26 (x = 1.325,
    // inside the old 400 mm strip) rises at 5000 m/s to row 9. A per-layer maximum over the
    // strip would follow the second one.
    let r = report(300, |t, i, j| {
        let bending = i == 29 && t >= row(j) / 600.0;
        let other = i == 26 && j <= 9 && t >= row(j) / 5000.0;
        if bending || other {
            2e-4
        } else {
            0.0
        }
    });
    for reading in [&r.cohesive_speed, &r.traction_free_speed] {
        assert_eq!(reading.status, TipStatus::Pass, "{reading:?}");
        assert_speed_within_resolution(reading, 600.0);
    }
    // At the last snapshot (747.5 us) the bending crack has reached 0.4485 m: row 8.
    assert!((r.cohesive.last().unwrap() - row(8)).abs() < 1e-12);
    assert_eq!(r.coalescence_length, 0.0);
}

#[test]
fn an_initiation_sweep_is_not_propagation() {
    // A process zone of rows 0..=4 (w_p <= w < w_cr / 2) is there from the start. The
    // traction-free front sweeps it at 6000 m/s (above c_R by more than the resolution of
    // its 25 us windows) from 40 us, then both tips rise
    // at 500 m/s, the cohesive one 20 us ahead.
    let sweep_end = 40e-6 + row(4) / 6000.0;
    let free = |j: usize| {
        if j <= 4 {
            40e-6 + row(j) / 6000.0
        } else {
            sweep_end + (row(j) - row(4)) / 500.0
        }
    };
    let r = report(400, |t, i, j| {
        if i != 29 {
            0.0
        } else if t >= free(j) {
            2e-4
        } else if j <= 4 || t >= free(j) - 20e-6 {
            2e-5
        } else {
            0.0
        }
    });
    // The traction-free crack appears in the bottom row at 44.2 us (the snapshot at 45 us), when the cohesive tip is
    // at row 4: the initiation length.
    let i = r.initiation.unwrap();
    assert!((i.length - row(4)).abs() < 1e-12, "{i:?}");
    assert!((i.traction_free_height - row(0)).abs() < 1e-12, "{i:?}");
    assert_eq!(r.traction_free_speed.status, TipStatus::Pass);
    assert_speed_within_resolution(&r.traction_free_speed, 500.0);
    // Read from its appearance on, the same traction-free history fails on the sweep.
    let from = r.traction_free.iter().position(|h| h.is_finite()).unwrap();
    let raw = TipReading::of(&r.times[from..], &r.traction_free[from..], CELL, C_R);
    assert_eq!(raw.status, TipStatus::Fail, "{raw:?}");
}

#[test]
fn no_tip_is_its_own_status() {
    // No crack at all.
    let r = report(50, |_, _, _| 0.0);
    assert_eq!(r.cohesive_speed.status, TipStatus::NoTip);
    assert_eq!(r.traction_free_speed.status, TipStatus::NoTip);
    assert!(r.initiation.is_none());
    // A crack appearing 10 rows tall at once that never grows: nothing propagates.
    let r = report(50, |t, i, j| {
        if i == 29 && j <= 9 && t >= 20e-6 {
            2e-4
        } else {
            0.0
        }
    });
    assert_eq!(r.cohesive_speed.status, TipStatus::NoTip);
    assert_eq!(r.traction_free_speed.status, TipStatus::NoTip);
    assert!((r.initiation.unwrap().length - row(9)).abs() < 1e-12);
}

#[test]
fn a_reading_within_its_resolution_of_c_r_is_inconclusive() {
    // Windows of 3 cells: h / T is the resolution of each.
    let window = |speed, t: f64| SpeedWindow {
        start: 0.0,
        end: t,
        advance: 0.15,
        speed,
        resolution: 0.05 / t,
    };
    // 100 us windows: resolution 500 m/s.
    assert_eq!(window_status(&window(1600.0, 1e-4), C_R), TipStatus::Pass);
    assert_eq!(
        window_status(&window(1700.0, 1e-4), C_R),
        TipStatus::Inconclusive
    );
    assert_eq!(
        window_status(&window(2600.0, 1e-4), C_R),
        TipStatus::Inconclusive
    );
    assert_eq!(window_status(&window(2700.0, 1e-4), C_R), TipStatus::Fail);
    let statuses = |speeds: &[f64]| {
        let w: Vec<SpeedWindow> = speeds.iter().map(|&v| window(v, 1e-4)).collect();
        reading_status(&w, C_R)
    };
    assert_eq!(statuses(&[1000.0, 1600.0]), TipStatus::Pass);
    assert_eq!(statuses(&[1000.0, 2000.0]), TipStatus::Inconclusive);
    assert_eq!(statuses(&[2000.0, 3000.0]), TipStatus::Fail);
    assert_eq!(statuses(&[]), TipStatus::NoTip);
}

#[test]
fn a_report_reads_back_from_json_with_its_missing_heights() {
    // Heights before a tip exists are NaN, which JSON writes as null: a report rebuilt from
    // results.json must still read the record.
    let r = report(30, |t, i, j| {
        if i == 29 && j == 0 && t >= 20e-6 {
            2e-4
        } else {
            0.0
        }
    });
    assert!(r.cohesive[0].is_nan() && r.cohesive[29].is_finite());
    let back: CrackTipReport = serde_json::from_str(&serde_json::to_string(&r).unwrap()).unwrap();
    assert!(back.cohesive[0].is_nan());
    assert_eq!(back.cohesive[29], r.cohesive[29]);
    assert_eq!(back.initiation, r.initiation);
    assert_eq!(back.cohesive_speed, r.cohesive_speed);
}

/// Depth of the centroid of row `j` below the top face (m).
fn depth(j: usize) -> f64 {
    0.6 - row(j)
}

/// The damage-front quantity of a report, with its verdict.
fn damage_front_read(r: &CrackTipReport) -> (f64, measure::SpeedVerdict) {
    let m = CrackTipMeasure {
        quantity: CrackTipQuantity::DamageFrontSpeedRatio,
        beam: Default::default(),
    };
    let (v, reading) = m.read(r);
    (v, reading.expect("the damage front carries a verdict"))
}

#[test]
fn a_wave_driven_damage_front_below_c_p_passes() {
    // Splitting under the load: the two mid-span columns (29 and 30) pass w_p top-down at
    // 2000 m/s from row 9 (rows 10 and 11 are the loading region) to row 1, joined to no
    // crack (the bottom row, where the bending crack starts, stays closed).
    let v = 2000.0;
    let r = report(200, |t, i, j| {
        if (i == 29 || i == 30) && (1..=9).contains(&j) && t >= 20e-6 + (depth(j) - depth(9)) / v {
            2e-5
        } else {
            0.0
        }
    });
    assert_eq!(r.damage_front_speed.status, TipStatus::Pass, "{r:?}");
    // Advance over the window: the least-squares slope of a staircase is v within h/T.
    let w = r.damage_front_speed.fastest.unwrap();
    assert!((w.speed - v).abs() <= w.resolution, "{w:?}");
    assert!((r.damage_front.last().unwrap() - depth(1)).abs() < 1e-12);
    // The pre-damaged column reaches up to row 9, the first below the loading region.
    assert!((r.damage_shallowest - depth(9)).abs() < 1e-12, "{r:?}");
    let (ratio, verdict) = damage_front_read(&r);
    assert!(verdict.pass, "{}", verdict.text);
    assert!((ratio - w.speed / C_P).abs() < 1e-12);
    // Not a bending crack: nothing at the bottom of mid-span connects it.
    assert_eq!(r.cohesive_speed.status, TipStatus::NoTip);
}

#[test]
fn a_column_opening_at_once_runs_ahead_of_the_wave() {
    // Rows 3..=9 of column 29 pass w_p in one snapshot: 0.3 m of column in 2.5 us
    // (120 km/s, 32 c_p), a state released at once, which no wave drives.
    let r = report(40, |t, i, j| {
        if i == 29 && (3..=9).contains(&j) && t >= 20e-6 {
            2e-5
        } else {
            0.0
        }
    });
    assert_eq!(r.damage_front_speed.status, TipStatus::Fail, "{r:?}");
    let (ratio, verdict) = damage_front_read(&r);
    assert!(!verdict.pass, "{}", verdict.text);
    assert!(ratio > 10.0, "{ratio}");
    // One element alone opening deep in the column is no front moving.
    let r = report(40, |t, i, j| {
        if i == 29 && j == 3 && t >= 20e-6 {
            2e-5
        } else {
            0.0
        }
    });
    let (ratio, verdict) = damage_front_read(&r);
    assert!((r.damage_shallowest - depth(3)).abs() < 1e-12, "{r:?}");
    // A front that does not move: speed zero to round-off over the whole record.
    assert_eq!(r.damage_front_speed.status, TipStatus::Pass);
    assert!(ratio.abs() < 1e-12, "{ratio}");
    assert!(verdict.pass, "{}", verdict.text);
}

#[test]
fn the_bending_crack_rising_into_the_column_is_no_damage_front() {
    // The crack rises from mid-span's bottom at 600 m/s through column 29 up to row 9:
    // every column element it opens joins the crack in the snapshot it passes w_p.
    let r = report(400, |t, i, j| {
        if i == 29 && j <= 9 && t >= row(j) / 600.0 {
            2e-4
        } else {
            0.0
        }
    });
    assert!(r.damage_front.iter().all(|d| d.is_nan()));
    assert!(r.damage_shallowest.is_nan());
    let (ratio, verdict) = damage_front_read(&r);
    assert_eq!(ratio, 0.0);
    assert!(verdict.pass, "{}", verdict.text);
    assert!(verdict.text.contains("no pre-damage front"));
}

#[test]
fn a_report_written_before_the_damage_front_reads_back() {
    let r = report(30, |_, _, _| 0.0);
    let mut json: serde_json::Value = serde_json::to_value(&r).unwrap();
    let record = json.as_object_mut().unwrap();
    for key in [
        "dilatational_speed",
        "damage_front",
        "damage_front_speed",
        "damage_shallowest",
    ] {
        assert!(record.remove(key).is_some(), "{key}");
    }
    let back: CrackTipReport = serde_json::from_value(json).unwrap();
    assert!(back.dilatational_speed.is_nan());
    assert!(back.damage_shallowest.is_nan());
    assert!(back.damage_front.is_empty());
    assert_eq!(back.damage_front_speed.status, TipStatus::NoTip);
}

#[test]
fn a_crack_reaching_an_element_by_its_corner_is_propagation() {
    // The crack rises in column 29 at 400 m/s to row 3 (0.175 m at 437.5 us). Element
    // (30, 4), which touches (29, 3) only at a corner, passes w_p 10 us after (29, 3) did,
    // before either of its face neighbours (29, 4) and (30, 3): the crack's own front reached
    // it across the corner, and nothing is coalescence. (29, 4) opens 20 us later and joins.
    let v = 400.0;
    // The crack, (29, 4) above it, and (30, 4) opening at `corner_opens`.
    let with_corner_at = |corner_opens: f64| {
        report(240, move |t, i, j| {
            let crack = i == 29 && j <= 3 && t >= row(j) / v;
            let corner = i == 30 && j == 4 && t >= corner_opens;
            let above = i == 29 && j == 4 && t >= row(3) / v + 30e-6;
            if crack || corner || above {
                2e-5
            } else {
                0.0
            }
        })
    };
    let r = with_corner_at(row(3) / v + 10e-6);
    assert_eq!(r.coalesced_elements, 0, "{r:?}");
    assert_eq!(r.coalescence_length, 0.0);
    // Both (30, 4) and (29, 4) are in the crack at the end: its tip is row 4.
    assert!((r.cohesive.last().unwrap() - row(4)).abs() < 1e-12);
    // The same element opened at 100 us, when the crack is still in row 0 and nothing of it
    // touches the element, is pre-damage joined by coalescence.
    let r = with_corner_at(100e-6);
    assert_eq!(r.coalesced_elements, 1, "{r:?}");
}
