//! The pieces of a kind's record as the report renders them, shared by the sections of the
//! kinds: metrics against their targets (HTML and Markdown tables), plots with target windows
//! and dashed references, and recorded tables.

use super::blocks::{badge, element, state_badge, table, text, Cell, Row};
use super::format::{self, num};
use super::plot::{render_plot_with, PlotExtras, PLOT_SIZE};
use super::summary::CaseState;
use crate::results::{CaseResult, MaterialPlot, MetricResult, RecordTable, Status, ToleranceKind};

/// A metric's target in words: `2.7 ± 3 %`, `[1e-4, 1.5e-4]`, `<= 1e-10`, `>= 0.5`.
pub fn target(m: &MetricResult) -> String {
    match m.tolerance_kind {
        ToleranceKind::Relative => {
            format!("{} ± {} %", num(m.reference), num(100.0 * m.tolerance))
        }
        ToleranceKind::Absolute => format!(
            "[{}, {}]",
            num(m.reference - m.tolerance),
            num(m.reference + m.tolerance)
        ),
        ToleranceKind::AtMost => format!("≤ {}", num(m.tolerance)),
        ToleranceKind::AtLeast => format!("≥ {}", num(m.tolerance)),
        _ => format!("{} (tolerance {})", num(m.reference), num(m.tolerance)),
    }
}

/// The verdict of a metric: `pass`, `known failure` (a failing metric of a case whose file says
/// it is known to fail: a debt, shown in amber as the banner counts it) or `FAIL`.
fn verdict(c: &CaseResult, m: &MetricResult) -> &'static str {
    match (m.pass, c.known_failure.is_some()) {
        (true, _) => "pass",
        (false, true) => "known failure",
        (false, false) => "FAIL",
    }
}

/// The rows of the measured-against-target table: metric, value, target, unit, verdict, source.
pub fn metric_rows(c: &CaseResult) -> Vec<[String; 6]> {
    c.metrics
        .iter()
        .map(|m| {
            [
                m.name.clone(),
                num(m.value),
                target(m),
                m.unit.clone(),
                verdict(c, m).to_string(),
                m.reference_source.clone(),
            ]
        })
        .collect()
}

/// Renders a record's plot as SVG with its target windows, dashed references and log axes.
pub fn target_plot(p: &MaterialPlot) -> String {
    let boxes = p
        .boxes
        .iter()
        .filter(|b| b.x.len() == 2 && b.y.len() == 2)
        .map(|b| ([b.x[0], b.x[1]], [b.y[0], b.y[1]], b.label.as_str()))
        .collect();
    let extras = PlotExtras {
        log_x: p.log_x,
        log_y: p.log_y,
        boxes,
        dashed: p.dashed.iter().map(String::as_str).collect(),
    };
    render_plot_with(&p.plot, &extras, PLOT_SIZE)
}

/// The metrics of `c` against their targets as an HTML table, with the unit column when
/// `with_unit`; failing rows marked.
pub fn metric_table(c: &CaseResult, with_unit: bool) -> String {
    let rows: Vec<Row> = metric_rows(c)
        .into_iter()
        .map(|r| {
            let (badge_html, class) = match r[4].as_str() {
                "pass" => (badge(Status::Pass), ""),
                "known failure" => (state_badge(CaseState::KnownFailure), "known"),
                _ => (badge(Status::Fail), "bad"),
            };
            let mut cells = vec![text(&r[0]), Cell::Num(r[1].clone()), text(&r[2])];
            if with_unit {
                cells.push(text(&r[3]));
            }
            cells.push(Cell::Html(badge_html));
            cells.push(Cell::Html(element("span", "source", &format::html(&r[5]))));
            Row { class, cells }
        })
        .collect();
    let head: Vec<String> = ["metric", "value", "target", "unit", "verdict", "source"]
        .iter()
        .filter(|h| with_unit || **h != "unit")
        .map(|s| s.to_string())
        .collect();
    table(&head, &rows)
}

/// The metrics of `c` against their targets as a Markdown table, with the unit column when
/// `with_unit`.
pub fn metric_markdown(c: &CaseResult, with_unit: bool) -> String {
    let mut md = if with_unit {
        String::from("| metric | value | target | unit | verdict |\n|---|---:|---|---|---|\n")
    } else {
        String::from("| metric | value | target | verdict |\n|---|---:|---|---|\n")
    };
    for r in metric_rows(c) {
        let unit = if with_unit {
            format!(" {} |", r[3])
        } else {
            String::new()
        };
        md.push_str(&format!(
            "| {} | {} | {} |{unit} {} |\n",
            format::markdown_cell(&r[0]),
            r[1],
            format::markdown_cell(&r[2]),
            match r[4].as_str() {
                "FAIL" => "**FAIL**",
                other => other,
            }
        ));
    }
    md
}

/// A record's table (material-point experiments, cross-checks): title, cells as text, note.
pub fn record_table(t: &RecordTable) -> String {
    let rows: Vec<Row> = t
        .rows
        .iter()
        .map(|r| Row::new(r.iter().map(|c| text(c)).collect()))
        .collect();
    let mut html = element("h4", "", &format::html(&t.title));
    html.push_str(&table(&t.head, &rows));
    if !t.note.is_empty() {
        html.push_str(&element("p", "muted", &format::html(&t.note)));
    }
    html
}

#[cfg(test)]
mod tests {
    use super::*;

    fn metric(kind: ToleranceKind, reference: f64, tolerance: f64) -> MetricResult {
        MetricResult {
            name: "m".into(),
            value: 1.0,
            reference,
            error: 0.0,
            tolerance,
            unit: String::new(),
            pass: true,
            tolerance_kind: kind,
            reference_source: String::new(),
            reading: None,
        }
    }

    #[test]
    fn targets_read_as_bands() {
        assert_eq!(
            target(&metric(ToleranceKind::Relative, 2.7, 0.03)),
            "2.7 ± 3 %"
        );
        assert_eq!(
            target(&metric(ToleranceKind::Absolute, 1.25e-4, 0.25e-4)),
            "[1e-4, 1.5e-4]"
        );
        assert_eq!(
            target(&metric(ToleranceKind::AtMost, 0.0, 1e-10)),
            "≤ 1e-10"
        );
        assert_eq!(target(&metric(ToleranceKind::AtLeast, 0.5, 0.5)), "≥ 0.5");
    }
}
