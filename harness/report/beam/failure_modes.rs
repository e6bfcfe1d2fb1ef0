//! The "Beam: failure modes" comparison: the beam cases side by side in rows, the monotonic
//! rise of the peak force with velocity, the `failure_mode` metric in words, and its Markdown.

use super::{BeamRecord, FAILURE_MODE_METRIC};
use crate::report::format::{self, num};
use crate::report::summary::code_name;
use crate::results::{CaseResult, RunResults};

/// One case of the failure-mode comparison.
pub struct FailureRow<'a> {
    /// The case's result (id, variant, status, metrics).
    pub case: &'a CaseResult,
    /// What the case recorded for its pictures (crack side views, failure mode).
    pub record: &'a BeamRecord,
    /// The `failure_mode` metric, if the case has one.
    pub metric: Option<&'a crate::results::MetricResult>,
}

/// The beam cases of a run in comparison order: by mesh family (the record's mesh in words),
/// then static ones (no speed) first, then by speed (then by id), so each family's velocities
/// stand side by side. Cases with a refinement sweep are left out: they repeat a velocity on
/// another mesh (their pictures stay in their own section).
pub fn failure_rows<'a>(
    results: &'a RunResults,
    records: &'a [(usize, BeamRecord)],
) -> Vec<FailureRow<'a>> {
    let mut rows: Vec<FailureRow<'a>> = records
        .iter()
        .filter_map(|(i, r)| {
            let case = results.cases.get(*i).filter(|c| c.sweep.is_none())?;
            Some(FailureRow {
                case,
                record: r,
                metric: case.metrics.iter().find(|m| m.name == FAILURE_MODE_METRIC),
            })
        })
        .collect();
    rows.sort_by(|a, b| {
        let key = |r: &FailureRow<'_>| r.record.speed.unwrap_or(-1.0);
        a.record
            .mesh
            .cmp(&b.record.mesh)
            .then_with(|| key(a).total_cmp(&key(b)))
            .then_with(|| a.case.id.cmp(&b.case.id))
    });
    rows
}

/// Whether the peak contact force rises monotonically with the impact velocity on each mesh
/// family (the record's mesh in words), in words with the numbers; `None` without a family of
/// two impact cases with a peak force. Meshes are not compared with each other (a finer or
/// unstructured mesh meets the hammer with another contact stiffness), nor cases at the same
/// velocity on one mesh (variants of one drop, e.g. other supports).
pub fn monotonic_statement(rows: &[FailureRow<'_>]) -> Option<String> {
    monotonic_by_mesh(rows.iter().filter_map(|r| {
        Some((
            r.record.mesh.as_str(),
            r.record.speed?,
            r.record.peak_force?,
        ))
    }))
}

/// [`monotonic_statement`] on `(mesh, velocity, peak force)` points.
fn monotonic_by_mesh<'a>(points: impl Iterator<Item = (&'a str, f64, f64)>) -> Option<String> {
    let mut families: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
    for (mesh, v, f) in points {
        match families.iter_mut().find(|(m, _)| *m == mesh) {
            Some((_, pts)) => pts.push((v, f)),
            None => families.push((mesh, vec![(v, f)])),
        }
    }
    families.retain(|(_, pts)| {
        pts.iter()
            .any(|a| pts.iter().any(|b| b.0 != a.0 && a.0.is_finite()))
    });
    if families.is_empty() {
        return None;
    }
    let falling: Vec<&str> = families
        .iter()
        .filter(|(_, pts)| !rises(pts))
        .map(|(m, _)| *m)
        .collect();
    let lists: Vec<String> = families
        .iter()
        .map(|(mesh, pts)| {
            format!(
                "{}: {}",
                if mesh.is_empty() {
                    "mesh not recorded"
                } else {
                    mesh
                },
                points_text(pts)
            )
        })
        .collect();
    Some(if falling.is_empty() {
        format!(
            "The peak contact force rises monotonically with the impact velocity on every mesh ({}).",
            lists.join("; ")
        )
    } else {
        format!(
            "The peak contact force does NOT rise monotonically with the impact velocity on {} ({}).",
            falling.join(", "),
            lists.join("; ")
        )
    })
}

/// Whether every case at a higher velocity has a higher peak than every case at a lower one.
fn rises(pts: &[(f64, f64)]) -> bool {
    pts.iter()
        .all(|a| pts.iter().all(|b| a.0 >= b.0 || b.1 > a.1))
}

