//! The assembly against the serial scatter it must reproduce bitwise.

use super::*;
use crate::material::ElementState;
use crate::material::IsotropicElastic;
use crate::material::MaterialModel;
use crate::mesh::{box_mesh, perturb_interior, BoxSpec};

const CONCRETE: IsotropicElastic = IsotropicElastic {
    density: 2300.0,
    youngs_modulus: 30e9,
    poisson_ratio: 0.2,
};

/// Two bodies of different materials, the first of `cells` cells, the second with a node that
/// no element uses.
fn model(cells: [usize; 3]) -> Model {
    let body = |origin: [f64; 3], divisions: [usize; 3], seed| {
        let spec = BoxSpec {
            origin,
            size: [1.0, 0.6, 0.4],
            divisions,
            mirror: Vec::new(),
        };
        let mut mesh = box_mesh(&spec);
        perturb_interior(&mut mesh, &spec, 0.2, seed);
        mesh
    };
    let mut second = body([2.0, 0.0, 0.0], [5, 4, 3], 2);
    second.nodes.push(Vector3::new(9.0, 9.0, 9.0));
    Model::new(vec![
        (
            "a".into(),
            body([0.0; 3], cells, 1),
            MaterialModel::LinearElastic(CONCRETE),
        ),
        (
            "b".into(),
            second,
            MaterialModel::SaintVenantKirchhoff(CONCRETE),
        ),
    ])
    .unwrap()
}

fn displacement(model: &Model, amplitude: f64) -> Vec<Vector3<f64>> {
    model
        .reference
        .iter()
        .map(|x| amplitude * Vector3::new((7.0 * x.y).sin(), x.z * x.x, (5.0 * x.x).cos()))
        .collect()
}

/// The serial scatter the assembly must reproduce bitwise.
fn serial(model: &Model, u: &[Vector3<f64>]) -> (Vec<Vector3<f64>>, Option<usize>) {
    let mut f = vec![Vector3::zeros(); u.len()];
    let mut inverted = None;
    for body in &model.bodies {
        for e in body.elements.clone() {
            let tet = model.tets[e];
            let ue = tet.map(|n| u[n as usize]);
            let local = e - body.elements.start;
            let update = body.material.static_element_forces(
                local,
                &model.grad_n(e),
                model.volume(e),
                &ue,
                ElementState::stateless(),
            );
            if !(update.det > 0.0) && inverted.is_none() {
                inverted = Some(e);
            }
            for a in 0..4 {
                f[tet[a] as usize] += update.forces[a];
            }
        }
    }
    (f, inverted)
}

#[test]
fn any_chunking_gives_the_serial_sum_bitwise() {
    let model = model([9, 6, 4]);
    let bodies: Vec<_> = model.bodies.iter().map(|b| b.elements.clone()).collect();
    let n = model.element_count();
    let assembler = &model.assembler;
    let first = &assembler.first_element;
    for amplitude in [1e-3, 1.0] {
        let u = displacement(&model, amplitude);
        let (expected, inverted) = serial(&model, &u);
        assert_eq!(
            inverted.is_some(),
            amplitude > 0.1,
            "the large field inverts"
        );
        for length in [1, 5, 64, 333, n / 3, n] {
            let mut layout = Layout::with_chunk_lengths(
                first,
                &model.tets,
                &bodies,
                &vec![length; bodies.len()],
                0..model.tets.len(),
            );
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                // Garbage in `f` must not leak into the result.
                let mut f = vec![Vector3::repeat(f64::NAN); u.len()];
                let found = pool.install(|| {
                    assembler.assemble_with(
                        &mut layout,
                        &model,
                        u[..].into(),
                        None,
                        f[..].as_mut().into(),
                    )
                });
                assert_eq!(found, inverted, "length {length}, {threads} threads");
                let same = f
                    .iter()
                    .zip(&expected)
                    .all(|(a, b)| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
                assert!(same, "length {length}, {threads} threads");
            }
        }
    }
}

#[test]
fn layout_follows_the_thread_count() {
    // The first body is large enough to be cut into more chunks for more threads.
    let model = model([48, 24, 12]);
    let u = displacement(&model, 1e-3);
    let (expected, _) = serial(&model, &u);
    let mut chunks = Vec::new();
    for threads in [1, 2, 4, 1] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut f = vec![Vector3::zeros(); u.len()];
        assert_eq!(
            pool.install(|| model.internal_forces(&u, &mut f).unwrap()),
            None
        );
        let bits = |f: &[Vector3<f64>]| -> Vec<u64> {
            f.iter()
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .collect()
        };
        assert_eq!(bits(&f), bits(&expected), "{threads} threads");
        let layout = model.assembler.layout.lock().unwrap();
        assert_eq!(layout.threads, threads);
        chunks.push(layout.chunks.iter().filter(|c| c.body == 0).count());
        assert_eq!(layout.buffer.is_empty(), threads == 1);
    }
    assert!(chunks[0] == 1 && chunks[1] > 1 && chunks[2] > chunks[1] && chunks[3] == 1);
}
