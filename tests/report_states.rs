//! The report as a reader meets its states: the banner counts passes, known failures and
//! failures apart and takes the colour of the worst; a zero tolerance reads as the value
//! against its reference; long titles wrap to their plot; a case's log is linked.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::fs;

use impact_vv::registry::SECTIONS;
use impact_vv::report::plot::{render_plot_sized, PLOT_SIZE, TREND_SIZE};
use impact_vv::report::summary::worst_text;
use impact_vv::report::text_fit::width_bound;
use impact_vv::report::{render_plot, write_report};
use impact_vv::results::{CaseResult, MetricResult, Status, ToleranceKind};

mod report_common;
use report_common::*;

/// The verdict banner's class and text.
fn banner(page: &str) -> (&str, &str) {
    let open = "<div class=\"verdict ";
    let start = page.find(open).expect("a banner") + open.len();
    let class_end = start + page[start..].find('"').unwrap();
    let text_start = class_end + 2;
    let text_end = text_start + page[text_start..].find("</div>").unwrap();
    (&page[start..class_end], &page[text_start..text_end])
}

fn page_of(name: &str, cases: Vec<CaseResult>) -> String {
    let dir = scratch(name);
    let mut run = results(name);
    run.cases = cases;
    let page = fs::read_to_string(write_report(&dir, &run, &[], SECTIONS).unwrap()).unwrap();
    let _ = fs::remove_dir_all(&dir);
    page
}

fn known_failure() -> CaseResult {
    let mut case = fail_case();
    case.known_failure = Some("order 1 until issue 12 lands".to_string());
    case
}

/// Green when all pass, amber when only known failures remain, red for any failure or error;
/// the banner counts each state, and a known failure is amber in the table and its section.
#[test]
fn the_banner_counts_states_and_takes_the_colour_of_the_worst() {
    let all_pass = page_of("banner-pass", vec![pass_case(), pass_case()]);
    assert_eq!(banner(&all_pass), ("ok", "2 passed · 0 failed"));

    let known = page_of("banner-known", vec![pass_case(), known_failure()]);
    assert_eq!(
        banner(&known),
        ("known", "1 passed · 1 known failure · 0 failed")
    );
    let summary =
        &known[known.find("id=\"summary\"").unwrap()..known.find("class=\"case\"").unwrap()];
    assert!(summary.contains("<tr class=\"known\">"), "{summary}");
    let badge = "<span class=\"badge known\">known failure</span>";
    let case = &known[known
        .find(&format!("{badge} {FAIL_ID}"))
        .expect("amber case heading")..];
    assert!(case.contains("<div class=\"callout known\">"));
    assert!(case.contains("order 1 until issue 12 lands"));
    assert!(
        !known.contains("<tr class=\"bad\">"),
        "no red row in a run with no new failure"
    );

    let mut skipped = pass_case();
    skipped.status = Status::Skipped;
    let failing = page_of(
        "banner-fail",
        vec![
            pass_case(),
            known_failure(),
            fail_case(),
            error_case(),
            skipped,
        ],
    );
    assert_eq!(
        banner(&failing),
        (
            "bad",
            "1 passed · 1 known failure · 1 failed · 1 error · 1 skipped"
        )
    );
}

fn zero_tolerance(name: &str, value: f64, reference: f64, source: &str) -> MetricResult {
    MetricResult {
        name: name.to_string(),
        value,
        reference,
        error: (value - reference).abs(),
        tolerance: 0.0,
        unit: String::new(),
        pass: value == reference,
        tolerance_kind: ToleranceKind::Absolute,
        reference_source: source.to_string(),
        reading: None,
    }
}