/// `2 m/s: 2298 kN, 8 m/s: 6795 kN`.
fn points_text(pts: &[(f64, f64)]) -> String {
    pts.iter()
        .map(|(v, f)| format!("{} m/s: {} kN", num(*v), num(f / 1e3)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One line per impact velocity: the thesis' mode (the `failure_mode` metric's reference) and
/// the mode each case (mesh family or support) gives at the end of the contact, with whether
/// they all agree with it.
pub fn verdicts(rows: &[FailureRow<'_>]) -> Vec<String> {
    let mut speeds: Vec<f64> = rows.iter().filter_map(|r| r.record.speed).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    speeds
        .into_iter()
        .map(|v| {
            let at: Vec<&FailureRow<'_>> =
                rows.iter().filter(|r| r.record.speed == Some(v)).collect();
            let thesis = at.iter().find_map(|r| {
                let m = r.metric?;
                code_name(&m.reference_source, m.reference)
            });
            let modes: Vec<String> = at
                .iter()
                .map(|r| {
                    let mode = r
                        .record
                        .contact_end
                        .as_ref()
                        .map_or("—", |j| j.mode.as_str());
                    format!("{} {mode}", r.case.id.trim_start_matches("beam/"))
                })
                .collect();
            let agree = thesis.as_ref().is_some_and(|t| {
                at.iter()
                    .all(|r| r.record.contact_end.as_ref().is_some_and(|j| &j.mode == t))
            });
            format!(
                "{} m/s: thesis {}; at the end of the contact: {}: {}.",
                num(v),
                thesis.as_deref().unwrap_or("unknown"),
                modes.join(", "),
                if agree {
                    "every mesh agrees with the thesis"
                } else {
                    "NOT as in the thesis on every mesh"
                }
            )
        })
        .collect()
}

/// The metric in words: `measured mixed (2), expected bending (1): fail` where its reference
/// source names the codes (`code 0 none, 1 bending, ...`); otherwise the numbers and the source.
pub fn metric_text(m: &crate::results::MetricResult) -> String {
    let verdict = if m.pass { "pass" } else { "fail" };
    match (
        code_name(&m.reference_source, m.value),
        code_name(&m.reference_source, m.reference),
    ) {
        (Some(v), Some(r)) => format!(
            "measured {v} ({}), expected {r} ({}): {verdict}",
            num(m.value),
            num(m.reference)
        ),
        _ => {
            let mut t = format!(
                "{} (reference {}, {verdict})",
                num(m.value),
                num(m.reference)
            );
            if !m.reference_source.is_empty() {
                t.push_str(&format!("; {}", m.reference_source));
            }
            t
        }
    }
}

/// The failure-mode comparison in Markdown for `summary.md`; empty without beam pictures.
pub fn markdown(results: &RunResults, records: &[(usize, BeamRecord)]) -> Option<String> {
    let rows = failure_rows(results, records);
    if rows.is_empty() {
        return None;
    }
    let mut md = String::from(
        "| case | velocity (m/s) | peak force (kN) | failure_mode |\n|---|---:|---:|---|\n",
    );
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            format::markdown_cell(&r.case.id),
            r.record.speed.map_or("static".into(), num),
            r.record.peak_force.map_or("—".into(), |f| num(f / 1e3)),
            r.metric
                .map_or("—".into(), |m| format::markdown_cell(&metric_text(m))),
        ));
    }
    if let Some(s) = monotonic_statement(&rows) {
        md.push_str(&format!("\n{s}\n"));
    }
    for line in verdicts(&rows) {
        md.push_str(&format!("\n- {line}"));
    }
    md.push('\n');
    for line in super::tip_agreement::agreement_lines(&rows) {
        md.push_str(&format!("\n- {line}"));
    }
    md.push('\n');
    if let Some(table) = super::column_demand::markdown(&rows) {
        md.push_str(&format!(
            "\n{}\n\n{table}",
            super::column_demand::EXPLANATION
        ));
    }
    Some(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meshes_are_judged_each_on_its_own() {
        // The Gmsh mesh's 6 m/s peak lies above the box's 8 m/s one: no fall on either mesh.
        let pts = [
            ("box 60 x 12 x 6", 2.0, 2310e3),
            ("box 60 x 12 x 6", 6.0, 6384e3),
            ("box 60 x 12 x 6", 8.0, 6835e3),
            ("beam.msh", 2.0, 3036e3),
            ("beam.msh", 6.0, 7269e3),
            ("beam.msh", 8.0, 10166e3),
            ("box 120 x 24 x 12", 2.0, 2310e3),
        ];
        let text = monotonic_by_mesh(pts.into_iter()).unwrap();
        assert!(
            text.contains("rises monotonically with the impact velocity on every mesh"),
            "{text}"
        );
        assert!(
            !text.contains("120 x 24"),
            "a single velocity is no family: {text}"
        );
        let mut falling = pts.to_vec();
        falling[5].2 = 7000e3;
        falling[4].2 = 7100e3;
        let text = monotonic_by_mesh(falling.into_iter()).unwrap();
        assert!(
            text.contains("does NOT rise monotonically with the impact velocity on beam.msh ("),
            "{text}"
        );
        assert!(monotonic_by_mesh([("box", 2.0, 1.0)].into_iter()).is_none());
    }

    #[test]
    fn variants_at_one_velocity_are_not_compared_with_each_other() {
        // Held-down and plate-supported drops at 2 and 8 m/s, sorted by velocity.
        assert!(rises(&[
            (2.0, 2298e3),
            (2.0, 2299e3),
            (8.0, 6795e3),
            (8.0, 6793e3)
        ]));
        assert!(!rises(&[(2.0, 2298e3), (2.0, 7000e3), (8.0, 6795e3)]));
        assert!(!rises(&[(2.0, 2298e3), (4.0, 2000e3)]));
    }
}
