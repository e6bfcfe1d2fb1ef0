//! The self-contained `index.html`: inline CSS, inline SVG plots, no scripts. Every piece of
//! text from the results goes through [`format::html`]; the helpers below take either escaped
//! fragments (`Cell::Html`, `inner`) or plain text, and say which.

use super::blocks::{
    badge, element, note, number, plots, state_badge, table, text, titles, Cell, Row,
};
use super::diagrams::{self, Trend};
use super::format;
use super::plot::{render_plot, render_plot_sized, TREND_SIZE};
use super::section::{self, Page, Section};
use super::summary::{
    self, against_reference, ratio_text, tolerance_ratio, CaseState, CaseSummary, STATES,
};
use crate::results::{CaseResult, HistoryRecord, MetricResult, RunResults, Status, SweepResult};

/// The page's style sheet, inlined so that the page opens from a CI artifact without network.
const STYLE: &str = include_str!("style.css");

/// The whole page.
pub fn page(page: &Page<'_>, history: &[HistoryRecord], sections: &[&dyn Section]) -> String {
    let results = page.results;
    let mut body = header(results);
    body.push_str(&summary_section(page.summaries));
    for s in sections {
        body.push_str(&section::html(*s, page));
    }
    for s in page.summaries {
        body.push_str(&case_section(s, page, history, sections));
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>V&amp;V report {}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        format::html(&results.run_id)
    )
}

/// Title, verdict banner, counts per state and the run's provenance.
fn header(results: &RunResults) -> String {
    let verdict = summary::verdict(results);
    let counts: String = STATES
        .iter()
        .map(|&s| {
            format!(
                "<span>{} {}</span>",
                state_badge(s),
                summary::count_state(results, s)
            )
        })
        .collect();
    let versions = results
        .versions
        .iter()
        .map(|(k, v)| format!("{k} {v}"))
        .collect::<Vec<_>>()
        .join(", ");
    let meta = [
        ("Run", results.run_id.clone()),
        ("Commit", results.commit.clone()),
        ("Tier", results.tier.clone()),
        ("Date", results.date.clone()),
        ("Machine", results.machine.clone()),
        ("Threads", results.threads.to_string()),
        ("Versions", versions),
        ("Wall time", format::seconds(results.wall_s)),
    ];
    let meta: String = meta
        .iter()
        .map(|(k, v)| format!("<dt>{k}</dt><dd>{}</dd>", format::html(v)))
        .collect();
    let banner_class = format!("verdict {}", verdict.tone.class());
    format!(
        "<header>\n<h1>Concrete-impact V&amp;V report</h1>\n{}{}{}</header>\n",
        element("div", &banner_class, &format::html(&verdict.text)),
        element("div", "counts", &counts),
        element("dl", "meta", &meta),
    )
}

