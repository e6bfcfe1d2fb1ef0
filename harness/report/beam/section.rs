//! The beam pictures on the page (content from `report::beam`): in a beam case's own section its
//! crack pattern at the end and a filmstrip of earlier instants; and the "Beam: failure modes"
//! section with the final crack patterns of all beam cases side by side, their impact velocity,
//! peak force and `failure_mode` metric, and whether the peak contact force rises with velocity.

use super::{
    failure_rows, load, load_one, metric_text, monotonic_statement, side_view_svg, verdicts,
    BeamRecord, FAILURE_MODE_METRIC, FILMSTRIP_WIDTH, SIDE_VIEW_WIDTH,
};
use crate::report::blocks::{element, list, note, plots, table, text, titles, Cell, Row};
use crate::report::format;
use crate::report::section::{Page, Section};
use crate::report::summary::CaseSummary;
use crate::results::{CaseResult, RunResults};

/// Anchor of the failure-mode section.
pub const ANCHOR: &str = "beam-failure-modes";

/// The "Beam: failure modes" section, and the crack pictures in each beam case's own section.
pub struct BeamSection;

impl Section for BeamSection {
    fn anchor(&self) -> &'static str {
        ANCHOR
    }

    fn title(&self) -> &'static str {
        "Beam: failure modes"
    }

    fn html(&self, page: &Page<'_>) -> Option<String> {
        let records = load(page);
        section(page.results, page.summaries, &records)
    }

    fn in_case(&self, case: &CaseSummary<'_>, page: &Page<'_>) -> String {
        page.read(load_one(page.run_dir, case.case))
            .map_or_else(String::new, |r| case_pictures(&r))
    }

    fn markdown(&self, page: &Page<'_>) -> Option<String> {
        super::markdown(page.results, &load(page))
    }
}

/// The crack pictures in a case's own section; empty for cases without them.
fn case_pictures(record: &BeamRecord) -> String {
    let mut html = element("h3", "", "Crack pattern (side view)");
    html.push_str(&element(
        "p",
        "",
        &format!(
            "Each cell of the side view shows the largest crack indicator eps_1/eps_r of the \
             elements across the width; 1 and more is cracked. Triangles: supports; blue bar: \
             impactor footprint. All beam cases side by side: <a href=\"#{ANCHOR}\">Beam: failure \
             modes</a>."
        ),
    ));
    let (last, earlier): (Vec<_>, Vec<_>) = record.frames.iter().partition(|f| f.last);
    html.push_str(&plots(
        "plots",
        last.iter()
            .map(|f| side_view_svg(record, f, SIDE_VIEW_WIDTH)),
    ));
    if !earlier.is_empty() {
        html.push_str(&element("h4", "", "Filmstrip"));
        html.push_str(&plots(
            "plots small",
            earlier
                .iter()
                .chain(last.iter())
                .map(|f| side_view_svg(record, f, FILMSTRIP_WIDTH)),
        ));
    }
    html
}

