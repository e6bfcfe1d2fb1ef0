//! The report writer: the page shows every case, escapes what it quotes, draws every plot, and
//! survives bad plot data; the history file round-trips and tolerates a bad line.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::fs;

use impact_vv::registry::SECTIONS;
use impact_vv::report::{append_history, read_history, render_plot, write_report};
use impact_vv::results::{CaseResult, PlotData, ReferenceLine, RunResults, Series, Status};

mod report_common;
use report_common::*;

/// Asserts that two JSON trees are equal, numbers to within a few ulps: serde_json without its
/// `float_roundtrip` feature may parse a 17-digit number to a neighbouring double.
fn assert_same_up_to_last_bit(a: &serde_json::Value, b: &serde_json::Value, path: &str) {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(
                (x - y).abs() <= 4.0 * f64::EPSILON * x.abs().max(y.abs()),
                "{path}: {x} != {y}"
            );
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{path}: lengths differ");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                assert_same_up_to_last_bit(x, y, &format!("{path}[{i}]"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{path}: keys differ"
            );
            for (k, v) in x {
                assert_same_up_to_last_bit(v, &y[k], &format!("{path}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{path}"),
    }
}

/// The page, the Markdown summary and results.json of a run with a pass, a failing sweep and an
/// error.
#[test]
fn report_shows_every_case_and_escapes_messages() {
    let dir = scratch("full");
    let run = results("run-3");
    let index = write_report(&dir, &run, &three_run_history(&run), SECTIONS).unwrap();
    assert_eq!(index, dir.join("index.html"));
    let page = fs::read_to_string(&index).unwrap();
    eprintln!("report written to {}", index.display());

    for id in [PASS_ID, FAIL_ID, ERROR_ID] {
        assert!(page.contains(id), "page lacks case {id}");
    }
    let summary_table =
        &page[page.find("id=\"summary\"").unwrap()..page.find("class=\"case\"").unwrap()];
    assert!(
        summary_table.contains(WORST),
        "summary lacks the worst metric of the failing case"
    );

    // 1 case plot each for the pass case, convergence + work-precision for the sweep, and the
    // trends: 2 metrics + wall time for the two cases with metrics, wall time for the error.
    let expected = [1, 2, 3, 3, 1].iter().sum::<usize>();
    let svgs = page.matches("<svg").count();
    assert!(svgs >= expected, "only {svgs} of {expected} plots");
    assert!(page.contains(&format!("Convergence: {FAIL_ID}")));
    assert!(page.contains(&format!("Work-precision: {FAIL_ID}")));
    assert!(page.contains("wave_speed per run"));
    assert!(!page.contains("no trend yet"));

    assert!(page.contains("&lt;script&gt;"));
    assert!(
        !page.contains("<script"),
        "the page has no scripts and quotes none unescaped"
    );
    assert!(page.contains("&amp; energy &gt; 1e9"));

    let md = fs::read_to_string(dir.join("summary.md")).unwrap();
    let failures = &md[md.find("## Failures").expect("summary.md lists failures")..];
    assert!(failures.contains(FAIL_ID) && failures.contains(WORST));
    assert!(failures.contains(ERROR_ID));
    assert!(!failures.contains(PASS_ID));

    let json = fs::read_to_string(dir.join("results.json")).unwrap();
    let back: RunResults = serde_json::from_str(&json).unwrap();
    assert_same_up_to_last_bit(
        &serde_json::to_value(&back).unwrap(),
        &serde_json::to_value(&run).unwrap(),
        "results",
    );
    // Set IMPACT_VV_KEEP_REPORT to look at the page in a browser.
    if std::env::var_os("IMPACT_VV_KEEP_REPORT").is_none() {
        let _ = fs::remove_dir_all(&dir);
    }
}

/// A first run has nothing to trend against, and says so.
#[test]
fn first_run_has_no_trend() {
    let dir = scratch("first");
    let run = results("run-1");
    let page =
        fs::read_to_string(write_report(&dir, &run, &run.history_records(), SECTIONS).unwrap())
            .unwrap();
    assert_eq!(page.matches("no trend yet (first run)").count(), 3);
    assert!(page.contains("1 passed · 1 failed · 1 error"));
    let _ = fs::remove_dir_all(&dir);
}

