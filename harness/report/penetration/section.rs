//! The "Penetration and remeshing" section: for each case that remeshed, its velocity and depth
//! curves, the remeshing table, the mesh pictures and the stress near the tip around each
//! remeshing; a link to it from the case's own section.

use super::mesh_view::{mesh_svg, time_text, MESH_VIEW_WIDTH};
use super::record::{load_pictures, NearTipPoint, PenetrationRecord, RemeshRow, KEY};
use crate::report::blocks::{element, note, number, plots, table, text, titles, Cell, Row};
use crate::report::format;
use crate::report::plot::render_plot;
use crate::report::section::{cases_with, part_heading, part_link, Page, Section};
use crate::report::summary::CaseSummary;
use crate::results::{PlotData, Series};

/// Anchor of the section.
pub const ANCHOR: &str = "penetration";
/// Most mesh pictures shown per case: the first, the last and evenly spread ones between.
pub const MAX_PICTURES: usize = 8;
/// Most remeshings drawn in a near-tip plot (evenly spread, the first and last among them).
pub const MAX_WINDOWS: usize = 8;

/// The section (see the module's documentation).
pub struct PenetrationSection;

impl Section for PenetrationSection {
    fn anchor(&self) -> &'static str {
        ANCHOR
    }

    fn title(&self) -> &'static str {
        "Penetration and remeshing"
    }

    fn html(&self, page: &Page<'_>) -> Option<String> {
        let cases = cases_with::<PenetrationRecord>(page, KEY);
        if cases.is_empty() {
            return None;
        }
        let mut html = element(
            "p",
            "",
            "Runs that remesh a body as its elements distort (thesis chapter 8; the nail of \
             thesis 10.4). Per case: the penetrator's velocity and depth curves (the case's plots \
             of velocity and displacement); each remeshing with the model's elements, the worst \
             collapse ratio L_max/L_min (8.1) and the jumps of kinetic, stored and total energy and \
             of momentum it made; the mesh in the case's section plane at the start, after \
             remeshings and at the end (thesis Fig. 10.22; at the end of a run that failed, its \
             last step); the stress of the remeshed body near the tip a few steps before and \
             after each remeshing, whose oscillation should die out within a few steps (thesis \
             10.4.2.2, Fig. 10.24). A run that failed shows what it wrote until it stopped.",
        );
        for (case, record) in &cases {
            html.push_str(&part(self, case, record, page));
        }
        Some(html)
    }

    fn in_case(&self, case: &CaseSummary<'_>, _page: &Page<'_>) -> String {
        if case.case.records.contains_key(KEY) {
            part_link(
                self,
                case,
                "Remeshing table, mesh pictures and stress near the tip",
            )
        } else {
            String::new()
        }
    }

    fn markdown(&self, page: &Page<'_>) -> Option<String> {
        let cases = cases_with::<PenetrationRecord>(page, KEY);
        if cases.is_empty() {
            return None;
        }
        let mut md = String::from(
            "| case | status | remeshings | elements first → last | worst collapse after the last | largest abs. energy jump (J) |\n\
             |---|---|---|---|---|---|\n",
        );
        for (case, r) in &cases {
            let c = case.case;
            let (elements, worst) = match (r.remeshings.first(), r.remeshings.last()) {
                (Some(a), Some(z)) => (
                    format!("{} → {}", a.elements[0], z.elements[1]),
                    z.worst_collapse
                        .get(1)
                        .map_or_else(|| "—".into(), |w| format::num(*w)),
                ),
                _ => ("—".into(), "—".into()),
            };
            let jump = r
                .remeshings
                .iter()
                .map(|x| x.total_energy_jump.abs())
                .fold(f64::NAN, f64::max);
            md.push_str(&format!(
                "| {} | {} | {} | {elements} | {worst} | {} |\n",
                format::markdown_cell(&c.id),
                crate::report::summary::status_name(c.status),
                r.remeshings.len(),
                if jump.is_nan() {
                    "—".into()
                } else {
                    format::num(jump)
                }
            ));
        }
        Some(md)
    }
}

/// `n` indices of `0..len` evenly spread, the first and last among them (all when `len <= n`).
pub fn spread(len: usize, n: usize) -> Vec<usize> {
    if len <= n {
        return (0..len).collect();
    }
    if n < 2 {
        return (0..n.min(len)).collect();
    }
    let mut out: Vec<usize> = (0..n)
        .map(|i| ((i * (len - 1)) as f64 / (n - 1) as f64).round() as usize)
        .collect();
    out.dedup();
    out
}

