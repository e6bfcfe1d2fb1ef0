//! Geometry that contact detection and the mesh operations share: axis-aligned boxes and the
//! uniform grid over them ([`broad_phase`]), and points against tetrahedra and triangles
//! ([`proximity`]). It depends on nothing of the solver, so both the mesh layer and the contact
//! layer build on it.

pub mod broad_phase;
pub mod proximity;