fn plot(series: Vec<Series>, log_log: bool) -> PlotData {
    PlotData {
        title: "robustness".to_string(),
        x_label: "x".to_string(),
        y_label: "y".to_string(),
        series,
        reference_lines: vec![ReferenceLine {
            label: "ref".to_string(),
            y: f64::NAN,
            band: Some([-1.0, f64::INFINITY]),
        }],
        log_log,
    }
}

fn series(x: &[f64], y: &[f64]) -> Series {
    Series {
        name: "s".to_string(),
        x: x.to_vec(),
        y: y.to_vec(),
    }
}

/// NaN, infinities, empty series, non-positive values on log axes and constant curves render
/// without panicking; a plot with nothing drawable says "no data".
#[test]
fn render_plot_survives_bad_data() {
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let cases = [
        plot(vec![], false),
        plot(vec![series(&[], &[])], false),
        plot(vec![series(&[nan, inf], &[1.0, nan])], true),
        plot(
            vec![series(&[1.0, 2.0, 3.0], &[nan, 2.0, inf]), series(&[], &[])],
            false,
        ),
        plot(vec![series(&[1.0, 2.0, 3.0], &[5.0, 5.0, 5.0])], false),
        plot(vec![series(&[1.0, 2.0, 3.0], &[0.0, 0.0, 0.0])], false),
        plot(
            vec![series(&[-1.0, 0.0, 1.0, 10.0], &[1.0, -2.0, 1e-3, 0.0])],
            true,
        ),
        plot(vec![series(&[1e-3, 1e-3], &[7.0, 7.0])], true),
        plot(vec![series(&[1.0, 2.0], &[1e300, -1e300])], false),
        plot(vec![series(&[1.0, 2.0, 3.0], &[1.0, 2.0])], false),
    ];
    for (i, p) in cases.iter().enumerate() {
        let svg = render_plot(p);
        assert!(svg.starts_with("<svg"), "case {i}: {svg}");
        assert!(svg.trim_end().ends_with("</svg>"), "case {i}");
    }
    assert!(render_plot(&cases[0]).contains("no data"));
    assert!(render_plot(&cases[2]).contains("no data"));
    assert!(!render_plot(&cases[4]).contains("no data"));
}

/// Appended records read back; a corrupt line is skipped; a missing file is an empty history.
#[test]
fn history_round_trips_and_skips_bad_lines() {
    let dir = scratch("history");
    let path = dir.join("reports").join("history.jsonl");
    assert!(read_history(&path).unwrap().is_empty());

    let first = results("run-1").history_records();
    let second = results("run-2").history_records();
    append_history(&path, &first).unwrap();
    fs::OpenOptions::new()
        .append(true)
        .open(&path)
        .and_then(|mut f| std::io::Write::write_all(&mut f, b"{\"run_id\": truncated\n\n"))
        .unwrap();
    append_history(&path, &second).unwrap();

    let read = read_history(&path).unwrap();
    assert_eq!(read, [first, second].concat());
    let _ = fs::remove_dir_all(&dir);
}

/// JSON has no NaN: a NaN metric is left out of the history line instead of losing the line.
#[test]
fn non_finite_metrics_do_not_lose_history_lines() {
    let dir = scratch("nan");
    let path = dir.join("history.jsonl");
    let mut records = results("run-1").history_records();
    records[0].metrics.insert("diverged".to_string(), f64::NAN);
    append_history(&path, &records).unwrap();
    let read = read_history(&path).unwrap();
    assert_eq!(read.len(), records.len());
    assert!(!read[0].metrics.contains_key("diverged"));
    let _ = fs::remove_dir_all(&dir);
}

// ---- Contact algorithms -------------------------------------------------------------------

use impact_solver::contact::problem_file::ProblemFile;
use impact_vv::contact_compare::{describe, Comparison, ComparisonRow, NORMALISATION};
use impact_vv::results::ContactSolverStats;

const COMPARISON_ID: &str = "contact/external-problems";
const SOLVER_CASE_ID: &str = "contact/spheres-headon";

