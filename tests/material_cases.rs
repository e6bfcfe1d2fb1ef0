//! The material-point cases of the catalogue (`cases/material/`, CATALOGUE "Concrete material").
//!
//! Their bands judge the microplane parameter set, which is still being calibrated, so a case may
//! fail today; these tests check what does not depend on the calibration: every case runs (no
//! error), every metric is measured, the record has its values, tables and plots with the targets
//! drawn, each case is fast, a failing or broken case does not stop the others, the report shows
//! the section, and the checks of the implementation itself (isotropy against Hooke, the rate
//! law's unit check, rate-independent stiffness, no healing) pass.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use impact_vv::case_file::{load_case, load_catalogue};
use impact_vv::case_kind::LoadedCase;
use impact_vv::case_kind::RunOptions;
use impact_vv::catalogue::Tier;
use impact_vv::material_point::{MaterialPointCase, MaterialRecord};
use impact_vv::registry::KINDS;
use impact_vv::registry::SECTIONS;
use impact_vv::report::write_report;
use impact_vv::results::{CaseResult, RunResults, Status};
use impact_vv::runner::run_cases;

fn options() -> RunOptions {
    RunOptions {
        output_dir: None,
        time_limit_s: 600.0,
        parallel: true,
        stop: None,
        verbose: false,
    }
}

fn material_cases() -> Vec<LoadedCase> {
    load_catalogue(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases"), &KINDS)
        .expect("catalogue loads")
        .into_iter()
        .filter(|c| c.kind.name() == "material_point")
        .collect()
}

fn metric<'a>(r: &'a CaseResult, name: &str) -> &'a impact_vv::results::MetricResult {
    r.metrics
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("{}: no metric `{name}`", r.id))
}

