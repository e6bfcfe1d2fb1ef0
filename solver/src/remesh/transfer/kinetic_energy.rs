//! The kinetic energy a remeshing's velocity transfer loses, given back to the region's nodes.
//!
//! T3 (8.10) interpolates the velocity at a new node from the old element that holds it: an
//! average of the old nodes' velocities, whose kinetic energy is less than the average of
//! theirs (the interpolated field is smoother than the one it samples). Where the velocity
//! varies steeply over an element, as in the concrete the nail drags along, the new nodes of a
//! region carry 20 % less kinetic energy than the nodes they replace, and the nail run lost
//! 2.6 % of its energy over 233 remeshings that way (docs/remeshing.md, "The nail case").
//! A remap conserves mass, momentum and energy (the conservative remap of ALE codes; DeBar's
//! fix puts the kinetic energy the momentum remap loses into internal energy, which concrete
//! without a thermal state has no place for). Here the velocity fluctuations of the nodes of
//! the region's new elements (the new nodes, and the kept ones whose masses those elements
//! changed) about their mean are scaled: `v_i <- v_mean + s (v_i - v_mean)`. Their momentum is
//! unchanged (the fluctuations weigh nothing in it), and `s` makes the body's kinetic energy
//! what it was.

use nalgebra::Vector3;

/// What [`restore_kinetic_energy`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KineticRestore {
    /// The factor on the nodes' velocity fluctuations (1: nothing changed).
    pub scale: f64,
    /// The part of `deficit` (J) left unrestored: the fluctuations could not give it within
    /// `max_scale`, or there were none.
    pub left: f64,
}

/// Scales the fluctuations of the velocities `v` at `nodes` about their mass-weighted mean
/// (masses `mass`) so that their kinetic energy changes by `deficit` (J; positive: it grows),
/// within a factor `max_scale` on the fluctuations (the rest is left, and reported). The
/// momentum of `nodes` is unchanged to round-off.
pub fn restore_kinetic_energy(
    v: &mut [Vector3<f64>],
    mass: &[f64],
    nodes: &[usize],
    deficit: f64,
    max_scale: f64,
) -> KineticRestore {
    let total: f64 = nodes.iter().map(|&i| mass[i]).sum();
    if nodes.is_empty() || !(total > 0.0) || deficit == 0.0 {
        return KineticRestore {
            scale: 1.0,
            left: deficit,
        };
    }
    let mean = nodes.iter().map(|&i| mass[i] * v[i]).sum::<Vector3<f64>>() / total;
    let fluctuation: f64 = nodes
        .iter()
        .map(|&i| 0.5 * mass[i] * (v[i] - mean).norm_squared())
        .sum();
    if !(fluctuation > 0.0) {
        return KineticRestore {
            scale: 1.0,
            left: deficit,
        };
    }
    let wanted = ((fluctuation + deficit) / fluctuation).max(0.0).sqrt();
    let scale = wanted.min(max_scale);
    for &i in nodes {
        v[i] = mean + scale * (v[i] - mean);
    }
    KineticRestore {
        scale,
        left: fluctuation + deficit - scale * scale * fluctuation,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinetic(v: &[Vector3<f64>], mass: &[f64]) -> f64 {
        v.iter()
            .zip(mass)
            .map(|(v, m)| 0.5 * m * v.norm_squared())
            .sum()
    }

    fn momentum(v: &[Vector3<f64>], mass: &[f64]) -> Vector3<f64> {
        v.iter().zip(mass).map(|(v, m)| *m * v).sum()
    }

    /// Four nodes moving at different velocities, the last one not among `nodes`.
    fn field() -> (Vec<Vector3<f64>>, Vec<f64>) {
        (
            vec![
                Vector3::new(0.0, -150.0, 3.0),
                Vector3::new(1.0, -40.0, 0.0),
                Vector3::new(-2.0, -90.0, 1.0),
                Vector3::new(0.0, -7.0, 0.0),
            ],
            vec![1e-6, 3e-6, 2e-6, 5e-6],
        )
    }

    #[test]
    fn the_deficit_is_given_back_and_the_momentum_kept() {
        let (mut v, mass) = field();
        let (k0, p0) = (kinetic(&v, &mass), momentum(&v, &mass));
        let deficit = 1e-3;
        let r = restore_kinetic_energy(&mut v, &mass, &[0, 1, 2], deficit, 2.0);
        assert!(r.scale > 1.0 && r.left.abs() < 1e-15, "{r:?}");
        assert!((kinetic(&v, &mass) - (k0 + deficit)).abs() < 1e-12 * k0);
        assert!((momentum(&v, &mass) - p0).norm() < 1e-12 * p0.norm());
        assert_eq!(v[3], Vector3::new(0.0, -7.0, 0.0));
    }

    #[test]
    fn a_surplus_is_taken_back_as_well() {
        let (mut v, mass) = field();
        let k0 = kinetic(&v, &mass);
        let r = restore_kinetic_energy(&mut v, &mass, &[0, 1, 2], -1e-3, 2.0);
        assert!(r.scale < 1.0 && r.left.abs() < 1e-15, "{r:?}");
        assert!((kinetic(&v, &mass) - (k0 - 1e-3)).abs() < 1e-12 * k0);
    }

    #[test]
    fn what_the_fluctuations_cannot_give_within_the_bound_is_left() {
        let (mut v, mass) = field();
        let k0 = kinetic(&v, &mass);
        let r = restore_kinetic_energy(&mut v, &mass, &[0, 1, 2], 1.0, 1.5);
        assert_eq!(r.scale, 1.5);
        assert!((kinetic(&v, &mass) + r.left - (k0 + 1.0)).abs() < 1e-12);
    }

    #[test]
    fn a_uniform_velocity_is_left_alone() {
        let mut v = vec![Vector3::new(0.0, -200.0, 0.0); 3];
        let mass = [1.0, 2.0, 3.0];
        let r = restore_kinetic_energy(&mut v, &mass, &[0, 1, 2], 0.5, 2.0);
        assert_eq!(
            r,
            KineticRestore {
                scale: 1.0,
                left: 0.5
            }
        );
        assert!(v.iter().all(|v| *v == Vector3::new(0.0, -200.0, 0.0)));
    }
}