fn compare_row(
    problem: &str,
    solver: &str,
    tolerance: f64,
    error: f64,
    seconds: f64,
) -> ComparisonRow {
    ComparisonRow {
        problem: problem.into(),
        solver: solver.into(),
        tolerance,
        error,
        absolute_error: error,
        iterations: 12,
        outer_iterations: 1,
        seconds,
        repeats: 3,
        status: if error <= tolerance {
            "converged"
        } else {
            "max-iterations"
        }
        .into(),
        solved: error <= tolerance,
        notes: vec![],
    }
}

/// Two problems, two solvers, two tolerances; conic/coulomb misses 1e-8 on `p2`.
fn comparison_case() -> CaseResult {
    let problem = serde_json::from_str::<ProblemFile>(
        r#"{ "format": "contact-problem/1", "dimension": 3, "contacts": 1, "mu": [0.3],
             "q": [-1, 0, 0], "W": { "rows": 3, "cols": 3,
             "triplets": [[0, 0, 2.0], [1, 1, 1.0], [2, 2, 1.0]] } }"#,
    )
    .unwrap()
    .to_problem("p")
    .unwrap();
    let mut rows = Vec::new();
    for p in ["p1", "p2"] {
        for (tol, gs, conic) in [
            (1e-4, 5e-5, 2e-5),
            (1e-8, 3.5e-9, if p == "p2" { 4e-6 } else { 1e-9 }),
        ] {
            rows.push(compare_row(p, "gauss-seidel/exact", tol, gs, 0.002));
            rows.push(compare_row(p, "conic/coulomb", tol, conic, 0.001));
        }
    }
    let mut case = error_case();
    case.id = COMPARISON_ID.into();
    case.variant = "default".into();
    case.status = Status::Pass;
    case.message = None;
    let comparison = Comparison {
        normalisation: NORMALISATION.into(),
        tolerances: vec![1e-4, 1e-8],
        time_limit_s: 10.0,
        solvers: vec!["gauss-seidel/exact".into(), "conic/coulomb".into()],
        problems: vec![
            describe(&problem, "p1", "p1.json"),
            describe(&problem, "p2", "p2.json"),
        ],
        unreadable: vec![],
        rows,
    };
    case.set_record(Comparison::KEY, &comparison);
    case
}

/// One variant of a contact case with a sweep: `contact_seconds` over 100 steps with contact.
fn solver_variant(variant: &str, solver: &str, status: Status, contact_seconds: f64) -> CaseResult {
    let mut case = fail_case();
    case.id = SOLVER_CASE_ID.into();
    case.variant = variant.into();
    case.status = status;
    case.contact = Some(ContactSolverStats {
        solver: solver.into(),
        steps_with_contact: 100,
        solves: 200,
        not_converged: 10,
        unresolved: 3,
        iterations: 5000,
        contact_seconds,
    });
    case
}

fn contact_results() -> RunResults {
    let mut run = results("run-contact");
    run.cases = vec![
        comparison_case(),
        solver_variant("gauss-seidel", "gauss-seidel", Status::Pass, 2.0),
        solver_variant("conic", "conic/coulomb", Status::Pass, 1.0),
        // Cheaper still, but failing: not the fastest among the passing.
        solver_variant("conic-relaxed", "conic/relaxed", Status::Fail, 0.1),
        pass_case(),
    ];
    run
}

/// The cells of the table row whose first cell is `first`, within `html`.
fn row_cells<'a>(html: &'a str, first: &str) -> &'a str {
    let start = html
        .find(&format!("<tr><td>{first}</td>"))
        .unwrap_or_else(|| panic!("no row starting with {first}"));
    &html[start..start + html[start..].find("</tr>").unwrap()]
}

