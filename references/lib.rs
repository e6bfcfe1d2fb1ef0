//! The references of the concrete-impact V&V, as one crate that the harness and the solver's
//! integration tests both depend on, so that a formula is written once (issue 19):
//!
//! - [`analytic`]: closed-form solutions, each with its formula and source;
//! - [`concrete`]: concrete design-code laws (fib Model Code 2010, Hordijk);
//! - [`elastic_refinement`], [`static_path`]: the case's own scene solved by the implicit static
//!   solver (a refined mesh, the same loading);
//! - [`hinge`]: the cohesive-crack hinge of a beam in three-point bending (Olesen 2001);
//! - [`queries`]: the seeded random CCD queries of the cross-check and of the solver's CCD
//!   sweep, one generator set;
//! - `strategies` (feature `strategies`): proptest strategies built on those generators.
//!
//! The reference data (`published/`, `crosscheck/`) sit beside these sources and are read by
//! path by the harness.
//!
//! Where to start: [`analytic`], whose functions a case names as `reference: { analytic: ... }`
//! (`docs/catalogue.md`, "The case format"); `README.md` beside this file describes the data.

pub mod analytic;
pub mod concrete;
pub mod elastic_refinement;
pub mod error;
pub mod hinge;
pub mod queries;
pub mod static_path;
#[cfg(feature = "strategies")]
pub mod strategies;