/// The summary table: one row per case, linking to its section.
fn summary_section(summaries: &[CaseSummary<'_>]) -> String {
    let rows: Vec<Row> = summaries.iter().map(summary_row).collect();
    let head = titles(&[
        "case",
        "variant",
        "status",
        "wall time",
        "metrics passed",
        "worst metric",
    ]);
    format!(
        "<section id=\"summary\">\n<h2>Summary</h2>\n{}</section>\n",
        table(&head, &rows)
    )
}

/// One row of the summary table.
fn summary_row(s: &CaseSummary<'_>) -> Row {
    let c = s.case;
    let link = format!("<a href=\"#{}\">{}</a>", s.anchor, format::html(&c.id));
    let worst = match s.worst {
        Some(m) => Cell::Html(worst_html(m, CaseState::of(c))),
        None => text("—"),
    };
    let state = CaseState::of(c);
    Row {
        class: match state {
            CaseState::Fail | CaseState::Error => "bad",
            CaseState::KnownFailure => "known",
            _ => "",
        },
        cells: vec![
            Cell::Html(link),
            text(&c.variant),
            Cell::Html(state_badge(state)),
            Cell::Num(format::seconds(c.wall_s)),
            Cell::Num(format!("{}/{}", s.passed, s.total)),
            worst,
        ],
    }
}

/// The worst metric's name and its error as a multiple of the tolerance, or its value against
/// the reference where the tolerance gives no finite multiple ([`ratio_text`]); red when it
/// failed, amber when the case's failure is a known one.
fn worst_html(m: &MetricResult, state: CaseState) -> String {
    let class = match (m.pass, state) {
        (true, _) => "ratio",
        (false, CaseState::KnownFailure) => "ratio known",
        (false, _) => "ratio bad",
    };
    let how_far = match ratio_text(m) {
        Some(ratio) => format!("{ratio} tol"),
        None => against_reference(m),
    };
    format!(
        "{} <span class=\"{class}\">{}</span>",
        format::html(&m.name),
        format::html(&how_far)
    )
}

/// The section of one case: what it is, why it did not pass, its metrics, plots, sweep and trend.
fn case_section(
    s: &CaseSummary<'_>,
    page: &Page<'_>,
    history: &[HistoryRecord],
    sections: &[&dyn Section],
) -> String {
    let c = s.case;
    let mut html = format!(
        "<section class=\"case\" id=\"{}\">\n<h2>{} {} <span class=\"variant\">{}</span></h2>\n",
        s.anchor,
        state_badge(CaseState::of(c)),
        format::html(&c.id),
        format::html(&c.variant)
    );
    html.push_str(&case_facts(c));
    if !c.description.is_empty() {
        html.push_str(&element("p", "description", &format::html(&c.description)));
    }
    html.push_str(&message(c));
    html.push_str(&element("h3", "", "Metrics"));
    html.push_str(&metrics_table(&c.metrics, s.worst, CaseState::of(c)));
    if !c.plots.is_empty() {
        html.push_str(&element("h3", "", "Plots"));
        html.push_str(&plots("plots", c.plots.iter().map(render_plot)));
    }
    if let Some(sweep) = &c.sweep {
        html.push_str(&sweep_section(c, sweep));
    }
    for section in sections {
        html.push_str(&section.in_case(s, page));
    }
    html.push_str(&trend_section(&diagrams::trend(c, history)));
    html.push_str("</section>\n");
    html
}

/// Tier, wall time and tags of a case, on one line, with a way back to the summary.
fn case_facts(c: &CaseResult) -> String {
    let tags: String = c
        .tags
        .iter()
        .map(|t| format!("<span class=\"tag\">{}</span>", format::html(t)))
        .collect();
    // The case's own log lines (remeshing summaries), kept off the terminal.
    let log = c.log_file.as_deref().map_or(String::new(), |path| {
        format!(" · <a href=\"{}\">log</a>", format::html(path))
    });
    format!(
        "<p class=\"facts\">tier <b>{}</b> · wall time <b>{}</b> {tags}{log} · <a href=\"#summary\">back to summary</a></p>\n",
        format::html(if c.tier.is_empty() { "—" } else { &c.tier }),
        format::seconds(c.wall_s),
    )
}

/// The case's message: a coloured call-out with the reason when it did not pass (for a known
/// failure, first the debt the case records, then how it failed this time), the solver's plan
/// folded away when it did.
fn message(c: &CaseResult) -> String {
    let msg = c.message.as_deref().unwrap_or("");
    let pre = element("pre", "", &format::html(msg));
    let state = CaseState::of(c);
    let title = match state {
        CaseState::Pass if msg.is_empty() => return String::new(),
        CaseState::Pass => {
            return format!("<details><summary>Solver plan</summary>\n{pre}</details>\n")
        }
        CaseState::KnownFailure => "How it failed",
        CaseState::Fail => "Why it failed",
        CaseState::Error => "Why it could not be evaluated",
        CaseState::Interrupted => "Interrupted",
        CaseState::Skipped => "Why it was skipped",
    };
    let mut body = String::new();
    if let Some(known) = c
        .known_failure
        .as_deref()
        .filter(|_| state == CaseState::KnownFailure)
    {
        // The debt the case records: why this failure does not fail the run.
        body.push_str(&format!(
            "<div class=\"callout-title\">Known failure (does not fail the run)</div>\n{}",
            element("pre", "", &format::html(known))
        ));
    }
    body.push_str(&format!("<div class=\"callout-title\">{title}</div>\n"));
    body.push_str(&if msg.is_empty() {
        note("no reason given")
    } else {
        pre
    });
    element("div", &format!("callout {}", state.class()), &body)
}

/// The metrics of a case with their references and tolerances; failing rows in red (amber in a
/// known failure), the worst metric marked.
fn metrics_table(
    metrics: &[MetricResult],
    worst: Option<&MetricResult>,
    state: CaseState,
) -> String {
    if metrics.is_empty() {
        return note("no metrics");
    }
    let head = titles(&[
        "metric",
        "value",
        "reference",
        "error",
        "tolerance",
        "error/tol",
        "kind",
        "unit",
        "verdict",
        "reference source",
    ]);
    let rows: Vec<Row> = metrics
        .iter()
        .map(|m| metric_row(m, worst.is_some_and(|w| std::ptr::eq(w, m)), state))
        .collect();
    table(&head, &rows)
}

/// One row of the metrics table.
fn metric_row(m: &MetricResult, is_worst: bool, state: CaseState) -> Row {
    let name = if is_worst {
        format!("{} <span class=\"tag\">worst</span>", format::html(&m.name))
    } else {
        format::html(&m.name)
    };
    let mut verdict = badge(if m.pass { Status::Pass } else { Status::Fail });
    // A measure's own reading (a tip speed "inconclusive" or "no tip") says why beside it.
    if let Some(reading) = &m.reading {
        verdict.push_str(&element("span", "source", &format::html(reading)));
    }
    Row {
        class: match (m.pass, state) {
            (true, _) => "",
            (false, CaseState::KnownFailure) => "known",
            (false, _) => "bad",
        },
        cells: vec![
            Cell::Html(name),
            number(m.value),
            number(m.reference),
            number(m.error),
            number(m.tolerance),
            // A zero tolerance has no finite multiple: the value and reference columns say it.
            ratio_text(m).map_or_else(|| text("—"), |_| number(tolerance_ratio(m))),
            text(m.tolerance_kind.name()),
            text(&m.unit),
            Cell::Html(verdict),
            Cell::Html(element(
                "span",
                "source",
                &format::html(&m.reference_source),
            )),
        ],
    }
}

/// A refinement sweep: its levels, the observed orders, and the convergence and
/// work-precision diagrams.
fn sweep_section(c: &CaseResult, sweep: &SweepResult) -> String {
    let metrics = diagrams::sweep_metrics(sweep);
    let mut head = vec![sweep.parameter.clone(), "wall time".into(), "status".into()];
    head.extend(metrics.iter().map(|m| format!("error: {m}")));
    let rows: Vec<Row> = sweep
        .levels
        .iter()
        .map(|l| {
            let mut cells = vec![number(l.parameter), Cell::Num(format::seconds(l.wall_s))];
            cells.push(text(&l.status.to_string()));
            cells.extend(
                metrics
                    .iter()
                    .map(|m| l.errors.get(m).map_or_else(|| text("—"), |&e| number(e))),
            );
            Row::new(cells)
        })
        .collect();
    let orders: Vec<Row> = sweep
        .observed_order
        .iter()
        .map(|(m, &o)| Row::new(vec![text(m), number(o)]))
        .collect();
    format!(
        "<h3>Refinement sweep over {}</h3>\n{}<h4>Observed orders</h4>\n{}{}",
        format::html(&sweep.parameter),
        table(&head, &rows),
        if orders.is_empty() {
            note("no observed order")
        } else {
            table(&titles(&["metric", "observed order"]), &orders)
        },
        plots(
            "plots",
            [
                render_plot(&diagrams::convergence_plot(c, sweep)),
                render_plot(&diagrams::work_precision_plot(c, sweep)),
            ]
        ),
    )
}

/// The trend plots of a case and the runs they cover (x = run index in the table).
fn trend_section(trend: &Trend<'_>) -> String {
    let title = element("h3", "", "Trend");
    if trend.runs.len() < 2 {
        return title + &note("no trend yet (first run)");
    }
    let rows: Vec<Row> = trend
        .runs
        .iter()
        .enumerate()
        .map(|(i, r)| {
            Row::new(vec![
                Cell::Num((i + 1).to_string()),
                text(&r.run_id),
                text(&r.commit),
                text(&r.date),
                Cell::Html(badge(r.status)),
                Cell::Num(format::seconds(r.wall_s)),
            ])
        })
        .collect();
    let runs = table(
        &titles(&["run", "run id", "commit", "date", "status", "wall time"]),
        &rows,
    );
    let svgs = trend.plots.iter().map(|p| render_plot_sized(p, TREND_SIZE));
    // Open while short; thirty rows per case would bury the next case.
    let open = if trend.runs.len() <= 10 { " open" } else { "" };
    format!(
        "{title}{}<details{open}><summary>The {} runs shown (run 1 is the oldest)</summary>\n{runs}</details>\n",
        plots("plots small", svgs),
        trend.runs.len(),
    )
}
