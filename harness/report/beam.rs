//! Pictures of the beam cases (CATALOGUE "Validation: the thesis' plain concrete beam", issue 7):
//! the crack pattern seen from the side (x-y) at a few instants and at the end, the energy
//! transformation (thesis Figs 10.11-10.14), contact force and support reactions against time,
//! the force components of (6.48) on the beam (Fig. 10.16), and the load-displacement curve of
//! a static case; plus the "Beam: failure modes" comparison of the cases side by side.
//!
//! The pictures need the displacement snapshots, which only exist while the case runs: the
//! runner calls [`record`] once per case, which returns the extra plots (they go into
//! `results.json` with the case's own) and writes a [`BeamRecord`] (the side-view rasters, the
//! outline, supports and impactor footprint) as `beam-<variant>.json` into the case's output
//! folder `<run>/cases/<id>/`, with one SVG file per picture next to it. `impact-vv report`
//! reads the records back from there ([`load`]), so the page stays self-contained.

mod column_demand;
mod failure_modes;
mod plots;
mod record;
pub mod section;
mod side_view;
mod tip_agreement;

pub use crate::beam::FAILURE_MODE_METRIC;
pub use failure_modes::{
    failure_rows, markdown, metric_text, monotonic_statement, verdicts, FailureRow,
};
pub use plots::central_differences;
pub use record::{load, load_one, rasterise, record, record_path, BeamRecord, SideView};
pub use side_view::{frame_title, side_view_svg, FILMSTRIP_WIDTH, SIDE_VIEW_WIDTH};

/// The body the pictures are of.
pub const BEAM_BODY: &str = "beam";
/// Instants of the filmstrip (s), before the final state.
pub const FILMSTRIP: [f64; 4] = [2.0e-4, 5.0e-4, 1.0e-3, 2.0e-3];
