//! Adaptive remeshing (thesis chapter 8, issue 21): when to remesh, where to refine, and how the
//! mechanical fields go from the old mesh to the new one. The local mesher is [`remesh_region`]
//! (method in `mesher.rs`), checked by [`check_remeshed`]; [`remesh_problem`] remeshes a
//! running one-body model between two steps (`apply.rs`), and the run goes on with
//! [`crate::dynamics::ExplicitSolver::resume`].
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
//! * elastic and Saint-Venant-Kirchhoff bodies carry their deformation gradient `F_0` (from the
//!   stress-free configuration to the current one) as an element field, through T1; the run
//!   goes on with `F = F_r F_0`, `F_r = I + grad_x u_r` the deformation since `t_r` measured on the
//!   new mesh, and the stress from `F` as before. T1 is exact for a uniform `F_0`, so a body in
//!   uniform stress keeps it exactly; a varying `F_0` is smoothed (8.4.1.1), component by
//!   component, which also averages differing rotations (and so shortens them a little where
//!   neighbours rotate differently): the run that goes on checks `det F_0 > 0` and may prefer
//!   to carry the polar factors `R`, `U` separately once it exists.
//! * microplane bodies carry their history (turning points and damage, the thesis' "damage
//!   variables") through T2, closest Gauss point, so that cracks do not diffuse; their `F_0`
//!   goes with the history from the **same** old element (T2, not T1), because the history's
//!   turning points are strains of that `F_0` and the pair must stay consistent (a smoothed
//!   `F_0` with a copied history would load or unload planes spuriously). Their Cauchy stress,
//!   a state variable, goes through T1 as the thesis does, for the output and for the check of
//!   (8.8); the run recomputes the stress from `F_0` and the history at the next update.
//! * the densities: the current density `rho_0 / det F_0` goes through T1 (the thesis' "mesh
//!   density", 8.4.1.1), and the new lumped masses are that density times the new volumes.
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
mod distortion;
mod locate;
mod mesh_check;
mod mesher;
mod record;
mod run;
mod splice;
mod transfer;

pub use apply::{remesh_problem, Remeshed};
pub use contact_surface::SurfaceSeparation;
pub use distortion::{
    check_distortion, collapse_ratio, deformation_jacobians, refinement_region, region_parts,
    DistortionCheck, JacobianExtreme, RefinementCriteria, COLLAPSE_RATIO_LIMIT, REFINEMENT_DELTA,
};
pub use locate::{centroids, CentroidSearch, Location, Locator, LOCATE_TOLERANCE};
pub use mesh_check::{check_remeshed, RemeshCheck, REMESH_TOLERANCE};
pub use mesher::{
    grow_region, mean_ratio, remesh_region, MesherOptions, RemeshedRegion, SMOOTHING_SWEEPS,
};
pub use record::{
    angular_momentum, kinetic_energy, lumped_masses, momentum, stored_energy, transfer_velocities,
    MeshState, RemeshRecord,
};
pub use run::{run_remeshing, RemeshPolicy, RemeshSettings, RemeshingRun};
pub use transfer::{
    closest_gauss_point_sources, copy_rows, element_integral, element_volumes, interpolate_nodal,
    matrices_to_rows, nodes_to_elements, project_to_nodes, rows_to_matrices,
    shape_function_transfer, transfer_nodal_vectors,
};
