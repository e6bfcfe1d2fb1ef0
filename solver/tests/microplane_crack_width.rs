//! The crack band across the crack (`material/microplane/crack_width.rs`): an element pulled
//! across its thin direction dissipates per unit crack area what an element of volume size equal
//! to that width does, whatever its own volume, where with the volume size's band a flat element
//! dissipates only its width over its volume size of that; the band follows the crack's direction;
//! elements too long for any band, and the tensile boundary, are refused.
#![allow(clippy::unwrap_used)]

mod common;

use common::shipped_concrete;
use impact_solver::material::microplane::{CrackBandWidth, MicroplaneParameters};
use impact_solver::material::{Deformation, ElementState, Material, MicroplaneMaterial};
use nalgebra::Matrix3;

/// The batch's concrete at static rates, with the band `band`.
fn concrete(band: CrackBandWidth) -> MicroplaneParameters {
    MicroplaneParameters {
        rate_effect: None,
        crack_band: band,
        ..shipped_concrete("gregoire-2013-concrete")
    }
}

/// The tetrahedron (0,0,0), (L,0,0), (L,L,0), (L,L,w): `w` thick along z, `L` wide across.
fn cell(across: f64, thick: f64) -> [[f64; 3]; 4] {
    [
        [0.0, 0.0, 0.0],
        [across, 0.0, 0.0],
        [across, across, 0.0],
        [across, across, thick],
    ]
}

/// One element of the given corners and parameters, pulled along the axis `axis` in uniaxial
/// strain to the strain `end` in `steps` steps: the work `int P_ii dF_ii` per unit reference
/// volume (J/m^3), the last stress over the peak, and the element's volume size.
fn pulled(
    parameters: MicroplaneParameters,
    corners: [[f64; 3]; 4],
    axis: usize,
    (end, steps): (f64, usize),
) -> (f64, f64, f64) {
    let d = |a: usize, i: usize| corners[a][i] - corners[0][i];
    let edges = Matrix3::from_fn(|i, a| d(a + 1, i));
    let volume = edges.determinant() / 6.0;
    let centroid = std::array::from_fn(|i| corners.iter().map(|c| c[i]).sum::<f64>() / 4.0);
    let material = MicroplaneMaterial::new("cell", parameters, &[volume], &[centroid], 0)
        .unwrap()
        .with_shapes("cell", std::iter::once(corners), 0)
        .unwrap();
    let mut history = vec![0.0f32; material.history_len()];
    material.initial_history(&mut history);
    let (mut work, mut last_stress, mut peak) = (0.0, 0.0, 0.0f64);
    for i in 1..=steps {
        let e = end * i as f64 / steps as f64;
        let mut h = Matrix3::zeros();
        h[(axis, axis)] = e;
        let p = material
            .update(
                0,
                &Deformation::at_rest(h),
                ElementState {
                    history: &mut history,
                    cauchy: None,
                },
            )
            .unwrap();
        let stress = p[(axis, axis)];
        work += 0.5 * (stress + last_stress) * end / steps as f64;
        last_stress = stress;
        peak = peak.max(stress);
    }
    (work, last_stress / peak, (6.0 * volume).cbrt())
}

/// The fracture energy the batch's concrete was calibrated to (N/m = J/m^2): the MC2010
/// estimate in `cases/materials/gregoire-2013-targets.yaml`.
const GF: f64 = 143.2;

/// The strain path: past the end of the tension law's tail at w = 2 mm (about 0.2 mm of
/// opening, 5 GF / ft, over 2 mm), in steps of 25 micro-strain.
const PATH: (f64, usize) = (0.15, 6000);

/// Flat cells 2 mm thick and 8 or 16 mm across (volume sizes 5.0 and 8.0 mm), pulled across
/// their thickness (z), dissipate per unit crack area what a cube-cut cell of edge 2 mm (volume
/// size 2 mm) does: the crack's normal is z, their width along it 2 mm. That is the fracture
/// energy the laws were calibrated to (in uniaxial stress, within 0.3 %; this path holds the
/// lateral strains, whose stresses change the planes' share a little: 5 %). With the volume
/// size's band the same cells spread the energy over their volume size instead, and dissipate
/// `w / h` of it: 0.40 and 0.25 of G_F.
#[test]
fn a_flat_element_across_its_thickness_dissipates_as_a_cube_of_that_width() {
    let w = 0.002;
    let (cube, cube_left, cube_size) =
        pulled(concrete(CrackBandWidth::Volume), cell(w, w), 2, PATH);
    assert!((cube_size - w).abs() < 1e-12, "cube-cut cell: {cube_size}");
    assert!(
        cube_left.abs() < 0.01,
        "the cube's law is not spent: {cube_left}"
    );
    println!(
        "cube-cut cell of edge {} mm: {:.4} N/mm per unit crack area",
        w * 1e3,
        w * cube / 1e3
    );
    assert!((w * cube / GF - 1.0).abs() < 0.05, "{} J/m^2", w * cube);
    for across in [0.008, 0.016] {
        let corners = cell(across, w);
        let (flat, left, size) = pulled(concrete(CrackBandWidth::AcrossCrack), corners, 2, PATH);
        let (volume_band, _, _) = pulled(concrete(CrackBandWidth::Volume), corners, 2, PATH);
        println!(
            "flat cell {} x {} mm (volume size {:.2} mm): across the crack {:.4} N/mm, with the \
             volume size {:.4} N/mm",
            across * 1e3,
            w * 1e3,
            size * 1e3,
            w * flat / 1e3,
            w * volume_band / 1e3
        );
        assert!(
            left.abs() < 0.01,
            "the flat cell's law is not spent: {left}"
        );
        assert!(
            (flat / cube - 1.0).abs() < 1e-6,
            "across the crack: {flat} J/m^3 against the cube's {cube}"
        );
        assert!(
            (volume_band / cube / (w / size) - 1.0).abs() < 0.05,
            "with the volume size: {volume_band} J/m^3 against the cube's {cube}, w / h = {}",
            w / size
        );
    }
}

