//! The V&V harness of the concrete-impact solver: reads the YAML catalogue, runs each case with
//! the solver, measures, judges against references, and reports.
//!
//! Pipeline: `catalogue -> runner (execute, measure) -> judge -> results -> report`.

pub mod band;
pub mod beam;
pub mod calibrate;
pub mod case_file;
pub mod case_kind;
pub mod case_log;
pub mod catalogue;
pub mod contact_compare;
pub mod contact_problems;
pub mod crosscheck;
pub mod determinism;
pub mod judge;
pub mod material_point;
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
pub mod scene_run;