/// A class code with tolerance 0 reads as the class against the expected one (thesis 10.3.2:
/// 2 mixed, 3 shear), a count with tolerance 0 as the value against its reference: never an
/// infinite multiple of a zero tolerance.
#[test]
fn a_zero_tolerance_metric_shows_its_value_against_the_reference() {
    let codes = "failure mode `mixed` (thesis 10.3.2; code 0 none, 1 bending, 2 mixed, 3 shear, 4 bending_inclined)";
    let mode = zero_tolerance("failure_mode", 3.0, 2.0, codes);
    assert_eq!(worst_text(&mode), "failure_mode: shear, expected mixed");
    // Without the code list, the beam's failure-mode classes still name the codes.
    let bare = zero_tolerance("failure_mode", 1.0, 4.0, "");
    assert_eq!(
        worst_text(&bare),
        "failure_mode: bending, expected bending_inclined"
    );
    let missed = zero_tolerance("missed_impacts", 3.0, 0.0, "exact solution: zero");
    assert_eq!(worst_text(&missed), "missed_impacts: 3, expected 0");
    let mut ceiling = zero_tolerance("uplift", 0.25, 0.0, "");
    ceiling.tolerance_kind = ToleranceKind::AtMost;
    ceiling.unit = "N".to_string();
    ceiling.error = 0.25;
    assert_eq!(worst_text(&ceiling), "uplift: 0.25 N, expected at most 0 N");

    let mut case = known_failure();
    case.metrics = vec![mode, metric("frequency", 101.0, 100.0, 0.05, "relative")];
    let mut counter = error_case();
    counter.status = Status::Fail;
    counter.id = "crosscheck/ccd".to_string();
    counter.metrics = vec![missed];
    let dir = scratch("zero-tolerance");
    let mut run = results("zero-tolerance");
    run.cases = vec![case, counter];
    let page = fs::read_to_string(write_report(&dir, &run, &[], SECTIONS).unwrap()).unwrap();
    assert!(page.contains("failure_mode <span class=\"ratio known\">shear, expected mixed</span>"));
    assert!(page.contains("missed_impacts <span class=\"ratio bad\">3, expected 0</span>"));
    let md = fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(md.contains("failure_mode: shear, expected mixed"), "{md}");
    assert!(
        md.contains("worst metric `missed_impacts` = 3, expected 0"),
        "{md}"
    );
    for text in [&page, &md] {
        assert!(!text.contains("inf×") && !text.contains("NaN×"));
    }
    let _ = fs::remove_dir_all(&dir);
}

/// The `<text>` elements of an SVG: (x, text-anchor, font-size, content).
fn svg_texts(svg: &str) -> Vec<(f64, String, f64, String)> {
    let attr = |tag: &str, name: &str| -> Option<String> {
        let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        Some(tag[start..start + tag[start..].find('"')?].to_string())
    };
    svg.split("<text")
        .skip(1)
        .map(|t| {
            let tag = &t[..t.find('>').unwrap()];
            let content = &t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()];
            (
                attr(tag, "x").unwrap().parse().unwrap(),
                attr(tag, "text-anchor").unwrap_or_else(|| "start".into()),
                attr(tag, "font-size").unwrap().parse().unwrap(),
                content.trim().to_string(),
            )
        })
        .collect()
}

/// A title longer than the plot is wide (the contact-compare grid's) is split into lines, each
/// within the plot's width by an upper bound of the glyph widths, with every word kept in order.
#[test]
fn a_long_plot_title_wraps_within_the_plot_width() {
    let title =
        "Work-precision by solver: contact/spheres-eccentric-frictionless, energy_after_separation";
    let mut plot = history_plot();
    plot.title = title.to_string();
    for size in [PLOT_SIZE, TREND_SIZE] {
        let svg = render_plot_sized(&plot, size);
        let width = f64::from(size.0);
        // The title's lines: the texts in the largest font.
        let texts = svg_texts(&svg);
        let largest = texts.iter().map(|t| t.2).fold(0.0, f64::max);
        let lines: Vec<_> = texts.into_iter().filter(|t| t.2 == largest).collect();
        assert!(lines.len() >= 2, "{size:?}: {lines:?}");
        // Every character of the title, in order (a word too long for a line breaks after a `-`).
        let shown: String = lines.iter().flat_map(|l| l.3.split_whitespace()).collect();
        let expected: String = title.split_whitespace().collect();
        assert_eq!(shown, expected, "{size:?}");
        for (x, anchor, font_px, text) in &lines {
            let w = width_bound(text, *font_px);
            assert_eq!(anchor, "middle", "{text}");
            assert!(
                x - w / 2.0 >= 0.0 && x + w / 2.0 <= width,
                "{size:?}: {text:?} spans {} to {} px",
                x - w / 2.0,
                x + w / 2.0
            );
        }
    }
    // A plot with nothing to draw says so under the same title, wrapped too.
    plot.series.clear();
    let svg = render_plot(&plot);
    let message = svg_texts(&svg);
    assert!(message.len() >= 2, "{message:?}");
    for (x, _, font_px, text) in &message {
        let w = width_bound(text, *font_px);
        assert!(
            x - w / 2.0 >= 0.0 && x + w / 2.0 <= f64::from(PLOT_SIZE.0),
            "{text:?}"
        );
    }
}

