//! The remeshings a run made so far, in a checkpoint: each [`RemeshRecord`] with every number
//! as its raw bits, so that a resumed run reports, sums and writes them (`<stem>_remeshing.csv`)
//! as the run never stopped would. The structs are taken apart field by field without `..`, so
//! a field added to one of them fails to compile here until the format carries it.

use nalgebra::Vector3;

use super::bytes::{Read, Reader, Writer};
use crate::remesh::{MeshState, RemeshRecord, SurfaceSeparation};

fn vector(w: &mut Writer, v: &Vector3<f64>) {
    v.iter().for_each(|&c| w.f64(c));
}

fn read_vector(r: &mut Reader, what: &str) -> Read<Vector3<f64>> {
    Ok(Vector3::new(r.f64(what)?, r.f64(what)?, r.f64(what)?))
}

fn mesh_state(w: &mut Writer, m: &MeshState) {
    let MeshState {
        elements,
        worst_collapse_ratio,
        worst_distortion,
        worst_distortion_element,
        mass,
        kinetic,
        stored,
        momentum,
        angular_momentum,
    } = m;
    w.usize(*elements);
    w.f64(*worst_collapse_ratio);
    w.f64(*worst_distortion);
    w.usize(*worst_distortion_element);
    w.f64(*mass);
    w.f64(*kinetic);
    w.f64(*stored);
    vector(w, momentum);
    vector(w, angular_momentum);
}

fn read_mesh_state(r: &mut Reader) -> Read<MeshState> {
    let what = "a remeshing's mesh state";
    Ok(MeshState {
        elements: r.usize(what)?,
        worst_collapse_ratio: r.f64(what)?,
        worst_distortion: r.f64(what)?,
        worst_distortion_element: r.usize(what)?,
        mass: r.f64(what)?,
        kinetic: r.f64(what)?,
        stored: r.f64(what)?,
        momentum: read_vector(r, what)?,
        angular_momentum: read_vector(r, what)?,
    })
}

/// Writes `records`, a count first.
pub fn write_remeshings(w: &mut Writer, records: &[RemeshRecord]) {
    w.usize(records.len());
    for record in records {
        let RemeshRecord {
            time,
            region_elements,
            before,
            after,
            velocity_shift,
            separation,
            peeled,
            peeled_volume,
            surface_collapses,
            surface_volume_change,
            added_mass,
            kinetic_restored,
            fluctuation_scale,
        } = record;
        let SurfaceSeparation {
            moved,
            largest_depth,
            left_inside,
        } = separation;
        w.f64(*time);
        w.usize(*region_elements);
        mesh_state(w, before);
        mesh_state(w, after);
        vector(w, velocity_shift);
        w.usize(*moved);
        w.f64(*largest_depth);
        w.usize(*left_inside);
        w.usize(*peeled);
        w.f64(*peeled_volume);
        w.usize(*surface_collapses);
        w.f64(*surface_volume_change);
        w.f64(*added_mass);
        w.f64(*kinetic_restored);
        w.f64(*fluctuation_scale);
    }
}

/// Reads what [`write_remeshings`] wrote.
pub fn read_remeshings(r: &mut Reader) -> Read<Vec<RemeshRecord>> {
    let what = "a remeshing's record";
    let count = r.usize("remeshings")?;
    (0..count)
        .map(|_| {
            Ok(RemeshRecord {
                time: r.f64(what)?,
                region_elements: r.usize(what)?,
                before: read_mesh_state(r)?,
                after: read_mesh_state(r)?,
                velocity_shift: read_vector(r, what)?,
                separation: SurfaceSeparation {
                    moved: r.usize(what)?,
                    largest_depth: r.f64(what)?,
                    left_inside: r.usize(what)?,
                },
                peeled: r.usize(what)?,
                peeled_volume: r.f64(what)?,
                surface_collapses: r.usize(what)?,
                surface_volume_change: r.f64(what)?,
                added_mass: r.f64(what)?,
                kinetic_restored: r.f64(what)?,
                fluctuation_scale: r.f64(what)?,
            })
        })
        .collect()
}