/// A case's part of the section.
fn part(
    section: &dyn Section,
    case: &CaseSummary<'_>,
    record: &PenetrationRecord,
    page: &Page<'_>,
) -> String {
    let mut html = part_heading(section, case, "");
    // The penetrator's velocity and depth: the case's own plots of them.
    let curves: Vec<&PlotData> = case
        .case
        .plots
        .iter()
        .filter(|p| {
            let label = p.y_label.to_lowercase();
            ["velocity", "displacement", "depth"]
                .iter()
                .any(|w| label.contains(w))
        })
        .collect();
    html.push_str(&element("h4", "", "Velocity and depth"));
    if curves.is_empty() {
        html.push_str(&note(
            "the case has no plot of a velocity or displacement (a y label naming one)",
        ));
    } else {
        html.push_str(&plots("plots", curves.into_iter().map(render_plot)));
    }
    html.push_str(&element(
        "h4",
        "",
        &format!("Remeshings ({})", record.remeshings.len()),
    ));
    html.push_str(&remeshing_table(&record.remeshings));
    html.push_str(&element("h4", "", "Mesh in the section plane"));
    let pictures = load_pictures(page.run_dir, case.case, record);
    if pictures.is_empty() {
        html.push_str(&note(if record.pictures.is_empty() {
            "no pictures: the case's remeshing settings have no `section`"
        } else {
            "the pictures' files are not in the run's folder"
        }));
    } else {
        let shown = spread(pictures.len(), MAX_PICTURES);
        if shown.len() < pictures.len() {
            html.push_str(&note(&format!(
                "{} of the {} pictures, evenly spread from the start to the end",
                shown.len(),
                pictures.len()
            )));
        }
        html.push_str(&plots(
            "plots",
            shown.iter().map(|&k| {
                mesh_svg(
                    &pictures[k],
                    &case.case.id,
                    &format!("{}-mesh-{k}", case.anchor),
                    MESH_VIEW_WIDTH,
                )
            }),
        ));
    }
    html.push_str(&element(
        "h4",
        "",
        "Stress near the tip around each remeshing",
    ));
    if record.near_tip.is_empty() {
        html.push_str(&note(
            "not recorded: the case's remeshing settings have no `near_tip`",
        ));
    } else {
        html.push_str(&element(
            "p",
            "",
            "The remeshed body's elements within the `near_tip` radius of the probe: their \
             largest von Mises stress and their mean pressure (volume-weighted) against the steps \
             from each remeshing (negative: the old mesh; 0: the transferred state, at the time \
             of the remeshing; positive: the steps after).",
        ));
        html.push_str(&plots(
            "plots",
            [
                render_plot(&near_tip_plot(
                    &record.near_tip,
                    &record.remeshings,
                    "Largest von Mises stress near the tip",
                    "von Mises stress (MPa)",
                    |p| p.max_von_mises * 1e-6,
                )),
                render_plot(&near_tip_plot(
                    &record.near_tip,
                    &record.remeshings,
                    "Mean pressure near the tip",
                    "pressure (MPa)",
                    |p| p.mean_pressure * 1e-6,
                )),
            ],
        ));
    }
    html
}

/// The remeshing table.
fn remeshing_table(rows: &[RemeshRow]) -> String {
    if rows.is_empty() {
        return note("no remeshing: no element passed the collapse limit");
    }
    let pair = |a: String, b: String| text(&format!("{a} → {b}"));
    let body: Vec<Row> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let w = |k: usize| r.worst_collapse.get(k).copied().unwrap_or(f64::NAN);
            Row::new(vec![
                Cell::Num((i + 1).to_string()),
                number(r.time * 1e6),
                pair(r.elements[0].to_string(), r.elements[1].to_string()),
                pair(format::num(w(0)), format::num(w(1))),
                number(r.kinetic_jump),
                number(r.stored_jump),
                number(r.total_energy_jump),
                number(r.momentum_jump),
                number(r.added_mass),
                number(r.kinetic_restored),
            ])
        })
        .collect();
    table(
        &titles(&[
            "#",
            "time (µs)",
            "elements before → after",
            "worst collapse ratio before → after",
            "kinetic jump (J)",
            "stored jump (J)",
            "total energy jump (J)",
            "|momentum jump| (kg m/s)",
            "added mass (kg)",
            "kinetic energy given back (J)",
        ]),
        &body,
    )
}

/// A near-tip quantity `value` (in the plot's unit) against the steps from the remeshing, one
/// curve per remeshing ([`MAX_WINDOWS`] of them at most).
fn near_tip_plot(
    points: &[NearTipPoint],
    remeshings: &[RemeshRow],
    title: &str,
    y_label: &str,
    value: impl Fn(&NearTipPoint) -> f64,
) -> PlotData {
    let count = points.iter().map(|p| p.remeshing).max().unwrap_or(0);
    let series = spread(count, MAX_WINDOWS)
        .into_iter()
        .map(|i| i + 1)
        .map(|k| {
            let window: Vec<&NearTipPoint> = points.iter().filter(|p| p.remeshing == k).collect();
            let time = remeshings
                .get(k - 1)
                .map(|r| r.time)
                .or_else(|| window.iter().find(|p| p.offset == 0).map(|p| p.time))
                .unwrap_or(f64::NAN);
            Series {
                name: format!("#{k}, {}", time_text(time)),
                x: window.iter().map(|p| p.offset as f64).collect(),
                y: window.iter().map(|p| value(p)).collect(),
            }
        })
        .collect();
    PlotData {
        title: title.to_string(),
        x_label: "steps from the remeshing".into(),
        y_label: y_label.to_string(),
        series,
        reference_lines: Vec::new(),
        log_log: false,
    }
}