/// Legend labels are laid out by an upper bound of their glyph widths: a label too long for the
/// strip wraps onto rows of its own, and no legend text runs past the picture's right edge (a
/// Forrestal reference label was cut off when widths were estimated at a fixed 7.6 px a glyph).
#[test]
fn legend_labels_stay_within_the_plot_width() {
    let long = "Forrestal et al. (1994) penetration depth for a 6061-T6511 aluminium rod, \
                ogive nose, into 23 MPa concrete (digitised)";
    let mut plot = history_plot();
    plot.series[0].name = "Measured Within Wide Margins".to_string();
    plot.reference_lines[0].label = long.to_string();
    for size in [PLOT_SIZE, TREND_SIZE] {
        let svg = render_plot_sized(&plot, size);
        let width = f64::from(size.0);
        let texts = svg_texts(&svg);
        for (x, _, font_px, text) in texts.iter().filter(|t| t.1 == "start") {
            let w = width_bound(text, *font_px);
            assert!(
                x + w <= width,
                "{size:?}: {text:?} ends at {} px of {width}",
                x + w
            );
        }
        // Every word of the long label is drawn, in order.
        let shown: String = texts
            .iter()
            .filter(|t| t.1 == "start")
            .flat_map(|t| t.3.split_whitespace())
            .collect::<Vec<_>>()
            .join(" ");
        assert!(
            shown.contains(&long.split_whitespace().collect::<Vec<_>>().join(" ")),
            "{size:?}: {shown}"
        );
    }
}

/// In the tables of the material-point and cross-check sections, a failing metric of a case
/// known to fail reads `known failure` (amber), as the banner counts it; of any other case, FAIL.
#[test]
fn a_known_failures_metrics_read_known_failure_not_fail() {
    use impact_vv::report::records::{metric_markdown, metric_rows, metric_table};
    let mut case = pass_case();
    case.metrics[0].pass = false;
    assert_eq!(metric_rows(&case)[0][4], "FAIL");
    assert!(metric_markdown(&case, true).contains("**FAIL**"));
    case.known_failure = Some("a debt on record".into());
    assert_eq!(metric_rows(&case)[0][4], "known failure");
    assert!(!metric_markdown(&case, true).contains("FAIL"));
    let html = metric_table(&case, true);
    assert!(
        html.contains("known failure") && !html.contains(">fail<"),
        "{html}"
    );
}

/// A case that logged lines links its log file (relative to the run folder, where the page is);
/// a case that logged nothing has no link.
#[test]
fn a_case_with_a_log_links_it() {
    let dir = scratch("log");
    let mut run = results("run-log");
    run.cases[0].log_file = Some("cases/a__b/log.txt".into());
    let index = write_report(&dir, &run, &[], SECTIONS).unwrap();
    let page = fs::read_to_string(&index).unwrap();
    assert_eq!(
        page.matches("<a href=\"cases/a__b/log.txt\">log</a>")
            .count(),
        1
    );
    assert_eq!(
        page.matches(">log</a>").count(),
        1,
        "no link for cases without a log"
    );
}
