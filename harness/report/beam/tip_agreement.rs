//! Whether the drop cases at one impact velocity agree on the crack-tip speeds within their
//! resolution: two readings `v_a +- r_a` and `v_b +- r_b` (the fastest windows, over `c_R`)
//! agree when `|v_a - v_b| <= r_a + r_b`. The meshes (structured, Gmsh, 25 mm; the seeds and
//! supports beside them) must not tell different speeds apart from what their cells resolve.
//! The ratio to the thesis's 0.55 `c_R` is given for information.

use super::FailureRow;
use crate::beam::cracks::{CrackTipReport, TipReading};
use crate::report::format::num;

/// The thesis's crack speed over `c_R` (10.3.2), for information only.
pub const THESIS_TIP_SPEED: f64 = 0.55;

/// Pairs named in a line that says the cases disagree; the rest are counted.
const SHOWN_PAIRS: usize = 3;

/// Which of a report's two tip readings a line is about.
type TipOf = fn(&CrackTipReport) -> &TipReading;

/// A case's fastest window over `c_R`: `(case, v, r)`.
type Reading = (String, f64, f64);

/// Whether every pair of `readings` agrees within resolution, and the pairs that do not.
fn disagreeing(readings: &[Reading]) -> Vec<(&Reading, &Reading)> {
    let mut out = Vec::new();
    for (i, a) in readings.iter().enumerate() {
        for b in &readings[i + 1..] {
            if (a.1 - b.1).abs() > a.2 + b.2 {
                out.push((a, b));
            }
        }
    }
    out
}

/// One line per impact velocity and tip (`cohesive`, `traction-free`): the readings of every
/// case at that velocity with a window, whether they agree within resolution, their range over
/// the thesis's 0.55 `c_R`, and the cases with no tip.
pub fn agreement_lines(rows: &[FailureRow<'_>]) -> Vec<String> {
    let mut speeds: Vec<f64> = rows.iter().filter_map(|r| r.record.speed).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let tips: [(&str, TipOf); 2] = [
        ("cohesive", |t| &t.cohesive_speed),
        ("traction-free", |t| &t.traction_free_speed),
    ];
    let mut lines = Vec::new();
    for v in speeds {
        for (name, reading) in tips {
            let mut readings: Vec<Reading> = Vec::new();
            let mut no_tip: Vec<String> = Vec::new();
            for r in rows.iter().filter(|r| r.record.speed == Some(v)) {
                let Some(t) = &r.record.crack_tip else {
                    continue;
                };
                let id = r.case.id.trim_start_matches("beam/").to_string();
                let id = if r.case.variant == "default" || r.case.variant.is_empty() {
                    id
                } else {
                    format!("{id} [{}]", r.case.variant)
                };
                match reading(t).fastest {
                    Some(w) => readings.push((
                        id,
                        w.speed / t.rayleigh_speed,
                        w.resolution / t.rayleigh_speed,
                    )),
                    None => no_tip.push(id),
                }
            }
            if readings.is_empty() && no_tip.is_empty() {
                continue;
            }
            lines.push(line(v, name, &readings, &no_tip));
        }
    }
    lines
}

/// The line of one velocity and tip.
fn line(v: f64, tip: &str, readings: &[Reading], no_tip: &[String]) -> String {
    let list: Vec<String> = readings
        .iter()
        .map(|(id, s, r)| format!("{id} {} ± {}", num(round2(*s)), num(round2(*r))))
        .collect();
    let mut text = format!("{} m/s, {tip} tip (over c_R): ", num(v));
    if readings.len() < 2 {
        text.push_str(&format!(
            "{}fewer than two cases with a window to compare",
            if list.is_empty() {
                String::new()
            } else {
                format!("{}; ", list.join(", "))
            }
        ));
    } else {
        let bad = disagreeing(readings);
        let (lo, hi) = readings
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r.1), hi.max(r.1))
            });
        text.push_str(&format!(
            "{}: {}; {}-{} times the thesis's 0.55 (for information)",
            list.join(", "),
            if bad.is_empty() {
                "the cases agree within resolution".to_string()
            } else {
                let pairs: Vec<String> = bad
                    .iter()
                    .take(SHOWN_PAIRS)
                    .map(|(a, b)| format!("{} and {}", a.0, b.0))
                    .collect();
                let more = if bad.len() > SHOWN_PAIRS {
                    format!(" ({} pairs in all)", bad.len())
                } else {
                    String::new()
                };
                format!("NOT within resolution: {}{more}", pairs.join("; "))
            },
            num(round2(lo / THESIS_TIP_SPEED)),
            num(round2(hi / THESIS_TIP_SPEED)),
        ));
    }
    if !no_tip.is_empty() {
        text.push_str(&format!("; no tip: {}", no_tip.join(", ")));
    }
    text.push('.');
    text
}

/// Two decimals, as the readings' resolution (a quarter of `c_R` and more) warrants.
fn round2(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(id: &str, v: f64, r: f64) -> Reading {
        (id.to_string(), v, r)
    }

    #[test]
    fn readings_agree_when_their_resolutions_overlap() {
        // The 2 m/s readings of the three meshes: 0.70 +- 0.24, 0.86 +- 0.25, 1.18 +- 0.30.
        let meshes = [
            reading("drop-2ms", 0.70, 0.24),
            reading("drop-2ms-gmsh", 0.86, 0.25),
            reading("drop-2ms-h25", 1.18, 0.30),
        ];
        assert!(disagreeing(&meshes).is_empty());
        let text = line(2.0, "cohesive", &meshes, &[]);
        assert!(text.contains("the cases agree within resolution"), "{text}");
        assert!(text.contains("1.27-2.15 times the thesis's 0.55"), "{text}");
        // A release read at 9 c_R does not agree with a tip at 0.7.
        let apart = [reading("a", 0.70, 0.24), reading("b", 9.06, 3.02)];
        assert_eq!(disagreeing(&apart).len(), 1);
    }

    #[test]
    fn readings_apart_by_more_than_their_resolutions_disagree() {
        let apart = [
            reading("a", 0.70, 0.24),
            reading("b", 1.90, 0.67),
            reading("c", 1.10, 0.20),
        ];
        let bad = disagreeing(&apart);
        assert_eq!(bad.len(), 1);
        assert_eq!((bad[0].0 .0.as_str(), bad[0].1 .0.as_str()), ("a", "b"));
        let text = line(4.0, "cohesive", &apart, &["d".into()]);
        assert!(text.contains("NOT within resolution: a and b"), "{text}");
        assert!(text.ends_with("; no tip: d."), "{text}");
        let one = line(8.0, "traction-free", &apart[..1], &["e".into()]);
        assert!(one.contains("fewer than two cases"), "{one}");
    }
}
