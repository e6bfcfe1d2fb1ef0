//! Saint-Venant-Kirchhoff under uniaxial stress (CATALOGUE `elastic/svk-uniaxial`), stretch 0.7 to
//! 1.5, against the closed form of (2.123): `E22 = -nu E11`, `S11 = E E11`,
//! `P11 = E l (l^2 - 1) / 2`.

mod common;

use common::*;
use impact_references::analytic::svk_uniaxial;
use impact_solver::material::MaterialModel;
use impact_solver::model::{Constraint, Motion, TimeFunction};
use impact_solver::statics::{solve_static, StaticSettings};

#[test]
fn uniaxial_stress_matches_closed_form_from_stretch_0_7_to_1_5() {
    let (lx, ly, lz) = (2.0, 0.5, 0.4);
    let c = STEEL;
    for stretch in [0.7, 0.8, 0.9, 0.95, 1.05, 1.2, 1.35, 1.5] {
        let mut p = problem(
            box_body([lx, ly, lz], [4, 2, 2], 0.2, 5),
            MaterialModel::SaintVenantKirchhoff(c),
        );
        let on = |axis: usize, value: f64| -> Vec<u32> {
            (0..p.model.node_count() as u32)
                .filter(|&n| (p.model.reference[n as usize][axis] - value).abs() < 1e-12)
                .collect()
        };
        let (x0, x1, y0, z0) = (on(0, 0.0), on(0, lx), on(1, 0.0), on(2, 0.0));
        let roller = |name: &str, nodes, d: usize| {
            let mut dofs = [false; 3];
            dofs[d] = true;
            Constraint {
                name: name.into(),
                nodes,
                motion: Motion::Fixed(dofs),
            }
        };
        p.constraints.push(roller("x0", x0, 0));
        p.constraints.push(roller("y0", y0, 1));
        p.constraints.push(roller("z0", z0, 2));
        p.constraints.push(Constraint {
            name: "pull".into(),
            nodes: x1.clone(),
            motion: Motion::Displacement(
                [true, false, false],
                TimeFunction::Ramp {
                    t0: 0.0,
                    t1: 1.0,
                    from: 0.0,
                    to: (stretch - 1.0) * lx,
                },
            ),
        });
        let s = solve_static(
            &p,
            &StaticSettings {
                load_steps: 8,
                ..Default::default()
            },
        )
        .unwrap();
        // Closed form (references/analytic.rs).
        let exact = svk_uniaxial(&c, stretch);
        let (e11, e22, p11) = (exact.e11, exact.e22, exact.p11);
        // Measured: the lateral stretch of the far corner, and the end reaction over the reference area.
        let corner = (0..p.model.node_count())
            .find(|&n| (p.model.reference[n] - v3([lx, ly, lz])).norm() < 1e-12)
            .unwrap();
        let l2 = 1.0 + s.u[corner].y / ly;
        let l3 = 1.0 + s.u[corner].z / lz;
        let measured_e22 = 0.5 * (l2 * l2 - 1.0);
        let measured_e33 = 0.5 * (l3 * l3 - 1.0);
        let measured_p11 = s.total_reaction(&x1).x / (ly * lz);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(
            rel(measured_e22, e22) < 1e-8,
            "stretch {stretch}: E22 {measured_e22} vs {e22}"
        );
        assert!(
            rel(measured_e33, e22) < 1e-8,
            "stretch {stretch}: E33 {measured_e33} vs {e22}"
        );
        assert!(
            rel(measured_p11, p11) < 1e-8,
            "stretch {stretch}: P11 {measured_p11} vs {p11}"
        );
        // S11 = P11 / l (F is diagonal): E E11.
        assert!(
            rel(measured_p11 / stretch, c.youngs_modulus * e11) < 1e-8,
            "stretch {stretch}: S11"
        );
    }
}
