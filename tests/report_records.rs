//! A kind's record that does not read as its type is an error on the page, in the kind's
//! section, naming the case and the field, and a warning of the run; a record that reads is
//! shown as before.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::fs;

use impact_vv::contact_compare::Comparison;
use impact_vv::material_point::MaterialRecord;
use impact_vv::registry::SECTIONS;
use impact_vv::report::beam::record_path;
use impact_vv::report::write_report;
use impact_vv::results::{case_dir, RunResults};
use serde_json::json;

mod report_common;
use report_common::*;

/// The part of `page` from the section `anchor` to its end.
fn section<'a>(page: &'a str, anchor: &str) -> &'a str {
    let start = page
        .find(&format!("<section id=\"{anchor}\">"))
        .unwrap_or_else(|| panic!("the page has no section {anchor}"));
    let end = page[start..].find("</section>").unwrap();
    &page[start..start + end]
}

#[test]
fn a_record_with_a_field_of_the_wrong_type_is_an_error_in_its_section() {
    let dir = scratch("records");
    let mut run: RunResults = results("run-records");
    // The material's name as a number, a comparison's problems as a string: each JSON, neither
    // of its kind's type.
    run.cases[0].records.insert(
        MaterialRecord::KEY.into(),
        json!({ "material": 5, "experiment": "uniaxial" }),
    );
    run.cases[1]
        .records
        .insert(Comparison::KEY.into(), json!({ "problems": "none" }));
    // A beam record file that is not a record.
    let beam = record_path(&case_dir(&dir, ERROR_ID), &run.cases[2].variant);
    fs::create_dir_all(beam.parent().unwrap()).unwrap();
    fs::write(&beam, "{ \"frames\": 3 }").unwrap();

    let page = fs::read_to_string(write_report(&dir, &run, &[], SECTIONS).unwrap()).unwrap();

    let material = section(&page, "concrete-material");
    assert!(material.contains("callout error"), "{material}");
    assert!(material.contains(PASS_ID), "{material}");
    assert!(
        material.contains("the `material` record does not read")
            && material.contains("invalid type: integer `5`, expected a string"),
        "{material}"
    );
    let contact = section(&page, "contact-algorithms");
    assert!(
        contact.contains(FAIL_ID) && contact.contains("`contact_comparison` record does not read"),
        "{contact}"
    );
    let beam_section = section(&page, "beam-failure-modes");
    assert!(
        beam_section.contains(ERROR_ID)
            && beam_section.contains(&format!(
                "`{}` record does not read",
                beam.file_name().unwrap().to_string_lossy()
            )),
        "{beam_section}"
    );
    let md = fs::read_to_string(dir.join("summary.md")).unwrap();
    let md_material = &md[md.find("## Concrete material").expect("summary.md has it")..];
    assert!(
        md_material.contains("**Error:**") && md_material.contains(PASS_ID),
        "{md_material}"
    );

    // `impact-vv report` on the same run folder says so in its log, once per record.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_impact-vv"))
        .arg("report")
        .arg(&dir)
        .arg("--reports")
        .arg(dir.join("reports"))
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    // Exit 2 is a report not written; the run's failing and erring cases give 1.
    assert_ne!(out.status.code(), Some(2), "{log}");
    let warnings: Vec<&str> = log.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 3, "{log}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains(PASS_ID) && w.contains("`material` record")),
        "{log}"
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_run_whose_records_read_has_no_error_block() {
    let dir = scratch("records-fine");
    let page = fs::read_to_string(write_report(&dir, &results("run-fine"), &[], SECTIONS).unwrap())
        .unwrap();
    assert!(!page.contains("does not read"));
    assert!(!page.contains("concrete-material"));
    let _ = fs::remove_dir_all(&dir);
}
