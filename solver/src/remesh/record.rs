//! Mass, momentum and energy on both meshes, the velocity transfer that keeps momentum, and the
//! record of one remeshing (issue 21: "time, elements before and after, quality before and
//! after, the jump in kinetic, stored and total energy and in momentum").

use nalgebra::{Matrix3, Vector3};

use super::transfer::transfer_nodal_vectors;
use crate::error::{Result, SolverError};
use crate::material::Material;
use crate::mesh::ops::locate::Location;

/// Lumped nodal masses (kg) of the mesh `tets` with element volumes `volumes` (m^3) and element
/// densities `density` (kg/m^3) in the same configuration: a quarter of each element's mass to
/// each of its nodes (FORMULATION 2). On the new mesh, the volumes are current ones and the
/// densities the current density `rho_0 / det F` carried by T1 (the thesis transfers "the mesh
/// density" with T1, 8.4.1.1).
pub fn lumped_masses(
    tets: &[[u32; 4]],
    volumes: &[f64],
    density: &[f64],
    node_count: usize,
) -> Vec<f64> {
    let mut mass = vec![0.0; node_count];
    for (e, tet) in tets.iter().enumerate() {
        let m = density[e] * volumes[e] / 4.0;
        for &n in tet {
            mass[n as usize] += m;
        }
    }
    mass
}

/// Kinetic energy `K = 1/2 sum_n m_n |v_n|^2` (J) of lumped masses `mass` (kg) moving at `v`
/// (m/s).
pub fn kinetic_energy(mass: &[f64], v: &[Vector3<f64>]) -> f64 {
    0.5 * mass
        .iter()
        .zip(v)
        .map(|(m, v)| m * v.norm_squared())
        .sum::<f64>()
}

/// Linear momentum `p = sum_n m_n v_n` (kg m/s).
pub fn momentum(mass: &[f64], v: &[Vector3<f64>]) -> Vector3<f64> {
    mass.iter().zip(v).map(|(m, v)| *m * v).sum()
}

/// Angular momentum `L = sum_n x_n x m_n v_n` about the origin (kg m^2/s), at positions `x`.
pub fn angular_momentum(x: &[Vector3<f64>], mass: &[f64], v: &[Vector3<f64>]) -> Vector3<f64> {
    x.iter()
        .zip(mass)
        .zip(v)
        .map(|((x, m), v)| x.cross(&(*m * v)))
        .sum()
}

/// The velocities of the new mesh: T3 (8.10) of the old velocities, then one uniform shift
/// `dv = (p_old - sum_n m_n^new v_n^T3) / M_new` added to every new node, so that the new
/// momentum `sum m^new v^new` equals the old one to round-off.
///
/// The thesis does not transfer velocities: it transfers displacements and reconstructs the
/// velocities from them (8.4.2). We transfer them (they are the state of the explicit scheme)
/// and correct the momentum, because interpolation alone does not keep it: the new lumped
/// masses sit at other points. Among all corrections `dv_n` that restore the momentum, the
/// uniform one is the smallest in the kinetic-energy norm `sum m_n |dv_n|^2` (a Lagrange
/// multiplier gives `m_n dv_n = m_n lambda`); it changes the kinetic energy by
/// `p^T3 . dv + M/2 |dv|^2` and is exact for a rigid translation (then `dv = 0` to round-off up
/// to the change of total mass). Angular momentum is not corrected; [`angular_momentum`]
/// measures it. Returns the velocities and the shift `dv` (m/s), for the record.
pub fn transfer_velocities(
    old_v: &[Vector3<f64>],
    old_mass: &[f64],
    old_tets: &[[u32; 4]],
    locations: &[Location],
    new_mass: &[f64],
) -> Result<(Vec<Vector3<f64>>, Vector3<f64>)> {
    if old_v.len() != old_mass.len() || new_mass.len() != locations.len() {
        return Err(SolverError::Remesh {
            entity: "velocity transfer".to_string(),
            message: format!(
                "{} old velocities for {} old masses, {} new masses for {} located new nodes",
                old_v.len(),
                old_mass.len(),
                new_mass.len(),
                locations.len()
            ),
        });
    }
    let total: f64 = new_mass.iter().sum();
    if !(total > 0.0) {
        return Err(SolverError::Remesh {
            entity: "new mesh".to_string(),
            message: format!("total mass {total:e} kg is not positive"),
        });
    }
    let mut v = transfer_nodal_vectors(old_v, old_tets, locations);
    let shift = (momentum(old_mass, old_v) - momentum(new_mass, &v)) / total;
    v.iter_mut().for_each(|v| *v += shift);
    Ok((v, shift))
}

