//! The transfer operators of a remeshing: how the fields of the old mesh become those of the
//! new one (thesis 8.4), and the two corrections that follow them. Which field goes through
//! which operator, and in which configuration, is in the module `remesh`.
//!
//! * **T1**, the shape-function transfer of state variables (thesis 8.9, Fig. 8.5: Gauss points
//!   to old nodes by volume weights, old nodes to new nodes by the old shape functions, new
//!   nodes to new Gauss points): [`shape_function_transfer`], with its steps
//!   [`project_to_nodes`], [`interpolate_nodal`] and [`nodes_to_elements`]; `operators.rs`.
//! * **T2**, the closest-Gauss-point transfer of damage variables (thesis 8.4.1, Fig. 8.6): each
//!   new element copies the values of the old element whose Gauss point is closest to its own,
//!   [`closest_gauss_point_sources`] with [`copy_rows`]; `operators.rs`.
//! * **T3**, the nodal transfer (thesis 8.10, Box 8.3): a nodal field at a new node from the old
//!   element that holds it, [`transfer_nodal_vectors`]; `operators.rs`. The momentum
//!   correction of the velocities that follows it is `crate::remesh::transfer_velocities`.
//! * The **kinetic energy correction**: the velocity fluctuations of the region's nodes about
//!   their mean are scaled so that the body keeps the kinetic energy T3 smooths away, its
//!   momentum untouched (the conservative remap of ALE codes; DeBar's fix puts that energy into
//!   internal energy, which concrete without a thermal state has no place for):
//!   [`restore_kinetic_energy`]; `kinetic_energy.rs`.
//! * **Selective mass scaling**: mass added to the elements whose stable step the remesher left
//!   below a floor, `s_e = max(1, (dt_min / dt_e)^2)` (FORMULATION 2 for the stable step;
//!   LS-DYNA's `*CONTROL_TIMESTEP` with a negative `DT2MS` for the practice):
//!   [`mass_scale_factors`], [`add_scaled_mass`]; `mass_scaling.rs`.

mod kinetic_energy;
mod mass_scaling;
mod operators;

pub use kinetic_energy::{restore_kinetic_energy, KineticRestore};
pub use mass_scaling::{add_scaled_mass, mass_scale_factors};
pub use operators::{
    closest_gauss_point_sources, copy_rows, element_integral, element_volumes, interpolate_nodal,
    matrices_to_rows, nodes_to_elements, project_to_nodes, rows_to_matrices,
    shape_function_transfer, transfer_nodal_vectors,
};
