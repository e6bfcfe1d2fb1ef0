//! The report's "Penetration and remeshing" section (issue 21) on a small run that remeshes:
//! a soft block sheared by its boundary and remeshed as it distorts (as in
//! `solver/tests/remesh_run.rs`), run through `analysis::execute` into a case's folder as the
//! runner does; then the record is read from the files it wrote and the page is rendered.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

/// The integration tests' builders of the solver crate (the sheared box).
#[path = "../solver/tests/common/mod.rs"]
mod common;

use std::fs;
use std::path::{Path, PathBuf};

use impact_solver::analysis::{execute, ExecuteOptions};
use impact_solver::dynamics::ExplicitSettings;
use impact_solver::material::{IsotropicElastic, MaterialModel};
use impact_solver::mesh::ops::check_distortion;
use impact_solver::model::Model;
use impact_solver::problem::Problem;
use impact_solver::remesh::{RemeshSettings, REMESHING_CSV_HEADER};
use impact_solver::scene::{Analysis, ExplicitAnalysis};
use impact_vv::registry::SECTIONS;
use impact_vv::report::penetration::{
    read_record, read_remeshings, record, PenetrationRecord, KEY,
};
use impact_vv::report::write_report;
use impact_vv::results::{case_dir, CaseResult, PlotData, RunResults, Series, Status};

const ID: &str = "penetration/sheared-block";
const SIZE: f64 = 0.1;
const END: f64 = 0.02;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "impact-vv-penetration-{name}-{}",
        std::process::id()
    ));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the sheared block (Saint-Venant-Kirchhoff, 4 x 4 x 4 cells, interior nodes perturbed)
/// into `dir` with stem `run`, remeshing at 1.3 times the initial worst collapse ratio with the
/// extra `remeshing` options; returns the top face's x displacement against time, and whether
/// the run completed.
fn sheared_block_run(dir: &Path, remeshing: &str) -> (Vec<f64>, Vec<f64>, bool) {
    let soft = IsotropicElastic {
        density: 1000.0,
        youngs_modulus: 1.0e7,
        poisson_ratio: 0.3,
    };
    let mesh = common::box_body([SIZE; 3], [4, 4, 4], 0.3, 11);
    let model = Model::new(vec![(
        "block".into(),
        mesh,
        MaterialModel::SaintVenantKirchhoff(soft),
    )])
    .unwrap();
    let mut p = Problem::new(model);
    common::shear_the_box(&mut p, [SIZE; 3], 1.0 / END);
    let initial = check_distortion(&p.model.reference, &p.model.tets, f64::INFINITY).worst_ratio;
    let mut settings = ExplicitSettings::new(END);
    settings.safety = 0.5;
    settings.history_interval = Some(END / 100.0);
    let yaml = format!(
        "{{ body: block, check_every: 5, collapse_limit: {}, {remeshing} }}",
        1.3 * initial
    );
    let analysis = Analysis::Explicit(ExplicitAnalysis {
        settings,
        remeshing: Some(serde_norway::from_str::<RemeshSettings>(&yaml).unwrap()),
    });
    let options = ExecuteOptions {
        out: Some(dir),
        stem: "run",
        final_state: true,
        fields: false,
        time_limit_s: None,
        stop: None,
        ranks: None,
        log: &impact_solver::analysis::log_to_stderr,
    };
    match execute(&mut p, &analysis, &options, &mut |_| {}) {
        Ok(run) => {
            let h = run.history.unwrap();
            (h.column("time").unwrap(), h.column("top_x").unwrap(), true)
        }
        Err(_) => (Vec::new(), Vec::new(), false),
    }
}

fn case_result(plots: Vec<PlotData>) -> CaseResult {
    serde_json::from_value(serde_json::json!({
        "id": ID,
        "variant": "default",
        "status": "pass",
        "wall_s": 1.0,
        "metrics": [],
        "description": "a sheared block remeshed as it distorts",
        "tags": ["penetration", "remeshing"],
    }))
    .map(|mut c: CaseResult| {
        c.plots = plots;
        c
    })
    .unwrap()
}