#[test]
fn every_material_case_runs_measures_and_draws_its_targets() {
    let cases = material_cases();
    let ids: Vec<&str> = cases.iter().map(|c| c.spec.id.as_str()).collect();
    for id in [
        "material/microplane-isotropy",
        "material/uniaxial-tension",
        "material/uniaxial-compression",
        "material/equal-biaxial",
        "material/hydrostatic",
        "material/cyclic",
        "material/crack-band",
        "material/rate-effect",
    ] {
        assert!(ids.contains(&id), "{id} missing from {ids:?}");
    }
    let results = run_cases(&cases, &options(), &|_| {});
    for (case, r) in cases.iter().zip(&results) {
        eprintln!("{:<36} {:?} {:.3} s", r.id, r.status, r.wall_s);
        for m in &r.metrics {
            eprintln!(
                "    {:<40} {:>14.6e} ref {:>12.4e} tol {:.1e} {}",
                m.name,
                m.value,
                m.reference,
                m.tolerance,
                if m.pass { "ok" } else { "FAIL" }
            );
        }
        // Runs to a verdict, pass or fail, never an error.
        assert!(
            matches!(r.status, Status::Pass | Status::Fail),
            "{}: {:?}: {:?}",
            r.id,
            r.status,
            r.message
        );
        // Every metric of the case is measured (a failed lookup would be missing here).
        assert_eq!(
            r.metrics.len(),
            case.spec.metrics.len(),
            "{}: {:?}",
            r.id,
            r.message
        );
        let record = r
            .record::<MaterialRecord>(MaterialRecord::KEY)
            .expect("a material record");
        assert!(
            !record.values.is_empty() && !record.plots.is_empty(),
            "{}",
            r.id
        );
        for p in &record.plots {
            assert!(
                p.plot.series.iter().any(|s| !s.x.is_empty()),
                "{}: plot `{}` is empty",
                r.id,
                p.plot.title
            );
            assert!(
                p.plot
                    .series
                    .iter()
                    .all(|s| s.x.len() == s.y.len() && s.x.len() <= 400),
                "{}: plot `{}`",
                r.id,
                p.plot.title
            );
            assert!(
                !p.plot.x_label.is_empty() && !p.plot.y_label.is_empty(),
                "{}: plot `{}` lacks axis labels",
                r.id,
                p.plot.title
            );
        }
        // Every judged metric is marked in the record's values.
        for m in &r.metrics {
            assert!(
                record.values.iter().any(|v| v.judged_by.contains(&m.name)),
                "{}: {} not marked",
                r.id,
                m.name
            );
        }
        // The quick tier runs in CI: a few seconds at most per case in release (generous for a
        // noisy two-core machine and for debug-assertion test builds).
        if case.spec.tier == Tier::Quick {
            assert!(r.wall_s < 10.0, "{}: {} s", r.id, r.wall_s);
        }
    }
    let by_id = |id: &str| results.iter().find(|r| r.id == id).expect(id);

    // Checks of the implementation, whatever the calibration.
    let isotropy = by_id("material/microplane-isotropy");
    assert_eq!(isotropy.status, Status::Pass, "{:?}", isotropy.message);
    let rate = by_id("material/rate-effect");
    for name in [
        "rate_law_unit_check_1e-3",
        "rate_law_unit_check_1",
        "rate_law_unit_check_10",
        "initial_slope_spread",
    ] {
        assert!(metric(rate, name).pass, "{name}: {:?}", metric(rate, name));
    }
    let cyclic = by_id("material/cyclic");
    for name in [
        "healed_uniaxial_strain",
        "healed_shear_normal",
        "healed_tension_shear",
        "healed_growing_tension",
    ] {
        assert!(metric(cyclic, name).pass, "{name}");
    }
    // Both settings of the trace term are recorded for every cycle.
    let cycles = cases
        .iter()
        .find(|c| c.spec.id == "material/cyclic")
        .and_then(|c| c.kind.as_any().downcast_ref::<MaterialPointCase>())
        .map(|m| m.spec.cycles.len())
        .unwrap();
    let record = cyclic
        .record::<MaterialRecord>(MaterialRecord::KEY)
        .unwrap();
    for setting in ["default (no trace term)", "with trace term"] {
        let recorded = record
            .values
            .iter()
            .filter(|v| v.quantity == "smallest_dissipation" && v.at.ends_with(setting))
            .count();
        assert_eq!(recorded, cycles, "{setting}");
    }

    // Targets are drawn: the tension peak window, the crack-band GF band, the MC2010 curves.
    let tension = by_id("material/uniaxial-tension")
        .record::<MaterialRecord>(MaterialRecord::KEY)
        .unwrap();
    assert!(tension.plots.iter().any(|p| !p.boxes.is_empty()));
    let band = by_id("material/crack-band")
        .record::<MaterialRecord>(MaterialRecord::KEY)
        .unwrap();
    assert_eq!(
        band.values
            .iter()
            .filter(|v| v.quantity == "fracture_energy")
            .count(),
        3
    );
    assert!(band
        .plots
        .iter()
        .any(|p| p.plot.reference_lines.iter().any(|l| l.band.is_some())));
    assert!(band
        .plots
        .iter()
        .any(|p| p.dashed.iter().any(|d| d.starts_with("MC2010 bilinear"))));
    let compression = by_id("material/uniaxial-compression")
        .record::<MaterialRecord>(MaterialRecord::KEY)
        .unwrap();
    assert!(compression
        .values
        .iter()
        .any(|v| v.quantity == "mc2010_curve_misfit" && v.value.is_finite()));
    let rate_record = rate.record::<MaterialRecord>(MaterialRecord::KEY).unwrap();
    let dif_plots: Vec<_> = rate_record.plots.iter().filter(|p| p.log_x).collect();
    assert_eq!(dif_plots.len(), 2, "tension and compression DIF plots");
    assert!(dif_plots
        .iter()
        .all(|p| p.dashed.iter().any(|d| d == "fib MC2010")));

    // The report has the section, with one SVG per recorded plot, and summary.md its tables.
    let run = RunResults {
        run_id: "material-test".into(),
        commit: "test".into(),
        tier: "nightly".into(),
        cases: results.clone(),
        date: String::new(),
        machine: String::new(),
        threads: 1,
        versions: Default::default(),
        wall_s: 0.0,
    };
    let dir = std::env::temp_dir().join(format!("impact-vv-material-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let index = write_report(&dir, &run, &run.history_records(), SECTIONS).expect("report");
    let html = std::fs::read_to_string(index).unwrap();
    let start = html.find("id=\"concrete-material\"").expect("section");
    let section = &html[start..start + html[start..].find("</section>").unwrap()];
    let plots: usize = results
        .iter()
        .filter_map(|r| r.record::<MaterialRecord>(MaterialRecord::KEY))
        .map(|m| m.plots.len())
        .sum();
    assert_eq!(section.matches("<svg").count(), plots);
    assert!(!section.contains("no data to plot"));
    assert!(section.contains("strain rate [/s]") && section.contains("[MPa]"));
    let md = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(md.contains("## Concrete material") && md.contains("material/crack-band"));
    // The results round-trip through results.json (the `report` command rebuilds from it).
    let json = std::fs::read_to_string(dir.join("results.json")).unwrap();
    let back: RunResults = serde_json::from_str(&json).expect("results.json reads back");
    assert_eq!(back.cases.len(), results.len());
    assert!(back
        .cases
        .iter()
        .all(|c| c.record::<MaterialRecord>(MaterialRecord::KEY).is_some()));
    std::fs::remove_dir_all(&dir).ok();
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("impact-vv-mp-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The `parameters:` part of the shipped parameter file (its own `calibration:` record, if any,
/// left out).
fn shipped_parameters() -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/materials/thesis-concrete.yaml"),
    )
    .unwrap();
    let mut out = String::new();
    let mut skipping = false;
    for line in text.lines() {
        if !line.starts_with([' ', '#']) && !line.is_empty() {
            skipping = line.starts_with("calibration:");
        }
        if !skipping {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

const TENSION_CASE: &str = "id: t
description: d
tier: quick
material_point: { material: concrete.yaml, experiment: uniaxial_tension }
metrics:
  - name: peak
    measure: { material_point: { quantity: peak_stress } }
    reference: { value: { value: 2.7, source: s } }
    tolerance: { relative: 0.03 }
";

#[test]
fn a_calibration_record_is_ignored_and_other_keys_are_refused() {
    let dir = scratch("calibration");
    std::fs::write(
        dir.join("concrete.yaml"),
        format!(
            "{}\ncalibration:\n  targets: {{ ft: 2.7e6 }}\n  residuals: [0.01, -0.02]\n",
            shipped_parameters()
        ),
    )
    .unwrap();
    std::fs::write(dir.join("case.yaml"), TENSION_CASE).unwrap();
    let case = load_case(&dir.join("case.yaml"), &KINDS).unwrap();
    let r = &run_cases(std::slice::from_ref(&case), &options(), &|_| {})[0];
    assert!(matches!(r.status, Status::Pass | Status::Fail), "{r:?}");
    assert_eq!(r.metrics.len(), 1);
    assert!(r.metrics[0].value > 0.0);

    std::fs::write(
        dir.join("concrete.yaml"),
        format!("{}\ntargets: {{ ft: 2.7e6 }}\n", shipped_parameters()),
    )
    .unwrap();
    let r = &run_cases(&[case], &options(), &|_| {})[0];
    assert_eq!(r.status, Status::Error);
    let m = r.message.clone().unwrap();
    assert!(m.contains("targets") && m.contains("concrete.yaml"), "{m}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_catalogue_says_what_is_wrong_with_a_material_case() {
    let dir = scratch("validate");
    let check = |body: &str, expected: &[&str]| {
        std::fs::write(dir.join("case.yaml"), body).unwrap();
        let e = load_case(&dir.join("case.yaml"), &KINDS)
            .unwrap_err()
            .to_string();
        for x in expected {
            assert!(e.contains(x), "`{x}` not in: {e}");
        }
    };
    // An option the experiment does not read.
    check(
        &TENSION_CASE.replace(
            "experiment: uniaxial_tension }",
            "experiment: uniaxial_tension, element_sizes: [0.05] }",
        ),
        &["element_sizes", "uniaxial_tension", "element_size, rate"],
    );
    // A quantity the experiment does not measure.
    check(
        &TENSION_CASE.replace("quantity: peak_stress", "quantity: biaxial_ratio"),
        &["biaxial_ratio", "peak_stress"],
    );
    // A scene measure in a material case, and a material measure in a scene case.
    check(
        &TENSION_CASE.replace(
            "{ material_point: { quantity: peak_stress } }",
            "energy_balance_error",
        ),
        &["metric `peak`", "not a measure of a material_point case"],
    );
    check(
        &TENSION_CASE.replace(
            "material_point: { material: concrete.yaml, experiment: uniaxial_tension }",
            "scene: { name: s, bodies: [], analysis: { static: {} } }",
        ),
        &["not a measure of a scene case", "`material_point`"],
    );
    // Required options.
    check(
        &TENSION_CASE
            .replace("uniaxial_tension }", "rate_effect, rates: [1.0e-5] }")
            .replace("quantity: peak_stress", "quantity: tension_peak_ratio"),
        &["relative_to"],
    );
    check(
        &TENSION_CASE.replace("uniaxial_tension }", "crack_band }"),
        &["element_sizes"],
    );
    // A typo in the measure.
    check(
        &TENSION_CASE.replace("quantity: peak_stress", "quantity: peak_stress, sise: 1"),
        &["unknown field `sise`"],
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_broken_material_case_is_an_error_of_its_own_and_the_others_still_run() {
    let dir = scratch("broken");
    std::fs::write(dir.join("concrete.yaml"), shipped_parameters()).unwrap();
    // An element far beyond the crack band's limit: the model refuses it.
    std::fs::write(
        dir.join("huge.yaml"),
        TENSION_CASE.replace("id: t", "id: huge").replace(
            "uniaxial_tension }",
            "uniaxial_tension, element_size: 10.0 }",
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("missing.yaml"),
        TENSION_CASE
            .replace("id: t", "id: missing")
            .replace("concrete.yaml", "no-such-file.yaml"),
    )
    .unwrap();
    std::fs::write(
        dir.join("fine.yaml"),
        TENSION_CASE.replace("id: t", "id: fine"),
    )
    .unwrap();
    let cases: Vec<LoadedCase> = ["huge", "missing", "fine"]
        .iter()
        .map(|n| load_case(&dir.join(format!("{n}.yaml")), &KINDS).unwrap())
        .collect();
    let results = run_cases(&cases, &options(), &|_| {});
    assert_eq!(results[0].status, Status::Error);
    assert!(
        results[0].message.as_ref().unwrap().contains("snap"),
        "{:?}",
        results[0].message
    );
    assert_eq!(results[1].status, Status::Error);
    assert!(results[1]
        .message
        .as_ref()
        .unwrap()
        .contains("no-such-file.yaml"));
    assert!(matches!(results[2].status, Status::Pass | Status::Fail));
    std::fs::remove_dir_all(dir).ok();
}
