//! The microplane model at the finite strains of a penetration (issue 21): a point crushed to a
//! tenth of its volume while stretched across must resist in volumetric compression. With the
//! trace of the Green-Lagrange strain as `e_V` (MICROPLANE.md) it reads the path as volumetric
//! tension and offers no resistance, which let elements under the nail collapse to zero volume;
//! with the volume-ratio measure (`material/microplane/volumetric.rs`) the compaction law holds.
#![allow(clippy::unwrap_used)]

use std::path::Path;

use impact_solver::material::microplane::driver::MaterialPoint;
use impact_solver::material::microplane::{MicroplaneConcrete, VolumetricStrain};
use impact_solver::material::read_microplane_file;

/// The mean stress at the end of the path `F = diag(1 + t (l - 1))`, `t` from 0 to 1, with the
/// volumetric measure `measure`, and the compressive strength of the concrete.
fn mean_stress_after(l: [f64; 3], measure: VolumetricStrain) -> (f64, f64) {
    let mut p = read_microplane_file(Path::new("../cases/materials/thesis-concrete.yaml")).unwrap();
    p.volumetric_strain = measure;
    p.rate_effect = None;
    let model = MicroplaneConcrete::new(p).unwrap();
    let mut point = MaterialPoint::new(&model, 0.05).unwrap();
    let steps = 400;
    let mut last = None;
    for i in 1..=steps {
        let t = i as f64 / steps as f64;
        let s = l.map(|l| 1.0 + t * (l - 1.0));
        let strain = [
            0.5 * (s[0] * s[0] - 1.0),
            0.5 * (s[1] * s[1] - 1.0),
            0.5 * (s[2] * s[2] - 1.0),
            0.0,
            0.0,
            0.0,
        ];
        last = Some(point.strain_step(strain, 1e-3));
    }
    let stress = last.unwrap().stress;
    // fc: the peak of uniaxial compression the calibration targets (45 MPa).
    ((stress[0] + stress[1] + stress[2]) / 3.0, 45e6)
}

#[test]
fn a_point_crushed_while_stretched_resists_only_with_the_volume_ratio_measure() {
    // J = 0.05 * 1.5 * 1.5 = 0.1125; tr E / 3 = +0.25, (J^(2/3) - 1) / 2 = -0.38.
    let l = [0.05, 1.5, 1.5];
    let (trace_mean, fc) = mean_stress_after(l, VolumetricStrain::GreenLagrangeTrace);
    let (ratio_mean, _) = mean_stress_after(l, VolumetricStrain::VolumeRatio);
    println!("mean stress: trace {trace_mean:.3e} Pa, volume ratio {ratio_mean:.3e} Pa");
    assert!(
        trace_mean > -fc,
        "the trace measure reads the crushing as tension: mean stress {trace_mean:.3e} Pa"
    );
    assert!(
        ratio_mean < -10.0 * fc,
        "the compaction law must resist a volume of 0.11: mean stress {ratio_mean:.3e} Pa"
    );
}

#[test]
fn small_strain_paths_do_not_see_the_measure() {
    // Uniaxial compression to 1e-3 (before the peak) with lateral expansion: the two measures of
    // e_V differ by O(eps^2) = 1e-6, so the mean stress by about E_V0 eps^2 (E_V0 = E / (1 - 2
    // nu) = 47 GPa): 2 E_V0 eps^2 = 9.4e4 Pa bounds it, 1 % of the mean stress.
    let eps: f64 = 1e-3;
    let l = [1.0 - eps, 1.0 + 2e-4, 1.0 + 2e-4];
    let (a, _) = mean_stress_after(l, VolumetricStrain::GreenLagrangeTrace);
    let (b, _) = mean_stress_after(l, VolumetricStrain::VolumeRatio);
    let e_v0 = 30e9 / (1.0 - 2.0 * 0.18);
    assert!(
        (a - b).abs() <= 2.0 * e_v0 * eps * eps,
        "{a:e} against {b:e}"
    );
}
