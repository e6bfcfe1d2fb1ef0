//! Element kinematics and material laws against independent constructions.

mod common;

use common::*;
use impact_references::analytic::corotated_cauchy;
use impact_references::strategies::displacement_gradient;
use impact_solver::kinematics::{
    cofactor, polar_decomposition, polar_rotation, shape_gradients, signed_volume,
};
use impact_solver::material::{
    Deformation, ElementState, LinearElastic, Material, SaintVenantKirchhoff,
};

/// First Piola-Kirchhoff stress of a model without history at `F`.
fn first_piola(m: &dyn Material, f: &Matrix3<f64>) -> Matrix3<f64> {
    let at = Deformation::at_rest(f - Matrix3::identity());
    m.update(0, &at, ElementState::stateless())
        .expect("an elastic model updates every element")
}
use impact_solver::mesh::{boundary_faces, boundary_nodes, box_mesh, element_quality};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;

fn tet() -> [Vector3<f64>; 4] {
    [
        v3([0.1, 0.0, 0.2]),
        v3([1.2, 0.1, 0.0]),
        v3([0.3, 0.9, 0.1]),
        v3([0.2, 0.3, 1.1]),
    ]
}

#[test]
fn shape_gradients_reproduce_linear_fields() {
    let x = tet();
    let (g, v) = shape_gradients(&x).unwrap();
    assert!((v - signed_volume(&x)).abs() < 1e-15);
    // sum_a x_a (x) grad N_a = I and sum_a grad N_a = 0 (partition of unity).
    let id: Matrix3<f64> = (0..4).map(|a| x[a] * g[a].transpose()).sum();
    assert!((id - Matrix3::identity()).norm() < 1e-14);
    assert!(g.iter().sum::<Vector3<f64>>().norm() < 1e-14);
}

#[test]
fn element_quality_of_the_cube_corner_tetrahedron() {
    let x = [
        v3([0.0; 3]),
        v3([1.0, 0.0, 0.0]),
        v3([0.0, 1.0, 0.0]),
        v3([0.0, 0.0, 1.0]),
    ];
    let q = element_quality(&x);
    assert!((q.volume - 1.0 / 6.0).abs() < 1e-15);
    // Largest face is the slanted one, area sqrt(3)/2: altitude 3 V / A = 1/sqrt(3).
    assert!((q.min_altitude - 1.0 / 3f64.sqrt()).abs() < 1e-15);
    assert!((q.volume_size() - 1.0).abs() < 1e-15);
    assert!((q.edge_ratio - 2f64.sqrt()).abs() < 1e-15);
}

#[test]
fn box_mesh_volume_and_boundary_are_exact() {
    let (nx, ny, nz) = (3, 4, 5);
    let mesh = box_mesh(&spec([1.5, 2.0, 0.5], [nx, ny, nz]));
    assert_eq!(mesh.tets.len(), 6 * nx * ny * nz);
    assert!((mesh.volume() - 1.5).abs() < 1e-12);
    let faces = boundary_faces(&mesh);
    assert_eq!(
        faces.len(),
        4 * (nx * ny + ny * nz + nx * nz),
        "two triangles per boundary cell face"
    );
    // Outward normals: the boundary faces close the surface, so sum of area vectors is zero and
    // the divergence theorem gives the volume: V = 1/3 sum (x_c . n) A.
    let mut area_sum = Vector3::zeros();
    let mut volume = 0.0;
    for f in &faces {
        let [a, b, c] = f.nodes.map(|n| mesh.nodes[n as usize]);
        let an = 0.5 * (b - a).cross(&(c - a));
        area_sum += an;
        volume += (a + b + c).dot(&an) / 9.0;
    }
    assert!(area_sum.norm() < 1e-12);
    assert!(
        (volume - 1.5).abs() < 1e-12,
        "outward-oriented faces enclose {volume}"
    );
    let nodes = boundary_nodes(&faces);
    assert_eq!(
        nodes.len(),
        (nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1)
    );
}

#[test]
fn polar_rotation_of_a_rotation_is_itself_and_of_an_inversion_none() {
    let q = nalgebra::Rotation3::from_euler_angles(0.3, -1.2, 2.9);
    let r = polar_rotation(q.matrix()).unwrap();
    assert!((r - q.matrix()).norm() < 1e-15);
    assert!(polar_rotation(&-Matrix3::identity()).is_none());
    assert!(polar_rotation(&Matrix3::zeros()).is_none());
    assert!(polar_rotation(&Matrix3::repeat(f64::NAN)).is_none());
}

