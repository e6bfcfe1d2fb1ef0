//! The normal of a contact: the master facet's, or one smoothed over the facets around the
//! contact point.
//!
//! The thesis uses the facet normal (6.4.1.1). On a faceted curved surface it is off the true
//! normal by up to half the angle between neighbouring facets, so a frictionless contact pushes
//! along a line that misses the centre of a sphere and makes it spin (thesis 6.6.3 shows the
//! effect). The smoothed normal interpolates, with the contact point's barycentric weights, corner
//! normals that average the area-weighted normals of the facets meeting at each corner: on a
//! sphere it is radial to second order in the facet size. Facets whose normal turns by more than
//! the crease angle from the contact facet's are left out, so the flat faces of a block keep
//! their own normal up to their edges.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::ContactSurface;

/// Which normal a contact's force conditions use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalKind {
    /// The master facet's own normal (the thesis).
    Facet,
    /// Corner normals averaged over the facets within the crease angle, interpolated at the
    /// contact point.
    #[default]
    Smooth,
}

/// How the normal of a contact is formed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalSettings {
    /// Facet normals (the thesis) or smoothed corner normals.
    pub kind: NormalKind,
    /// Facets meeting at a corner at more than this angle (radians) are not averaged.
    pub crease_angle: f64,
}

impl Default for NormalSettings {
    fn default() -> Self {
        Self {
            kind: NormalKind::Smooth,
            crease_angle: 30f64.to_radians(),
        }
    }
}

/// Area-weighted outward normals `(b - a) x (c - a)` of every facet of `surface` at positions `x`.
pub fn facet_normals(surface: &ContactSurface, x: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    (0..surface.faces.len())
        .map(|f| facet_normal(surface, x, f))
        .collect()
}

/// The area-weighted normal of one facet, as [`facet_normals`] gives it: detection computes
/// those of the facets a contact asks for only, a few among all the facets of the surface.
pub fn facet_normal(surface: &ContactSurface, x: &[Vector3<f64>], face: usize) -> Vector3<f64> {
    let [a, b, c] = surface.faces[face].map(|n| x[n as usize]);
    (b - a).cross(&(c - a))
}

/// Unit normal of the contact at barycentric `weights` on facet `face` of `surface`, given the
/// area-weighted facet normals from [`facet_normals`].
pub fn contact_normal(
    surface: &ContactSurface,
    facet: &[Vector3<f64>],
    face: usize,
    weights: &[f64; 3],
    settings: &NormalSettings,
) -> Vector3<f64> {
    contact_normal_with(surface, |g| facet[g], face, weights, settings)
}

/// [`contact_normal`] with the area-weighted facet normals given by `facet(g)` (for example
/// computed on demand by [`facet_normal`]), asked for the contact facet and, for smoothed normals, the
/// facets around its corners.
pub fn contact_normal_with(
    surface: &ContactSurface,
    mut facet: impl FnMut(usize) -> Vector3<f64>,
    face: usize,
    weights: &[f64; 3],
    settings: &NormalSettings,
) -> Vector3<f64> {
    let own = facet(face).normalize();
    if settings.kind == NormalKind::Facet {
        return own;
    }
    let cos_crease = settings.crease_angle.cos();
    let mut normal = Vector3::zeros();
    for (k, &w) in weights.iter().enumerate() {
        let corner = surface
            .faces_at_corner(face, k)
            .iter()
            .fold(Vector3::zeros(), |sum, &g| {
                let n = facet(g as usize);
                if n.dot(&own) >= cos_crease * n.norm() {
                    sum + n
                } else {
                    sum
                }
            });
        normal += corner.normalize() * w.max(0.0);
    }
    let length = normal.norm();
    if length > 0.0 {
        normal / length
    } else {
        own
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::test_blocks::elastic_boxes;
    use crate::mesh::BoxSpec;
    use crate::model::Model;

    fn cube() -> (Model, ContactSurface) {
        let model = elastic_boxes(&[BoxSpec {
            origin: [0.0; 3],
            size: [1.0, 1.0, 1.0],
            divisions: [3, 3, 3],
            mirror: Vec::new(),
        }]);
        let surface = ContactSurface::new(&model, 0);
        (model, surface)
    }

    #[test]
    fn flat_faces_keep_their_normal_up_to_the_edges() {
        let (model, surface) = cube();
        let facet = facet_normals(&surface, &model.reference);
        let settings = NormalSettings::default();
        for (f, n) in facet.iter().enumerate() {
            for w in [[1.0, 0.0, 0.0], [0.2, 0.3, 0.5], [0.0, 0.5, 0.5]] {
                let smooth = contact_normal(&surface, &facet, f, &w, &settings);
                assert!((smooth - n.normalize()).norm() < 1e-14, "facet {f}");
            }
        }
    }

    #[test]
    fn without_a_crease_angle_an_edge_corner_averages_both_faces() {
        let (model, surface) = cube();
        let facet = facet_normals(&surface, &model.reference);
        let settings = NormalSettings {
            kind: NormalKind::Smooth,
            crease_angle: std::f64::consts::PI,
        };
        // A top facet corner on the edge y = 0, z = 1 (not a cube corner).
        let (f, k) = (0..surface.faces.len())
            .flat_map(|f| (0..3).map(move |k| (f, k)))
            .find(|&(f, k)| {
                let x = model.reference[surface.faces[f][k] as usize];
                facet[f].normalize().z > 0.99 && x.y.abs() < 1e-12 && (x.x - 0.5).abs() < 0.2
            })
            .unwrap();
        let mut w = [0.0; 3];
        w[k] = 1.0;
        let n = contact_normal(&surface, &facet, f, &w, &settings);
        assert!(n.z > 0.1 && n.y < -0.1, "{n:?}");
        assert!(n.x.abs() < 1e-12);
    }
}
