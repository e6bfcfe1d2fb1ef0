//! The "Concrete material" part of the report, as data both outputs render: the cases that ran a
//! material-point experiment (`material_point` cases), each with its metrics against their
//! targets, the tables and plots its experiment recorded, and its notes.

use super::format::num;
use super::plot::{render_plot_with, PlotExtras, PLOT_SIZE};
use super::summary::status_name;
use crate::material_point::{MaterialPlot, MaterialRecord};
use crate::results::{CaseResult, MetricResult, RunResults, ToleranceKind};

/// Cases carrying a material record, in run order.
pub fn cases(results: &RunResults) -> Vec<(usize, &CaseResult, &MaterialRecord)> {
    results
        .cases
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.material.as_ref().map(|m| (i, c, m)))
        .collect()
}

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
                if m.pass { "pass" } else { "FAIL" }.to_string(),
                m.reference_source.clone(),
            ]
        })
        .collect()
}

/// Renders a record's plot as SVG with its target windows, dashed references and log axes.
pub fn render(p: &MaterialPlot) -> String {
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

/// The section in Markdown for `summary.md`; empty when the run has nothing for it.
pub fn markdown(results: &RunResults) -> String {
    let list = cases(results);
    if list.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Concrete material\n\nMaterial-point experiments of the microplane model; the \
         report page has their curves.\n",
    );
    for (_, c, record) in list {
        md.push_str(&format!(
            "\n### {} ({}, {})\n\n{}\n\n",
            c.id,
            status_name(c.status).to_uppercase(),
            record.material,
            record.setup.join("; ")
        ));
        if !c.metrics.is_empty() {
            md.push_str("| metric | value | target | unit | verdict |\n|---|---:|---|---|---|\n");
            for r in metric_rows(c) {
                md.push_str(&format!(
                    "| {} | {} | {} | {} | {} |\n",
                    super::format::markdown_cell(&r[0]),
                    r[1],
                    super::format::markdown_cell(&r[2]),
                    r[3],
                    if r[4] == "pass" { "pass" } else { "**FAIL**" }
                ));
            }
        }
        for note in &record.notes {
            md.push_str(&format!("\n- {}", super::format::first_line(note, 240)));
        }
        if !record.notes.is_empty() {
            md.push('\n');
        }
    }
    md
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
