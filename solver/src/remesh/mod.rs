//! Adaptive remeshing (thesis chapter 8, issue 21): when to remesh, where to refine, and how the
//! mechanical fields go from the old mesh to the new one. The local mesher is
//! [`crate::mesh::ops::remesh_region`] (the operations on a mesh alone are `mesh/ops/`), checked
//! by [`check_remeshed`]; [`remesh_problem`] remeshes one
//! body of a running model between two steps (`apply/`, `splice.rs`), and the run goes on
//! with [`crate::dynamics::ExplicitSolver::resume`]; [`run_remeshing`] is such a run
//! (`driver.rs`, checkpoints `resume.rs`). What such a run shows besides its history (the records as a CSV written as it
//! goes, pictures of the mesh in a plane, the stress near a tip around each remeshing) is
//! watched through [`RemeshWatch`] (`watch.rs`, `section.rs`, `near_tip.rs`).
//!
//! # Configuration and formulation
//!
//! The new mesh is generated over the **current** (deformed) configuration at the time `t_r` of
//! the remeshing (thesis 8.2: "a new spatial discretization over the constructed deformed
//! boundary"), and becomes the reference configuration of the run that goes on: all searches,
//! volumes and centroids here use the old mesh's current coordinates `x = X + u` and the new
//! mesh's nodes as generated. This is the thesis' updated-Lagrangian step (9.2: "after
//! `TRANSFER_OPERATORS`, the meshes are set to their reference configurations").
//!
//! The solver itself is total-Lagrangian (`F = I + grad_X u` from the initial configuration,
//! FORMULATION 1), so the deformation reached so far has to travel with the elements:
//!
//! * every body carries its deformation gradient `F_0` (from the stress-free configuration to
//!   the current one) as an element field; the run goes on with `F = F_r F_0`, `F_r = I +
//!   grad_x u_r` the deformation since `t_r` measured on the new mesh, and the stress from `F`
//!   as before. A new element takes its **parent's** `F_0` (the old element that holds its
//!   centroid), not T1 of it: `F_0` is constant per element, and refinement splits each parent
//!   into children inside it, so the copy keeps a uniform `F_0` exactly and the stored energy of
//!   a refined element exactly; T1 (8.9) smoothed the concentrated strain at a nail's tip and
//!   lost 48 % of the model's stored energy in one remeshing. The price is the incompatibility
//!   of `F_0` across parents: forces at the new nodes where the parents' stresses differ.
//! * microplane bodies carry their history (turning points and damage, the thesis' "damage
//!   variables") with their `F_0` from the same parent (T2 with the parent for the closest
//!   Gauss point, which it is where a region is refined), so cracks do not diffuse and the
//!   history's turning points stay strains of its `F_0`. Their Cauchy stress, kept for the
//!   output, goes through T1 as the thesis does; the run recomputes the stress from `F_0` and
//!   the history at the next update.
//! * the element masses: copied for kept elements; a new element takes its parent's density
//!   times its volume, scaled so that the new elements' mass is that of the old elements they
//!   replace (the body's mass is kept to round-off).
//! * nodal fields: displacements go through T3 (8.10); velocities too (the thesis reconstructs
//!   them instead), followed by a uniform shift that restores the momentum
//!   ([`transfer_velocities`]).
//!
//! # Names of the operators
//!
//! The thesis names them inconsistently: 8.4 calls the Gauss-point operator `T1` and the nodal
//! one `T2`, then 8.4.1 calls the closest-point operator `T2` and the nodal one `T3`. We use the
//! later, sectioned names, which are the issue's: **T1** shape-function transfer of state
//! variables (8.9, [`shape_function_transfer`]), **T2** closest-Gauss-point transfer of damage
//! variables (Fig. 8.6, [`closest_gauss_point_sources`] with [`copy_rows`]), **T3** nodal
//! transfer (8.10, [`transfer_nodal_vectors`]).

mod apply;
mod contact_surface;
mod driver;
mod mesh_check;
mod near_tip;
mod record;
mod resume;
mod run;
mod section;
mod splice;
mod transfer;
mod watch;

pub use apply::{remesh_problem, Remeshed};
pub use contact_surface::SurfaceSeparation;
pub use driver::{
    run_remeshing, run_remeshing_checkpointed, run_remeshing_watched, RemeshHooks, RemeshingRun,
};
pub use mesh_check::{check_remeshed, RemeshCheck, REMESH_TOLERANCE};
pub use near_tip::{
    measure_near_tip, von_mises, NearTipRow, NearTipSpec, NearTipStress, NEAR_TIP_CSV_HEADER,
};
pub use record::{
    angular_momentum, kinetic_energy, lumped_masses, momentum, stored_energy, transfer_velocities,
    MeshState, RemeshRecord,
};
pub use resume::{Checkpointing, RemeshCheckpoint, RemeshCheckpoints, RemeshStart};
pub use run::{RemeshPolicy, RemeshSettings};
pub use section::{SectionBody, SectionFrame, SectionPictures, SectionSpec};
pub use transfer::{
    add_scaled_mass, closest_gauss_point_sources, copy_rows, element_integral, element_volumes,
    interpolate_nodal, mass_scale_factors, matrices_to_rows, nodes_to_elements, project_to_nodes,
    rows_to_matrices, shape_function_transfer, transfer_nodal_vectors,
};
pub use watch::{
    remeshing_csv_row, NearTipMarks, RemeshWatch, RemeshingCsv, WatchMarks, Watches,
    REMESHING_CSV_HEADER,
};