/// The band follows the crack: the 8 mm x 2 mm cell pulled along x, where it is 8 mm wide,
/// dissipates per unit crack area what a cube-cut cell of edge 8 mm does, a quarter of what it
/// dissipates per unit volume pulled across its thickness.
#[test]
fn the_band_is_the_width_along_the_largest_principal_stress() {
    let (w, across) = (0.002, 0.008);
    let path = (0.06, 6000);
    let (along_x, left, _) = pulled(
        concrete(CrackBandWidth::AcrossCrack),
        cell(across, w),
        0,
        path,
    );
    let (cube, _, cube_size) = pulled(
        concrete(CrackBandWidth::Volume),
        cell(across, across),
        0,
        path,
    );
    println!(
        "8 x 2 mm cell along x: {:.4} N/mm; cube-cut cell of edge 8 mm: {:.4} N/mm",
        across * along_x / 1e3,
        cube_size * cube / 1e3
    );
    assert!(left.abs() < 0.01, "the law is not spent: {left}");
    assert!(
        (along_x / cube - 1.0).abs() < 1e-6,
        "along x: {along_x} J/m^3 against the 8 mm cube's {cube}"
    );
}

/// An element whose longest edge is too large for the laws is refused at setup with the
/// across-crack message, though its volume size is admitted: its crack may run along any
/// direction, and along its longest edge no band factor dissipates G_F without a snap-back.
#[test]
fn an_element_too_wide_for_its_band_is_refused() {
    use impact_solver::material::microplane::MicroplaneConcrete;
    let parameters = concrete(CrackBandWidth::AcrossCrack);
    let largest = MicroplaneConcrete::new(parameters)
        .unwrap()
        .largest_element();
    println!("largest admissible band {:.1} mm", largest * 1e3);
    // A needle 1.2 times the largest band long and thin enough that its volume size is small.
    let (long, thin) = (1.2 * largest, 0.002);
    let corners = [
        [0.0, 0.0, 0.0],
        [thin, 0.0, 0.0],
        [thin, thin, 0.0],
        [thin, thin, long],
    ];
    let volume = thin * thin * long / 6.0;
    assert!((6.0 * volume).cbrt() < largest);
    let centroid = [0.0; 3];
    let material =
        MicroplaneMaterial::new("needle", parameters, &[volume], &[centroid], 0).unwrap();
    let message = material
        .with_shapes("needle", std::iter::once(corners), 0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("longest edge"), "{message}");
    // With the volume size's band the same element is admitted.
    let volume_band = concrete(CrackBandWidth::Volume);
    assert!(
        MicroplaneMaterial::new("needle", volume_band, &[volume], &[centroid], 0)
            .unwrap()
            .with_shapes("needle", std::iter::once(corners), 0)
            .is_ok()
    );
}

/// The band across the crack is refused with the tensile boundary, whose planes crack through
/// their own crack strains (the onset is read from the tension laws' history, which the boundary
/// replaces), with a message that says so.
#[test]
fn the_band_across_the_crack_is_refused_with_the_tensile_boundary() {
    use impact_solver::material::microplane::MicroplaneConcrete;
    let parameters = MicroplaneParameters {
        crack_band: CrackBandWidth::AcrossCrack,
        ..shipped_concrete("thesis-concrete-tension-boundary")
    };
    let message = MicroplaneConcrete::new(parameters).unwrap_err().to_string();
    assert!(message.contains("tension_boundary"), "{message}");
    let volume = MicroplaneParameters {
        crack_band: CrackBandWidth::Volume,
        ..parameters
    };
    assert!(MicroplaneConcrete::new(volume).is_ok());
}