proptest! {
    #[test]
    fn polar_decomposition_is_exact(h in displacement_gradient()) {
        let f = Matrix3::identity() + h;
        prop_assume!(f.determinant() > 0.1);
        let (r, u) = polar_decomposition(&f).unwrap();
        prop_assert!((r * u - f).norm() < 1e-13);
        prop_assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-13);
        prop_assert!((r.determinant() - 1.0).abs() < 1e-13);
        prop_assert!((u - u.transpose()).norm() < 1e-13);
        prop_assert!(u.symmetric_eigenvalues().min() > 0.0);
    }

    /// Newton's iteration gives the rotation of the SVD to round-off (times the condition of F),
    /// for small strains, large distortions and any rotation.
    #[test]
    fn polar_rotation_matches_the_svd(
        h in displacement_gradient(),
        scale in prop::sample::select(vec![1e-6, 1e-3, 1.0, 5.0]),
        axis in prop::array::uniform3(-1.0f64..1.0),
        angle in -3.2f64..3.2,
    ) {
        let stretch = Matrix3::identity() + h * scale;
        prop_assume!(stretch.determinant() > 0.05);
        let axis = Vector3::from(axis);
        prop_assume!(axis.norm() > 1e-3);
        let q = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
        let f = q.matrix() * stretch;
        // Reference from the SVD F = W S V^T, R = W V^T (accurate for ill-conditioned F, where
        // the eigen-decomposition of C = F^T F squares the condition number).
        let svd = f.svd(true, true);
        let expected = svd.u.unwrap() * svd.v_t.unwrap();
        let condition = svd.singular_values.max() / svd.singular_values.min();
        let r = polar_rotation(&f).unwrap();
        prop_assert!(
            (r - expected).norm() < 1e-14 * condition,
            "error {:e}, condition {condition:e}", (r - expected).norm()
        );
        prop_assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
    }

    #[test]
    fn cofactor_is_det_times_inverse_transpose(h in displacement_gradient()) {
        let f = Matrix3::identity() + h;
        prop_assume!(f.determinant().abs() > 0.1);
        let expected = f.determinant() * f.try_inverse().unwrap().transpose();
        prop_assert!((cofactor(&f) - expected).norm() < 1e-13);
    }

    /// The consistent tangent equals a central finite difference of `P` (error O(eps^2)).
    #[test]
    fn tangents_match_finite_differences(h in displacement_gradient(), d in displacement_gradient()) {
        let f = Matrix3::identity() + h;
        prop_assume!(f.determinant() > 0.2);
        let check = |m: &dyn Material| {
            let eps = 1e-6;
            let p = |f: Matrix3<f64>| first_piola(m, &f);
            let fd = (p(f + d * eps) - p(f - d * eps)) / (2.0 * eps);
            let exact = m.first_piola_derivative(&f, &d).expect("a closed-form tangent");
            (fd - exact).norm() / (exact.norm() + 1e-3 * STEEL.youngs_modulus)
        };
        prop_assert!(check(&SaintVenantKirchhoff::new(STEEL)) < 1e-7);
        prop_assert!(check(&LinearElastic::new(STEEL)) < 1e-7);
    }

    /// Both models are objective: `P(Q F) = Q P(F)` for any rotation `Q`.
    #[test]
    fn stress_is_objective(h in displacement_gradient(), axis in prop::array::uniform3(-1.0f64..1.0), angle in -3.1f64..3.1) {
        let f = Matrix3::identity() + h;
        prop_assume!(f.determinant() > 0.2 && Vector3::from(axis).norm() > 0.1);
        let q = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(Vector3::from(axis)), angle).into_inner();
        for m in [&SaintVenantKirchhoff::new(STEEL) as &dyn Material, &LinearElastic::new(STEEL)] {
            let qf = q * f;
            let p = first_piola(m, &f);
            let pq = first_piola(m, &qf);
            prop_assert!((pq - q * p).norm() < 1e-12 * STEEL.youngs_modulus);
        }
    }
}

#[test]
fn linear_elastic_matches_its_definition_through_the_rotation() {
    let f = Matrix3::new(1.05, 0.2, -0.1, -0.15, 0.97, 0.08, 0.12, -0.05, 1.1);
    let m = LinearElastic::new(STEEL);
    let p = first_piola(&m, &f);
    let sigma = p * f.transpose() / f.determinant();
    let sigma = 0.5 * (sigma + sigma.transpose());
    let expected = corotated_cauchy(&STEEL, &f);
    assert!((sigma - expected).norm() / expected.norm() < 1e-13);
}
