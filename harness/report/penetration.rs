//! The report's part on runs that remesh (issue 21: "the velocity and depth curves, the
//! remeshing table and the mesh pictures ... and the stress near the tip after each
//! remeshing"; the nail of thesis 10.4).
//!
//! A scene run that remeshes writes its records into the case's output folder as it goes
//! (`impact_solver::remesh`, module `watch`): `<stem>_remeshing.csv`, and with the scene's
//! `section` and `near_tip` options `<stem>_mesh_<k>.json` and `<stem>_near_tip.csv`. At the
//! end of the case, completed or failed, [`record`] reads the tables into the case's result
//! (key `penetration`, so `results.json` has them) with the names of the pictures; the section
//! ([`section::PenetrationSection`]) reads the pictures back from the case's folder when it
//! draws them (as the beam pictures are), so the page stays self-contained.

mod mesh_view;
mod record;
pub mod section;

pub use mesh_view::{caption, mesh_svg, time_text, MESH_VIEW_WIDTH};
pub use record::{
    load_pictures, read_near_tip, read_record, read_remeshings, record, NearTipPoint,
    PenetrationRecord, RemeshRow, KEY,
};
