//! The report writer: the page shows every case, escapes what it quotes, draws every plot, and
//! survives bad plot data; the history file round-trips and tolerates a bad line.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::fs;
use std::path::PathBuf;

use impact_vv::registry::SECTIONS;
use impact_vv::report::plot::{render_plot_sized, PLOT_SIZE, TREND_SIZE};
use impact_vv::report::summary::worst_text;
use impact_vv::report::text_fit::width_bound;
use impact_vv::report::{append_history, read_history, render_plot, write_report};
use impact_vv::results::{
    CaseResult, HistoryRecord, MetricResult, PlotData, ReferenceLine, RunResults, Series, Status,
    SweepLevel, SweepResult, ToleranceKind,
};

const PASS_ID: &str = "bar-wave-speed";
const FAIL_ID: &str = "cantilever-mesh-convergence";
const ERROR_ID: &str = "projectile-penetration";
const WORST: &str = "tip_deflection_error";
const NASTY: &str = "solver diverged: <script>alert('x')</script> & energy > 1e9";

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("impact-vv-report-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn metric(name: &str, value: f64, reference: f64, tolerance: f64, kind: &str) -> MetricResult {
    let error = match kind {
        "relative" => (value - reference).abs() / reference.abs(),
        _ => (value - reference).abs(),
    };
    MetricResult {
        name: name.to_string(),
        value,
        reference,
        error,
        tolerance,
        unit: "m/s".to_string(),
        pass: error <= tolerance,
        tolerance_kind: serde_json::from_value(serde_json::Value::String(kind.into())).unwrap(),
        reference_source: "c = sqrt(E/rho), Graff (1975) eq. 2.1.8".to_string(),
    }
}

/// A time history with a reference plateau and its acceptance band.
fn history_plot() -> PlotData {
    let t: Vec<f64> = (0..200).map(|i| i as f64 * 1e-6).collect();
    let v: Vec<f64> = t
        .iter()
        .map(|t| 3000.0 * (1.0 - (-t / 2e-5).exp()))
        .collect();
    PlotData {
        title: "Particle velocity at x = 0.5 m".to_string(),
        x_label: "time [s]".to_string(),
        y_label: "velocity [m/s]".to_string(),
        series: vec![Series {
            name: "solver".to_string(),
            x: t,
            y: v,
        }],
        reference_lines: vec![ReferenceLine {
            label: "plateau (analytic)".to_string(),
            y: 3000.0,
            band: Some([2940.0, 3060.0]),
        }],
        log_log: false,
    }
}

fn pass_case() -> CaseResult {
    CaseResult {
        id: PASS_ID.to_string(),
        variant: "explicit-lumped".to_string(),
        status: Status::Pass,
        wall_s: 1.234,
        metrics: vec![
            metric("wave_speed", 3510.0, 3500.0, 0.02, "relative"),
            metric("plateau_velocity", 2990.0, 3000.0, 60.0, "absolute"),
        ],
        description: "Elastic bar struck at one end: the front travels at c.".to_string(),
        tier: "smoke".to_string(),
        tags: vec!["wave".to_string(), "1d".to_string()],
        message: Some("plan: 200 steps of 1e-6 s, 4000 elements".to_string()),
        plots: vec![history_plot()],
        sweep: None,
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

fn level(h: f64, wall_s: f64, deflection: f64, frequency: f64) -> SweepLevel {
    SweepLevel {
        parameter: h,
        wall_s,
        errors: BTreeMap::from([
            (WORST.to_string(), deflection),
            ("frequency_error".to_string(), frequency),
        ]),
        values: BTreeMap::new(),
        status: impact_vv::results::LevelStatus::Completed,
    }
}

fn fail_case() -> CaseResult {
    let sweep = SweepResult {
        parameter: "element size [m]".to_string(),
        levels: vec![
            level(0.1, 0.05, 4e-2, 1e-2),
            level(0.05, 0.31, 2.1e-2, 2.6e-3),
            level(0.025, 2.2, 1.1e-2, 6.4e-4),
            level(0.0125, 17.0, 5.6e-3, 1.6e-4),
        ],
        observed_order: BTreeMap::from([
            (WORST.to_string(), 0.95),
            ("frequency_error".to_string(), 2.0),
        ]),
    };
    CaseResult {
        id: FAIL_ID.to_string(),
        variant: "explicit-lumped".to_string(),
        status: Status::Fail,
        wall_s: 19.6,
        metrics: vec![
            metric("frequency", 101.0, 100.0, 0.05, "relative"),
            metric(WORST, 0.1056, 0.1, 0.001, "absolute"),
        ],
        description: "Cantilever under tip load, refined four times.".to_string(),
        tier: "nightly".to_string(),
        tags: vec!["convergence".to_string()],
        message: Some("tip deflection order 0.95 < expected 2".to_string()),
        plots: vec![],
        sweep: Some(sweep),
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

fn error_case() -> CaseResult {
    CaseResult {
        id: ERROR_ID.to_string(),
        variant: "explicit-lumped".to_string(),
        status: Status::Error,
        wall_s: 0.2,
        metrics: vec![],
        description: "Steel projectile into a concrete slab.".to_string(),
        tier: "nightly".to_string(),
        tags: vec![],
        message: Some(NASTY.to_string()),
        plots: vec![],
        sweep: None,
        contact: None,
        phase_seconds: Default::default(),
        fast_update_share: None,
        records: Default::default(),
        known_failure: None,
        log_file: None,
    }
}

fn results(run_id: &str) -> RunResults {
    RunResults {
        run_id: run_id.to_string(),
        commit: "50c344d".to_string(),
        tier: "nightly".to_string(),
        cases: vec![pass_case(), fail_case(), error_case()],
        date: "2025-01-03T10:00:00Z".to_string(),
        machine: "ci-runner-7 (16 cores)".to_string(),
        threads: 16,
        versions: BTreeMap::from([
            ("impact-solver".to_string(), "0.1.0".to_string()),
            ("rustc".to_string(), "1.85.0".to_string()),
        ]),
        wall_s: 21.0,
    }
}

/// Three runs: two earlier ones with drifting values, then the current run.
fn three_run_history(current: &RunResults) -> Vec<HistoryRecord> {
    let mut history = Vec::new();
    for (run, drift) in [("run-1", 0.97), ("run-2", 0.99)] {
        for mut record in current.history_records() {
            record.run_id = run.to_string();
            record.wall_s *= drift;
            record.metrics.values_mut().for_each(|v| *v *= drift);
            history.push(record);
        }
    }
    history.extend(current.history_records());
    history
}

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
