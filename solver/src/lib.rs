//! `impact-solver`: explicit finite-strain dynamics of linear tetrahedra for concrete under
//! impact, after V. Travaš (2009), *Three-dimensional finite element formulation for concrete
//! failure at high-energy impact loadings* (the "thesis"), with the decisions recorded in the
//! project's `docs/formulation.md`.
//!
//! Where to start: [`scene::Scene`] describes a simulation (the YAML format of
//! `docs/scenes.md`) and [`analysis::execute`] runs it; [`dynamics`] holds the explicit
//! integrator, [`material`] the constitutive models (the concrete model in
//! [`material::microplane`], `docs/MICROPLANE.md`), [`contact`] detection and the contact
//! solvers (`docs/contact.md`). The modules, their layers and the conventions are in
//! `docs/architecture.md`.
//!
//! Data flows one way through a time step:
//! `kinematics -> material (stress) -> internal forces -> integrator -> state at n+1 -> energies/output`.
//!
//! Units are SI throughout (m, kg, s, Pa, J) and every quantity is `f64`.

pub mod analysis;
pub mod contact;
pub mod distributed;
pub mod dynamics;
pub mod error;
pub mod geometry;
pub mod kinematics;
pub mod material;
pub mod mesh;
pub mod model;
pub mod nodal;
pub mod output;
pub mod problem;
pub mod remesh;
pub mod restart;
pub mod rng;
pub mod scene;
pub mod statics;

pub use error::SolverError;
pub use nalgebra::{Matrix3, Vector3};
pub use problem::Problem;
