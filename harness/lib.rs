//! The V&V harness of the concrete-impact solver: reads the YAML catalogue, runs each case with
//! the solver, measures, judges against references, and reports.
//!
//! Pipeline: `catalogue -> runner (execute, measure) -> judge -> results -> report`.
//!
//! Where to start: `main.rs` is the `impact-vv` command line; a case file is read by
//! [`case_file`] into the schema of [`catalogue`] and run by its kind ([`case_kind::CaseKind`],
//! listed in [`registry`]; the default kind is [`scene_case`]); [`runner`] runs the jobs and
//! [`report`] writes the page. The case format is `docs/catalogue.md`, the layout
//! `docs/architecture.md`.

pub mod band;
pub mod beam;
pub mod calibrate;
pub mod case_file;
pub mod case_kind;
pub mod case_log;
pub mod catalogue;
pub mod commands;
pub mod contact_compare;
pub mod contact_problems;
pub mod crosscheck;
pub mod curve;
pub mod determinism;
pub mod judge;
pub mod material_point;
pub mod memory;
pub mod metadata;
pub mod mpirun;
pub mod progress;
pub mod rank_case;
pub mod reference;
pub mod registry;
pub mod replay;
pub mod report;
pub mod results;
pub mod run_log;
pub mod runner;
pub mod scene_case;
pub mod scene_restart;
pub mod scene_run;