/// The content of the "Beam: failure modes" section, or nothing when no case recorded beam
/// pictures.
fn section(
    results: &RunResults,
    summaries: &[CaseSummary<'_>],
    records: &[(usize, BeamRecord)],
) -> Option<String> {
    let rows = failure_rows(results, records);
    if rows.is_empty() {
        return None;
    }
    let mut html = String::new();
    html.push_str(&element(
        "p",
        "",
        "The thesis' plain concrete beam (chapter 10): the static and drop-weight cases side by \
         side, ordered by impact velocity. The failure mode is classified at the end of the \
         contact (the contact force below 1 % of its peak; thesis 10.3.2.1 judges it there) and \
         at the end of the run; the `failure_mode` metric judges the state its case names. \
         The crack patterns below are final states (side view, largest eps_1/eps_r across the \
         width; 1 and more is cracked); each case's section shows the state at the end of the \
         contact too. The tip speed is that of the bending crack's opening front (w = w_cr / 2), from \
         the crack's initiation on; the length the crack appears with is given beside it.",
    ));
    let anchor_of = |c: &CaseResult| {
        summaries
            .iter()
            .find(|s| std::ptr::eq(s.case, c))
            .map(|s| s.anchor.clone())
    };
    let table_rows: Vec<Row> = rows
        .iter()
        .map(|r| {
            let name = match anchor_of(r.case) {
                Some(a) => format!("<a href=\"#{a}\">{}</a>", format::html(&r.case.id)),
                None => format::html(&r.case.id),
            };
            Row::new(vec![
                Cell::Html(name),
                r.record
                    .speed
                    .map_or_else(|| text("static"), |v| Cell::Num(format::num(v))),
                r.record
                    .peak_force
                    .map_or_else(|| text("—"), |f| Cell::Num(format::num(f / 1e3))),
                text(if r.record.peak_force_label.is_empty() {
                    "—"
                } else {
                    &r.record.peak_force_label
                }),
                text(&r.record.mesh),
                r.record.contact_end.as_ref().map_or_else(
                    || text("—"),
                    |j| {
                        text(&format!(
                            "{} (judged at {} ms)",
                            format::num(j.contact_end * 1e3),
                            format::num(j.time * 1e3)
                        ))
                    },
                ),
                r.record
                    .contact_end
                    .as_ref()
                    .map_or_else(|| text("—"), |j| text(&j.mode)),
                text(r.record.mode_at_end.as_deref().unwrap_or("—")),
                r.metric
                    .map_or_else(|| text("no failure_mode metric"), |m| text(&metric_text(m))),
                initiation(r.record).map_or_else(
                    || text("—"),
                    |i| {
                        text(&format!(
                            "{} ms; initiation {} m",
                            format::num(i.time * 1e3),
                            format::num(i.length)
                        ))
                    },
                ),
                r.record
                    .crack_tip
                    .as_ref()
                    .map_or_else(|| text("—"), |t| text(&format::num(t.coalescence_length))),
                tip_text(r.record, |t| &t.cohesive_speed),
                tip_text(r.record, |t| &t.traction_free_speed),
                damage_front_text(r.record),
            ])
        })
        .collect();
    html.push_str(&table(
        &titles(&[
            "case",
            "impact velocity (m/s)",
            "peak force (kN)",
            "which force",
            "beam mesh",
            "end of contact (ms)",
            "mode at the end of contact",
            "mode at the end of the run",
            FAILURE_MODE_METRIC,
            "traction-free crack appears (time; cohesive tip then)",
            "coalescence length (m)",
            "cohesive tip speed / c_R ± h/T (thesis 0.55)",
            "traction-free tip speed / c_R ± h/T",
            "pre-damage front down the column / c_p ± h/T (depth reached)",
        ]),
        &table_rows,
    ));
    let lines = verdicts(&rows);
    if !lines.is_empty() {
        html.push_str(&element(
            "h4",
            "",
            "Verdict per velocity (failure mode at the end of the contact)",
        ));
        html.push_str(&list(&lines));
    }
    tip_agreement_list(&rows, &mut html);
    column_demand_table(&rows, &anchor_of, &mut html);
    match monotonic_statement(&rows) {
        Some(s) => html.push_str(&element("p", "", &format::html(&s))),
        None => html.push_str(&note(
            "fewer than two impact cases with a contact force: no monotonicity to state",
        )),
    }
    let finals = rows.iter().filter_map(|r| {
        let f = r.record.frames.iter().find(|f| f.last)?;
        Some(side_view_svg(r.record, f, FILMSTRIP_WIDTH + 60))
    });
    html.push_str(&plots("plots", finals));
    Some(html)
}

/// The tips' speeds across the meshes at each velocity (`super::tip_agreement`); nothing
/// without a crack-tip reading.
fn tip_agreement_list(rows: &[super::FailureRow<'_>], html: &mut String) {
    let agreement = super::tip_agreement::agreement_lines(rows);
    if !agreement.is_empty() {
        html.push_str(&element(
            "h4",
            "",
            "Crack-tip speeds across the meshes at each velocity (fastest windows, agreement within resolution)",
        ));
        html.push_str(&list(&agreement));
    }
}

/// The elastic column's demand against the envelope, beside the measured pre-damage
/// (`super::column_demand`); nothing without an impact case.
fn column_demand_table(
    rows: &[super::FailureRow<'_>],
    anchor_of: &dyn Fn(&CaseResult) -> Option<String>,
    html: &mut String,
) {
    let cells = super::column_demand::cells(rows);
    if cells.is_empty() {
        return;
    }
    html.push_str(&element(
        "h4",
        "",
        "The column under the hammer: elastic demand against the rate-enhanced Kupfer envelope",
    ));
    html.push_str(&element(
        "p",
        "",
        &format::html(super::column_demand::EXPLANATION),
    ));
    let table_rows: Vec<Row> = cells
        .iter()
        .map(|(id, c)| {
            let case = rows.iter().find(|r| &r.case.id == id).map(|r| r.case);
            let name = match case.and_then(anchor_of) {
                Some(a) => format!("<a href=\"#{a}\">{}</a>", format::html(id)),
                None => format::html(id),
            };
            let mut row = vec![Cell::Html(name), Cell::Num(c[0].clone())];
            row.extend(c[1..].iter().map(|s| text(s)));
            Row::new(row)
        })
        .collect();
    html.push_str(&table(&titles(&super::column_demand::TITLES), &table_rows));
}

/// When the traction-free crack appears and the cohesive tip's height then
/// (`crate::beam::Initiation`).
fn initiation(record: &BeamRecord) -> Option<crate::beam::cracks::Initiation> {
    record.crack_tip.as_ref()?.initiation
}

/// A tip's speed reading: its status, and its deciding window over `c_R` with the resolution.
fn tip_text(
    record: &BeamRecord,
    reading: fn(&crate::beam::CrackTipReport) -> &crate::beam::cracks::TipReading,
) -> Cell {
    record.crack_tip.as_ref().map_or_else(
        || text("—"),
        |t| text(&reading(t).describe(t.rayleigh_speed)),
    )
}

/// The pre-damage front's speed reading over `c_p` and the depth it reached, or that there is
/// none (`crate::beam::cracks::track::damage_front`).
fn damage_front_text(record: &BeamRecord) -> Cell {
    let Some(t) = record.crack_tip.as_ref() else {
        return text("—");
    };
    if t.dilatational_speed.is_nan() {
        return text("— (not measured in this record)");
    }
    match t.damage_front.iter().copied().rfind(|d| d.is_finite()) {
        None => text("none"),
        Some(depth) => text(&format!(
            "{}; {} m",
            t.damage_front_speed
                .describe_against(t.dilatational_speed, "c_p"),
            format::num(depth)
        )),
    }
}