/// Elastic energy stored in a mesh (J): `sum_e (v_e / det F_e) W(F_e)`, with `v_e` the current
/// volume of element `e`, `F_e` its deformation gradient from the stress-free configuration (so
/// `v_e / det F_e` is its reference volume) and `W` the strain energy per unit reference volume
/// of `material` ([`Material::strain_energy_density`]). On the new mesh `F_e` is the carried
/// deformation gradient. `None` when the material has no potential (microplane concrete) or an
/// element has `det F <= 0`.
pub fn stored_energy(
    volumes: &[f64],
    deformation: &[Matrix3<f64>],
    material: &dyn Material,
) -> Option<f64> {
    volumes
        .iter()
        .zip(deformation)
        .map(|(v, f)| {
            let det = f.determinant();
            if !(det > 0.0) {
                return None;
            }
            let h = f - Matrix3::identity();
            Some(v / det * material.strain_energy_density(&h)?)
        })
        .sum()
}

/// The mechanical state of one mesh at the instant of a remeshing, as the record reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshState {
    /// Number of elements.
    pub elements: usize,
    /// The largest collapse ratio `chi = L_max / L_min` of its elements (8.1).
    pub worst_collapse_ratio: f64,
    /// The largest distortion the run watches ([`crate::mesh::ops::distortion`]: `chi`, or the inverse
    /// mean ratio where larger, which sees slivers), infinite for an element without volume.
    pub worst_distortion: f64,
    /// The element of [`Self::worst_distortion`] (the lowest index among equals).
    pub worst_distortion_element: usize,
    /// Total mass (kg).
    pub mass: f64,
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Elastic energy stored (J), where the materials define it ([`stored_energy`]); 0 for a
    /// body without potential, whose stored and dissipated energy the run's internal work holds.
    pub stored: f64,
    /// Linear momentum (kg m/s).
    pub momentum: Vector3<f64>,
    /// Angular momentum about the origin (kg m^2/s).
    pub angular_momentum: Vector3<f64>,
}

impl MeshState {
    /// The state of the mesh `tets` over the current coordinates `x`, with lumped masses `mass`,
    /// velocities `v` and stored energy `stored` (J, from [`stored_energy`] or 0).
    pub fn measure(
        x: &[Vector3<f64>],
        tets: &[[u32; 4]],
        mass: &[f64],
        v: &[Vector3<f64>],
        stored: f64,
    ) -> Self {
        let (worst_distortion_element, worst_distortion) = tets
            .iter()
            .map(|tet| crate::mesh::ops::distortion(&tet.map(|n| x[n as usize])))
            .enumerate()
            .fold((0, 0.0), |worst, (e, d)| {
                if d > worst.1 || (d.is_nan() && !worst.1.is_nan()) {
                    (e, d)
                } else {
                    worst
                }
            });
        Self {
            elements: tets.len(),
            worst_collapse_ratio: crate::mesh::ops::check_distortion(x, tets, f64::INFINITY)
                .worst_ratio,
            worst_distortion,
            worst_distortion_element,
            mass: mass.iter().sum(),
            kinetic: kinetic_energy(mass, v),
            stored,
            momentum: momentum(mass, v),
            angular_momentum: angular_momentum(x, mass, v),
        }
    }

    /// Kinetic plus stored energy (J).
    pub fn total_energy(&self) -> f64 {
        self.kinetic + self.stored
    }
}

/// The record of one remeshing: when, the two meshes' state, and the velocity correction made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemeshRecord {
    /// Time of the remeshing (s).
    pub time: f64,
    /// Elements of the old mesh that were remeshed (the refinement region).
    pub region_elements: usize,
    /// The old mesh at that time.
    pub before: MeshState,
    /// The new mesh after the transfer.
    pub after: MeshState,
    /// The uniform velocity shift that restored the momentum (m/s), [`transfer_velocities`].
    pub velocity_shift: Vector3<f64>,
    /// New surface nodes placed on a contact partner's surface, which they started inside.
    pub separation: super::SurfaceSeparation,
    /// Boundary slivers the remesher removed (`peel.rs`).
    pub peeled: usize,
    /// Their volume (m^3): material taken out of the body (its mass stays, on the region's
    /// other new elements).
    pub peeled_volume: f64,
    /// Edge collapses that merged a node of a curved surface into a neighbour.
    pub surface_collapses: usize,
    /// The body's volume change by those collapses and by nodes that slid on a curved surface
    /// (m^3, after less before).
    pub surface_volume_change: f64,
    /// The mass selective mass scaling put on the new mesh's nodes (kg; in `after.mass`, not
    /// in the body's physical mass), `super::mass_scale_factors`; 0 without it.
    pub added_mass: f64,
    /// The kinetic energy (J) the velocity transfer lost and the region's nodes were given
    /// back (negative: a surplus taken back), `super::kinetic_energy`; already in `after`.
    pub kinetic_restored: f64,
    /// The factor on the region's velocity fluctuations that gave it back (1: none).
    pub fluctuation_scale: f64,
}

