//! Proptest strategies over the seeded generators of this crate (feature `strategies`), so that
//! a property test draws the very queries the cross-check and the CCD sweep draw, and shrinks
//! to a seed one can replay with [`crate::queries::Family::generate`].
//!
//! The strategies draw a seed and map it through the deterministic generator rather than build
//! values from proptest's own primitives: one generator set serves the seeded sweeps (whose
//! bits the cross-check's cached answers depend on) and the property tests.

use impact_solver::rng::SplitMix64;
use nalgebra::Matrix3;
use proptest::prelude::*;

use crate::queries::{Family, Query};

/// One query of a family of `mix` (chosen uniformly), from a random seed: `(family, seed,
/// query)`, the seed to replay it by `family.generate(&mut SplitMix64::new(seed))`.
pub fn query(mix: &'static [Family]) -> impl Strategy<Value = (Family, u64, Query)> {
    (prop::sample::select(mix), any::<u64>()).prop_map(|(family, seed)| {
        let query = family.generate(&mut SplitMix64::new(seed));
        (family, seed, query)
    })
}

/// A displacement gradient `H` (so `F = I + H`) with every entry uniform in `[-0.3, 0.3]`:
/// strain states from small to large, with rotations, for the kinematics and material
/// properties (callers filter out `det F` near zero).
pub fn displacement_gradient() -> impl Strategy<Value = Matrix3<f64>> {
    prop::array::uniform9(-0.3f64..0.3).prop_map(|a| Matrix3::from_row_slice(&a))
}
