//! The operations of the local remesher on a tetrahedral mesh (thesis chapter 8): the mesher
//! that replaces a region by a finer one (`mesher`: split, then repair by edge collapse
//! (`collapse`), face and edge flips (`flip`), smoothing (`smoothing`) and peeling of
//! boundary slivers (`peel`)), the shape measures they improve (`quality`), and point location
//! in a mesh (`locate`, over a box tree, `box_tree`); `fragments` finds the pieces a mesh
//! falls into, `subdivision` the regular split of one tetrahedron; `distortion` the measures of a
//! distorted element (thesis Box 8.1) that decide where to remesh.
//!
//! They need only the mesh, the geometry of one tetrahedron and the shared geometric queries:
//! when and where to remesh, and how a running problem goes onto the new mesh, is
//! `crate::remesh`, the driver above the integrator.

pub(crate) mod box_tree;
pub(crate) mod collapse;
pub(crate) mod distortion;
pub(crate) mod flip;
pub(crate) mod fragments;
pub(crate) mod locate;
pub(crate) mod mesher;
pub(crate) mod peel;
pub(crate) mod quality;
pub(crate) mod smoothing;
pub(crate) mod subdivision;

pub use distortion::{
    altitude_ratio, check_distortion, collapse_ratio, deformation_jacobians, distortion,
    refinement_region, region_parts, DistortionCheck, JacobianExtreme, RefinementCriteria,
    COLLAPSE_RATIO_LIMIT, REFINEMENT_DELTA,
};
pub use locate::{centroids, CentroidSearch, Location, Locator, LOCATE_TOLERANCE};
pub use mesher::{
    grow_region, remesh_region, remesh_region_keeping_edges, MesherOptions, RemeshedRegion,
    COLLAPSE_PASSES, FLIP_PASSES, SMOOTHING_SWEEPS,
};
pub use peel::PeeledElement;
pub use quality::mean_ratio;