impl RemeshRecord {
    /// The jump in kinetic energy, after minus before (J).
    pub fn kinetic_jump(&self) -> f64 {
        self.after.kinetic - self.before.kinetic
    }

    /// The jump in stored energy, after minus before (J).
    pub fn stored_jump(&self) -> f64 {
        self.after.stored - self.before.stored
    }

    /// The jump in total (kinetic plus stored) energy, after minus before (J).
    pub fn total_energy_jump(&self) -> f64 {
        self.after.total_energy() - self.before.total_energy()
    }

    /// The jump in linear momentum, after minus before (kg m/s).
    pub fn momentum_jump(&self) -> Vector3<f64> {
        self.after.momentum - self.before.momentum
    }

    /// One line for a run's log.
    pub fn summary(&self) -> String {
        format!(
            "remeshing at t = {:.6e} s: {} elements remeshed, {} -> {} elements, worst collapse ratio {:.3} -> {:.3}, \
             worst distortion {:.3} (element {}) -> {:.3} (element {}), mass {:.6e} -> {:.6e} kg, kinetic {:.6e} -> {:.6e} J, stored {:.6e} -> {:.6e} J, \
             total energy jump {:.3e} J, |momentum jump| {:.3e} kg m/s (velocity shift {:.3e} m/s), \
             {} new surface nodes moved out of a contact partner (by up to {:.3e} m; {} left \
             inside), {} boundary slivers peeled ({:.3e} m^3), {} surface collapses (volume change {:.3e} m^3), \
             added mass {:.3e} kg, kinetic energy restored {:.3e} J (fluctuations times {:.4})",
            self.time,
            self.region_elements,
            self.before.elements,
            self.after.elements,
            self.before.worst_collapse_ratio,
            self.after.worst_collapse_ratio,
            self.before.worst_distortion,
            self.before.worst_distortion_element,
            self.after.worst_distortion,
            self.after.worst_distortion_element,
            self.before.mass,
            self.after.mass,
            self.before.kinetic,
            self.after.kinetic,
            self.before.stored,
            self.after.stored,
            self.total_energy_jump(),
            self.momentum_jump().norm(),
            self.velocity_shift.norm(),
            self.separation.moved,
            self.separation.largest_depth,
            self.separation.left_inside,
            self.peeled,
            self.peeled_volume,
            self.surface_collapses,
            self.surface_volume_change,
            self.added_mass,
            self.kinetic_restored,
            self.fluctuation_scale,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::MeshState;
    use nalgebra::Vector3;

    /// A needle (a long element, `chi` 10) beside a sliver (edges alike, `chi` 1.41, nearly no
    /// volume): the collapse ratio names the needle, the watched distortion the sliver, which
    /// is the element a run pauses for.
    #[test]
    fn the_record_names_the_sliver_the_collapse_ratio_misses() {
        let h = 1e-3;
        let x = [
            // the needle
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(10.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
            // the sliver
            Vector3::new(1.0, 0.0, h),
            Vector3::new(-1.0, 0.0, h),
            Vector3::new(0.0, 1.0, -h),
            Vector3::new(0.0, -1.0, -h),
        ];
        let tets = [[0, 1, 2, 3], [4, 5, 6, 7]];
        let state = MeshState::measure(&x, &tets, &[1.0; 8], &[Vector3::zeros(); 8], 0.0);
        let chi_needle = crate::mesh::ops::collapse_ratio(&tets[0].map(|n| x[n as usize]));
        assert_eq!(state.worst_collapse_ratio, chi_needle);
        let sliver = crate::mesh::ops::distortion(&tets[1].map(|n| x[n as usize]));
        assert!(sliver > chi_needle, "sliver {sliver}, needle {chi_needle}");
        assert_eq!(state.worst_distortion_element, 1);
        assert_eq!(state.worst_distortion, sliver);
    }
}