/// The text of `html` without its tags, runs of white space made one space: what a reader sees
/// of titles drawn as several SVG `<text>` lines.
fn visible_text(html: &str) -> String {
    let mut text = String::new();
    let mut in_tag = false;
    for c in html.chars() {
        match c {
            '<' => {
                in_tag = true;
                text.push(' ');
            }
            '>' => in_tag = false,
            c if !in_tag => text.push(c),
            _ => {}
        }
    }
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn contact_algorithms_section_shows_comparisons_solver_tables_and_diagrams() {
    let dir = scratch("contact");
    let run = contact_results();
    let page =
        fs::read_to_string(write_report(&dir, &run, &run.history_records(), SECTIONS).unwrap())
            .unwrap();
    let start = page
        .find("<section id=\"contact-algorithms\">")
        .expect("the section");
    let section = &page[start..start + page[start..].find("</section>").unwrap()];
    assert!(section.contains("<h2>Contact algorithms</h2>"));

    // (a) The comparison: problems, per-tolerance errors, profiles and work-precision.
    assert!(section.contains(&format!("{COMPARISON_ID}: 2 problems, 2 solvers")));
    assert!(section.contains("Tolerance 1e-8"));
    let p2 = row_cells(&section[section.find("Tolerance 1e-8").unwrap()..], "p2");
    assert!(
        p2.contains("3.5e-9 ✓") && p2.contains("4e-6 ✗ max-iterations"),
        "{p2}"
    );
    // At 1e-8 conic/coulomb solves p1 only, in half gauss-seidel's time: 1/2 fastest each.
    let summary = row_cells(section, "conic/coulomb");
    assert!(summary.contains("<td>1e-4</td><td>2/2</td>"), "{summary}");
    assert!(section.contains("<td>conic/coulomb</td><td>1e-8</td><td>1/2</td>"));
    for title in [
        "Performance profile, tolerance 1e-4",
        "Performance profile, tolerance 1e-8",
        "Work-precision (all problems)",
    ] {
        assert!(section.contains(title), "no plot {title}");
    }

    // (b) The catalogue case under three contact solvers.
    assert!(section.contains(&format!("{SOLVER_CASE_ID}: contact solvers")));
    let conic = row_cells(section, "conic");
    assert!(conic.contains("fastest"), "{conic}");
    assert!(
        conic.contains("<td>10 (5%)</td>"),
        "not converged count and share: {conic}"
    );
    assert!(
        conic.contains("<td>25</td>"),
        "mean iterations per solve: {conic}"
    );
    assert!(
        conic.contains("<td>0.01 s</td>"),
        "contact time per step: {conic}"
    );
    assert!(!row_cells(section, "gauss-seidel").contains("fastest"));
    assert!(!row_cells(section, "conic-relaxed").contains("fastest"));
    assert!(section.contains("Fastest among the passing variants: conic, 0.01 s"));

    // (c) One work-precision diagram per swept metric, one curve per solver variant; their
    // titles are wrapped onto lines, so they are read as the reader sees them.
    let seen = visible_text(section);
    assert!(seen.contains(&format!(
        "Work-precision by solver: {SOLVER_CASE_ID}, {WORST}"
    )));
    assert!(seen.contains(&format!(
        "Work-precision by solver: {SOLVER_CASE_ID}, frequency_error"
    )));

    let md = fs::read_to_string(dir.join("summary.md")).unwrap();
    let md_section = &md[md
        .find("## Contact algorithms")
        .expect("summary.md has the section")..];
    assert!(md_section.contains(COMPARISON_ID) && md_section.contains("| p2 |"));
    assert!(md_section.contains("Fastest among the passing variants: conic"));

    // results.json keeps the comparison.
    let back: RunResults =
        serde_json::from_str(&fs::read_to_string(dir.join("results.json")).unwrap()).unwrap();
    assert_eq!(
        back.cases[0].records[Comparison::KEY],
        run.cases[0].records[Comparison::KEY]
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_run_without_contact_solvers_has_no_contact_section_and_old_results_load() {
    let dir = scratch("no-contact");
    let run = results("run-1");
    let page = fs::read_to_string(write_report(&dir, &run, &[], SECTIONS).unwrap()).unwrap();
    assert!(!page.contains("contact-algorithms"));
    assert!(!fs::read_to_string(dir.join("summary.md"))
        .unwrap()
        .contains("Contact algorithms"));
    // A results.json from before `contact` and `contact_comparison` existed.
    let old = r#"{"run_id": "old", "commit": "abc", "tier": "quick", "cases": [
        {"id": "a", "variant": "default", "status": "pass", "wall_s": 1.0, "metrics": []}]}"#;
    let old: RunResults = serde_json::from_str(old).unwrap();
    assert!(old.cases[0].contact.is_none() && old.cases[0].records.is_empty());
    assert!(write_report(&dir, &old, &[], SECTIONS).is_ok());
    let _ = fs::remove_dir_all(&dir);
}

// ---- How the page reads at a glance ---------------------------------------------------------
