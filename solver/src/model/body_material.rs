//! [`BodyMaterial`]: a [`Material`] together with the element loops compiled for it.
//!
//! A body holds its material as `Arc<dyn BodyMaterial>`. The trait is implemented for every
//! [`Material`], so a new constitutive model needs nothing but its `Material` implementation; the
//! loops are generic over the model, so its update inlines into them and the dispatch costs one
//! virtual call per assembly chunk, not one per element.

use std::sync::Arc;

use nalgebra::Vector3;

use super::assembly::{chunk_forces, ChunkJob};
use super::element::{element_forces, ElementForces};
use crate::material::{ElementDataError, ElementState, Material, RemeshedElements};

/// A [`Material`] with the element loops compiled for it; implemented for every `Material`.
pub trait BodyMaterial: Material {
    /// Runs the assembly's element loop over one chunk (`model::assembly`), returning the lowest
    /// inverted element of the chunk (`usize::MAX` if none).
    fn assemble_chunk(&self, job: &ChunkJob<'_>) -> usize;

    /// [`element_forces`] at zero strain rate, through the trait object.
    fn static_element_forces(
        &self,
        element: usize,
        grad_n: &[Vector3<f64>; 4],
        volume: f64,
        u: &[Vector3<f64>; 4],
        state: ElementState<'_>,
    ) -> ElementForces;

    /// [`Material::remeshed`] through the trait object: the body's material for its new mesh
    /// (`None`: the same material serves it).
    fn remeshed_material(
        &self,
        elements: &RemeshedElements<'_>,
    ) -> Result<Option<Arc<dyn BodyMaterial>>, (usize, String)>;

    /// [`Material::with_element_data`] through the trait object (`None`: the same material).
    fn with_element_data_material(
        &self,
        data: &[f64],
    ) -> Result<Option<Arc<dyn BodyMaterial>>, ElementDataError>;
}

impl<M: Material> BodyMaterial for M {
    fn assemble_chunk(&self, job: &ChunkJob<'_>) -> usize {
        chunk_forces(self, job)
    }

    fn remeshed_material(
        &self,
        elements: &RemeshedElements<'_>,
    ) -> Result<Option<Arc<dyn BodyMaterial>>, (usize, String)> {
        Ok(self
            .remeshed(elements)?
            .map(|m| Arc::new(m) as Arc<dyn BodyMaterial>))
    }

    fn static_element_forces(
        &self,
        element: usize,
        grad_n: &[Vector3<f64>; 4],
        volume: f64,
        u: &[Vector3<f64>; 4],
        state: ElementState<'_>,
    ) -> ElementForces {
        element_forces(self, element, grad_n, volume, u, None, state)
    }

    fn with_element_data_material(
        &self,
        data: &[f64],
    ) -> Result<Option<Arc<dyn BodyMaterial>>, ElementDataError> {
        Ok(self
            .with_element_data(data)?
            .map(|m| Arc::new(m) as Arc<dyn BodyMaterial>))
    }
}
