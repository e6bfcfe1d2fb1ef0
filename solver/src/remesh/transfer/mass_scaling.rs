//! Selective mass scaling of a remeshed body: mass added to the nodes of the elements whose
//! stable step falls below a floor, so that the explicit step is not set by a few elements the
//! remesher leaves thin (issue 21).
//!
//! The stable step of element `e` is `dt_e = l_e sqrt(r_e) / c` (FORMULATION 2: `l_e` its
//! smallest altitude, `c` the dilatational wave speed `sqrt(M / rho_0)`, `r_e <= 1` the
//! element's density over `rho_0` where it is lighter, `crate::model::light_density_ratio`).
//! Raising the element's density by a factor `s_e` lowers its wave speed by `sqrt(s_e)`; with
//!
//! `s_e = max(1, (dt_min / dt_e)^2)`
//!
//! its step becomes `dt_min` exactly, and the element adds `m_e (s_e - 1)` to the nodal masses, a
//! quarter to each node (the lumping of FORMULATION 2). This is the selective form of the mass
//! scaling explicit codes offer (LS-DYNA's `*CONTROL_TIMESTEP` with a negative `DT2MS`: "mass is
//! added only to those elements whose time step would otherwise be less than" the floor).
//! The added mass is fictitious: it slows the scaled elements' waves and adds their inertia, so
//! a run reports it (the remeshing record's `added_mass`) and a case that uses it must show
//! what it changed against a run without it.
//!
//! The physical element masses (`CarriedState::element_mass`) stay as they are: each
//! remeshing computes the added mass afresh on its new mesh, so the added mass does not
//! accumulate from one remeshing to the next or spread with the transfer.

use nalgebra::Vector3;

use crate::mesh::element_quality;

/// The density factor `s_e >= 1` of each element of `tets` over `nodes` that brings its stable
/// step `l_e sqrt(r_e) / wave_speed` up to `critical_step` (s), with `r_e` the element's entry
/// of `light_density_ratio`; 1 for an element already at or above it, and for every element
/// when `critical_step` is 0.
pub fn mass_scale_factors(
    nodes: &[Vector3<f64>],
    tets: &[[u32; 4]],
    light_density_ratio: &[f64],
    wave_speed: f64,
    critical_step: f64,
) -> Vec<f64> {
    if !(critical_step > 0.0) {
        return vec![1.0; tets.len()];
    }
    tets.iter()
        .zip(light_density_ratio)
        .map(|(tet, r)| {
            let l = element_quality(&tet.map(|n| nodes[n as usize])).min_altitude;
            let dt = l * r.sqrt() / wave_speed;
            if dt < critical_step {
                (critical_step / dt).powi(2)
            } else {
                1.0
            }
        })
        .collect()
}

/// Adds to the lumped masses `nodal_mass` the mass `m_e (s_e - 1)` of each element of `tets`
/// with physical mass `element_mass[e]` and factor `scale[e]`, a quarter to each node; returns
/// the total added (kg). Elements with a factor of 1 add nothing, so the masses stay bitwise.
pub fn add_scaled_mass(
    nodal_mass: &mut [f64],
    tets: &[[u32; 4]],
    element_mass: &[f64],
    scale: &[f64],
) -> f64 {
    let mut added = 0.0;
    for ((tet, m), s) in tets.iter().zip(element_mass).zip(scale) {
        if *s > 1.0 {
            let dm = m * (s - 1.0);
            for &n in tet {
                nodal_mass[n as usize] += 0.25 * dm;
            }
            added += dm;
        }
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A regular tetrahedron of edge 1 and, sharing its base, a flat one of height `h`.
    fn two(h: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 4]>) {
        let s3 = 3f64.sqrt();
        let nodes = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.5, 0.5 * s3, 0.0),
            Vector3::new(0.5, 0.5 / s3, (2.0f64 / 3.0).sqrt()),
            Vector3::new(0.5, 0.5 / s3, -h),
        ];
        (nodes, vec![[0, 1, 2, 3], [0, 2, 1, 4]])
    }

    #[test]
    fn a_thin_element_gets_the_factor_that_brings_its_step_to_the_floor() {
        let (nodes, tets) = two(0.01);
        let c = 4000.0;
        let l_regular = (2.0f64 / 3.0).sqrt();
        // A floor between the two elements' steps: only the flat one is scaled.
        let floor = 0.5 * l_regular / c;
        let s = mass_scale_factors(&nodes, &tets, &[1.0, 1.0], c, floor);
        assert_eq!(s[0], 1.0);
        let l_flat = element_quality(&tets[1].map(|n| nodes[n as usize])).min_altitude;
        assert!(l_flat < 0.011 && l_flat > 0.009, "{l_flat}");
        // Its step with the density raised by s: l sqrt(s) / c = the floor.
        let scaled_step = l_flat * s[1].sqrt() / c;
        assert!(
            (scaled_step / floor - 1.0).abs() < 1e-14,
            "{scaled_step} {floor}"
        );
        // No floor: nothing is scaled.
        assert_eq!(
            mass_scale_factors(&nodes, &tets, &[1.0, 1.0], c, 0.0),
            vec![1.0, 1.0]
        );
    }

    #[test]
    fn the_added_mass_goes_a_quarter_to_each_node_of_the_scaled_element_only() {
        let (_, tets) = two(0.01);
        let physical = [2.0, 0.08];
        let mut mass = vec![0.0; 5];
        for (tet, m) in tets.iter().zip(physical) {
            for &n in tet {
                mass[n as usize] += 0.25 * m;
            }
        }
        let before = mass.clone();
        let added = add_scaled_mass(&mut mass, &tets, &physical, &[1.0, 26.0]);
        assert_eq!(added, 0.08 * 25.0);
        // Node 3 belongs to the unscaled element only: bitwise unchanged.
        assert_eq!(mass[3], before[3]);
        for n in [0, 1, 2, 4] {
            assert!((mass[n] - before[n] - 0.5).abs() < 1e-15, "node {n}");
        }
        let total: f64 = mass.iter().sum::<f64>() - before.iter().sum::<f64>();
        assert!((total - added).abs() < 1e-14);
    }
}