fn results(case: CaseResult) -> RunResults {
    serde_json::from_value(serde_json::json!({
        "run_id": "penetration-test",
        "commit": "abc1234",
        "tier": "quick",
        "date": "2025-01-01",
        "machine": "test",
        "threads": 1,
        "wall_s": 1.0,
        "cases": [case],
    }))
    .unwrap()
}

/// The section of a completed run: the displacement curve, one table row per remeshing (the
/// CSV's), the pictures at the start, after remeshings and at the end with their times, and the
/// two near-tip plots; the case's own section links to it and `results.json` holds the record.
#[test]
fn the_section_shows_curves_table_pictures_and_near_tip_stress() {
    let run_dir = scratch("completed");
    let dir = case_dir(&run_dir, ID);
    fs::create_dir_all(&dir).unwrap();
    let (t, x, completed) = sheared_block_run(
        &dir,
        "section: { axis: z, value: 0.0 }, near_tip: { probe: top, radius: 0.04, steps: 5 }",
    );
    assert!(completed);
    let plot = PlotData {
        title: "Top face displacement".into(),
        x_label: "time (s)".into(),
        y_label: "displacement (m)".into(),
        series: vec![Series {
            name: "top_x".into(),
            x: t,
            y: x,
        }],
        reference_lines: Vec::new(),
        log_log: false,
    };
    let mut case = case_result(vec![plot]);
    record(&mut case, &dir, "run");
    let r: PenetrationRecord = case.record(KEY).unwrap();
    let csv_rows = fs::read_to_string(dir.join("run_remeshing.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert!(r.remeshings.len() >= 2, "{} remeshings", r.remeshings.len());
    assert_eq!(r.remeshings.len(), csv_rows);
    assert_eq!(r.pictures.len(), r.remeshings.len() + 2);
    assert!(r.near_tip.iter().any(|p| p.offset == -5));
    assert!(r.near_tip.iter().any(|p| p.offset == 5));
    for w in r.remeshings.windows(2) {
        assert!(w[1].time > w[0].time);
        assert!(
            w[1].elements[0] == w[0].elements[1],
            "the next starts where one ended"
        );
    }

    let results = results(case);
    let index = write_report(&run_dir, &results, &[], SECTIONS).unwrap();
    let html = fs::read_to_string(index).unwrap();
    assert!(html.contains("<section id=\"penetration\">"));
    assert!(html.contains("<h2>Penetration and remeshing</h2>"));
    let part = &html[html.find("<section id=\"penetration\">").unwrap()..];
    let part = &part[..part.find("</section>").unwrap()];
    assert!(
        part.contains("Top face displacement"),
        "the displacement plot"
    );
    assert!(part.contains(&format!("Remeshings ({})", r.remeshings.len())));
    assert_eq!(
        part.matches("<td class=\"num\">").count() % r.remeshings.len(),
        0,
        "the table's numeric cells"
    );
    let first = &r.remeshings[0];
    assert!(part.contains(&format!("{} → {}", first.elements[0], first.elements[1])));
    // All the pictures (fewer than the most shown), each with its time and state.
    assert_eq!(part.matches("clipPath id=").count(), r.pictures.len());
    assert!(part.contains("t = 0 µs, start") || part.contains("t = 0 ms, start"));
    assert!(part.contains("after remeshing 1"));
    assert!(part.contains(&format!("end ({} remeshings)", r.remeshings.len())));
    assert!(part.contains("Largest von Mises stress near the tip"));
    assert!(part.contains("Mean pressure near the tip"));
    assert!(
        html.contains("href=\"#penetration-"),
        "the case's link to its part"
    );
    let md = fs::read_to_string(run_dir.join("summary.md")).unwrap();
    assert!(md.contains("## Penetration and remeshing"));
    assert!(md.contains(ID));
    // results.json carries the record, and reads back.
    let json = fs::read_to_string(run_dir.join("results.json")).unwrap();
    let back: RunResults = serde_json::from_str(&json).unwrap();
    assert_eq!(back.cases[0].record::<PenetrationRecord>(KEY), Some(r));
    let _ = fs::remove_dir_all(&run_dir);
}

/// A run that stops at its second remeshing (at most one allowed) keeps the first remeshing's
/// row and its pictures: the record is read from what it wrote; a run without `section` and
/// `near_tip` has a record without pictures, whose section says so; a run that did not remesh
/// has none, and the page no section.
#[test]
fn a_failed_run_still_has_its_section_and_a_case_without_remeshing_none() {
    let run_dir = scratch("failed");
    let dir = case_dir(&run_dir, ID);
    fs::create_dir_all(&dir).unwrap();
    let (_, _, completed) = sheared_block_run(&dir, "max_remeshings: 1, section: { axis: z }");
    assert!(!completed);
    let r = read_record(&dir, "run").unwrap().unwrap();
    assert_eq!(r.remeshings.len(), 1);
    assert_eq!(
        r.pictures,
        ["run_mesh_0.json", "run_mesh_1.json", "run_mesh_2.json"]
    );
    assert!(r.near_tip.is_empty());
    let mut case = case_result(Vec::new());
    case.status = Status::Fail;
    record(&mut case, &dir, "run");
    let html =
        fs::read_to_string(write_report(&run_dir, &results(case), &[], SECTIONS).unwrap()).unwrap();
    assert!(html.contains("Remeshings (1)"));
    assert!(html.contains("end (1 remeshings)"));
    assert!(html.contains("the case has no plot of a velocity or displacement"));
    assert!(html.contains("not recorded: the case&#39;s remeshing settings have no `near_tip`"));

    let none = scratch("none");
    assert_eq!(read_record(&none, "run").unwrap(), None);
    let mut case = case_result(Vec::new());
    record(&mut case, &none, "run");
    assert!(!case.records.contains_key(KEY));
    let html =
        fs::read_to_string(write_report(&none, &results(case), &[], SECTIONS).unwrap()).unwrap();
    assert!(!html.contains("Penetration and remeshing"));
    let _ = fs::remove_dir_all(&run_dir);
    let _ = fs::remove_dir_all(&none);
}

/// The remeshing CSV is read by its header: the jumps are after minus before, NaN reads, a
/// header of another version or a short row is an error naming the file and line.
#[test]
fn the_remeshing_csv_reads_by_its_header_and_bad_files_are_errors() {
    let dir = scratch("csv");
    let path = dir.join("x_remeshing.csv");
    fs::write(
        &path,
        format!(
            "{REMESHING_CSV_HEADER}\n1e-5,10,20,12.5,4,3,2.5,1,NaN,0.25,1e-9,2e-8,0,0e0,22.5,9.9,7,3,2.5e-6,0,12,0.125,1.05\n"
        ),
    )
    .unwrap();
    let rows = read_remeshings(&path).unwrap();
    assert_eq!(rows.len(), 1);
    let r = &rows[0];
    assert_eq!((r.time, r.elements), (1e-5, [10, 20]));
    assert_eq!(r.worst_collapse, [12.5, 4.0]);
    assert_eq!(r.kinetic_jump, -0.5);
    assert!(r.stored_jump.is_nan());
    assert_eq!((r.total_energy_jump, r.momentum_jump), (0.25, 1e-9));
    assert_eq!(r.added_mass, 2.5e-6);
    assert_eq!(r.kinetic_restored, 0.125);

    fs::write(&path, "time,elements\n1,2\n").unwrap();
    let e = read_remeshings(&path).unwrap_err().to_string();
    assert!(e.contains("header"), "{e}");
    fs::write(&path, format!("{REMESHING_CSV_HEADER}\n1,2,3\n")).unwrap();
    let e = read_remeshings(&path).unwrap_err().to_string();
    assert!(e.contains("line 2") && e.contains("3 values"), "{e}");
    let _ = fs::remove_dir_all(&dir);
}
