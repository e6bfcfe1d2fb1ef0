//! Diagnostic for remeshing runs (issue 21): runs a scene with `analysis.explicit.remeshing` to
//! a given time, then describes the remeshed body's most distorted elements (collapse ratio,
//! mean ratio, volume, where their nodes lie: inside, or on boundary faces of how many
//! distinct planes), the folds of its surface (boundary edges whose faces turn by more than 120
//! degrees) and the fastest nodes of the model (a contact kick or an instability shows there
//! first).
//!
//! ```text
//! cargo run --release -p impact-solver --example remesh_diagnose -- \
//!     cases/penetration/nail-200ms.yaml 1.0e-5 [worst elements = 12]
//! ```
//! With `LOOSE=1` the run's energy-balance check is off, to look at the step a blow-up starts.
#![allow(clippy::unwrap_used)]

use std::collections::HashMap;
use std::path::Path;

use impact_solver::dynamics::OutputSettings;
use impact_solver::mesh::ops::{collapse_ratio, distortion, mean_ratio};
use impact_solver::mesh::{face_key, TET_FACES};
use impact_solver::remesh::run_remeshing;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, Scene};
use nalgebra::Vector3;

/// The distinct planes (unit normals up to sign, to 1e-3) among `normals`.
fn distinct_planes(normals: &[Vector3<f64>]) -> usize {
    let mut planes: Vec<Vector3<f64>> = Vec::new();
    for n in normals {
        if !planes
            .iter()
            .any(|p| (n - p).norm() < 1e-3 || (n + p).norm() < 1e-3)
        {
            planes.push(*n);
        }
    }
    planes.len()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = Scene::from_yaml_file_entry(Path::new(&args[1]), "scene").unwrap();
    let end: f64 = args[2].parse().unwrap();
    let worst_n: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(12);
    let problem = build_problem(&scene).unwrap();
    let Analysis::Explicit(ExplicitAnalysis {
        mut settings,
        remeshing,
    }) = scene.analysis.clone()
    else {
        panic!("an explicit analysis is needed")
    };
    settings.end_time = end;
    if std::env::var("LOOSE").is_ok() {
        settings.instability_energy_tolerance = 1e9;
    }
    let policy = remeshing
        .as_ref()
        .expect("the scene remeshes")
        .policy(&problem)
        .unwrap();
    let run = run_remeshing(
        &problem,
        &settings,
        &OutputSettings::default(),
        &policy,
        &mut [],
        &mut |r| eprintln!("  {}", r.summary()),
    )
    .unwrap();
    let p = run.problem.as_ref().unwrap_or(&problem);
    let m = &p.model;
    let body = &m.bodies[policy.body];
    let x: Vec<Vector3<f64>> = m
        .reference
        .iter()
        .zip(&run.state.u)
        .map(|(a, b)| a + b)
        .collect();
    println!(
        "t = {:.4e} s, dt = {:.3e} s, {} remeshings",
        run.state.time,
        run.state.time_step,
        run.records.len()
    );
    // Where the wall time went: the step's phases, and the rest (remeshing, distortion checks).
    let phases = run.summary.phase_seconds;
    let stepping: f64 = phases.named().iter().map(|(_, s)| s).sum();
    print!(
        "wall {:.1} s over {} steps: remeshing and checks {:.1} s",
        run.summary.wall_seconds,
        run.summary.steps,
        run.summary.wall_seconds - stepping
    );
    for (name, seconds) in phases.named() {
        print!(", {name} {seconds:.1} s");
    }
    println!();

    // Folds of the remeshed body's surface: boundary edges whose two faces' outward normals
    // point against each other (a crease sharper than 120 degrees), where the surface has
    // folded back on itself and traps the nodes under it.
    {
        let faces = impact_solver::mesh::boundary_faces_of(&m.tets[body.elements.clone()]);
        let normal = |f: &[u32; 3]| {
            let [a, b, c] = f.map(|i| x[i as usize]);
            (b - a).cross(&(c - a)).normalize()
        };
        let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (k, f) in faces.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (f.nodes[i], f.nodes[(i + 1) % 3]);
                by_edge.entry((a.min(b), a.max(b))).or_default().push(k);
            }
        }
        let mut folds: Vec<(f64, (u32, u32))> = by_edge
            .iter()
            .filter(|(_, fs)| fs.len() == 2)
            .map(|(e, fs)| {
                (
                    normal(&faces[fs[0]].nodes).dot(&normal(&faces[fs[1]].nodes)),
                    *e,
                )
            })
            .filter(|(d, _)| *d < -0.5)
            .collect();
        folds.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        print!("{} folded surface edges", folds.len());
        if let Some((d, (a, b))) = folds.first() {
            let p = x[*a as usize] * 1e3;
            print!(
                " (sharpest: normals' dot {d:.3}, edge {a}-{b} at ({:.3}, {:.3}, {:.3}) mm)",
                p.x, p.y, p.z
            );
        }
        println!();
    }

    // The elements that set the stable time step (smallest altitude over wave speed): `STEP=n`
    // lists the n smallest, with their volume ratio J = det F (from the stress-free state) and
    // how many of their faces lie on the surface.
    if let Ok(n) = std::env::var("STEP") {
        let n: usize = n.parse().unwrap();
        let on_surface: std::collections::HashSet<[u32; 3]> =
            impact_solver::mesh::boundary_faces_of(&m.tets)
                .iter()
                .map(|f| face_key(f.nodes))
                .collect();
        let mut steps: Vec<(f64, usize)> = (0..m.tets.len())
            .map(|e| {
                let c = m.tets[e].map(|k| x[k as usize]);
                let l = impact_solver::mesh::element_quality(&c).min_altitude;
                (
                    l / m.material_of(e).constants().dilatational_wave_speed(),
                    e,
                )
            })
            .collect();
        steps.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(dt, e) in steps.iter().take(n) {
            let c = m.tets[e].map(|k| x[k as usize]);
            let q = impact_solver::mesh::element_quality(&c);
            let centroid = (c[0] + c[1] + c[2] + c[3]) * 0.25e3;
            let faces = TET_FACES
                .iter()
                .filter(|f| on_surface.contains(&face_key(f.map(|i| m.tets[e][i]))))
                .count();
            println!(
                "  step {dt:.3e} s: element {e}, altitude {:.4} mm, distortion {:.1}, \
                 J {:.3}, {faces} surface faces, centroid ({:.3}, {:.3}, {:.3}) mm",
                q.min_altitude * 1e3,
                distortion(&c),
                m.deformation_gradient(e, &run.state.u).determinant(),
                centroid.x,
                centroid.y,
                centroid.z
            );
        }
    }

    // The element that sets the stable time step (smallest altitude over wave speed).
    {
        let (limit, e) = m.current_critical_time_step(&run.state.u);
        let b = m
            .bodies
            .iter()
            .position(|b| b.elements.contains(&e))
            .unwrap();
        let c = m.tets[e].map(|n| x[n as usize]);
        let q = impact_solver::mesh::element_quality(&c);
        let centroid = (c[0] + c[1] + c[2] + c[3]) * 0.25e3;
        let (short, long) = (0..4)
            .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
            .map(|(i, j)| (c[i] - c[j]).norm())
            .fold((f64::INFINITY, 0.0_f64), |(s, l), d| (s.min(d), l.max(d)));
        println!(
            "stable limit {limit:.3e} s from element {e} ({}): smallest altitude {:.4} mm, \
             edges {:.4}-{:.4} mm, distortion {:.1}, centroid ({:.3}, {:.3}, {:.3}) mm",
            m.bodies[b].name,
            q.min_altitude * 1e3,
            short * 1e3,
            long * 1e3,
            distortion(&c),
            centroid.x,
            centroid.y,
            centroid.z
        );
    }

    let mut speeds: Vec<(f64, usize)> = run
        .state
        .v_full
        .iter()
        .enumerate()
        .map(|(n, v)| (v.norm(), n))
        .collect();
    speeds.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (s, n) in speeds.iter().take(4) {
        let b = m.bodies.iter().position(|b| b.nodes.contains(n)).unwrap();
        let p = x[*n] * 1e3;
        println!(
            "fast node {n} ({}) {s:.2} m/s at ({:.4}, {:.4}, {:.4}) mm",
            m.bodies[b].name, p.x, p.y, p.z
        );
    }

    // Nodes asked for by `NODES=1,2,3`: position (mm) and velocity (m/s).
    if let Ok(list) = std::env::var("NODES") {
        for n in list.split(',').map(|s| s.trim().parse::<usize>().unwrap()) {
            let (p, v) = (x[n] * 1e3, run.state.v_full[n]);
            println!(
                "node {n}: x ({:.5}, {:.5}, {:.5}) mm, v ({:.2}, {:.2}, {:.2}) m/s",
                p.x, p.y, p.z, v.x, v.y, v.z
            );
            for other in m.bodies.iter().filter(|b| !b.nodes.contains(&n)) {
                let tets = &m.tets[other.elements.clone()];
                let locator = impact_solver::mesh::ops::Locator::new(&x, tets).unwrap();
                let at = locator.locate(&x[n]);
                if at.distance > 0.0 || at.barycentric.iter().any(|&w| w < -1e-12) {
                    continue;
                }
                let faces = impact_solver::mesh::boundary_faces_of(tets);
                let (depth, face) = faces
                    .iter()
                    .map(|f| {
                        let [a, b, c] = f.nodes.map(|i| x[i as usize]);
                        let q = impact_solver::geometry::proximity::closest_point_on_triangle(
                            &x[n], &a, &b, &c,
                        );
                        ((q - x[n]).norm(), f.nodes)
                    })
                    .fold(
                        (f64::INFINITY, [0; 3]),
                        |a, b| if b.0 < a.0 { b } else { a },
                    );
                println!(
                    "    inside {} by {depth:.3e} m (nearest boundary face {face:?})",
                    other.name
                );
            }
        }
    }

    // Nodes of the remeshed body inside another body (a contact partner it should not enter).
    for (o, other) in m.bodies.iter().enumerate() {
        if o == policy.body {
            continue;
        }
        let tets = &m.tets[other.elements.clone()];
        let locator = impact_solver::mesh::ops::Locator::new(&x, tets).unwrap();
        let faces = impact_solver::mesh::boundary_faces_of(tets);
        let mut inside = Vec::new();
        for n in body.nodes.clone() {
            let at = locator.locate(&x[n]);
            if at.distance > 0.0 || at.barycentric.iter().any(|&w| w < -1e-12) {
                continue;
            }
            let depth = faces
                .iter()
                .map(|f| {
                    let [a, b, c] = f.nodes.map(|i| x[i as usize]);
                    (impact_solver::geometry::proximity::closest_point_on_triangle(
                        &x[n], &a, &b, &c,
                    ) - x[n])
                        .norm()
                })
                .fold(f64::INFINITY, f64::min);
            let on_plane = at.barycentric.iter().any(|&w| w <= 1e-9);
            inside.push((n, depth, on_plane));
        }
        if !inside.is_empty() {
            let deepest = inside
                .iter()
                .fold((0, 0.0, false), |a, b| if b.1 > a.1 { *b } else { a });
            println!(
                "{} nodes of the body inside {} (deepest: node {} by {:.3e} m, on a face plane: {})",
                inside.len(),
                other.name,
                deepest.0,
                deepest.1,
                deepest.2
            );
        }
    }

    // Boundary faces of the body and the normals at each of their nodes.
    let mut count: HashMap<[u32; 3], u32> = HashMap::new();
    for e in body.elements.clone() {
        for f in TET_FACES {
            *count.entry(face_key(f.map(|i| m.tets[e][i]))).or_insert(0) += 1;
        }
    }
    let mut normals: HashMap<u32, Vec<Vector3<f64>>> = HashMap::new();
    for (k, c) in &count {
        if *c == 1 {
            let [a, b, c] = k.map(|n| x[n as usize]);
            let n = (b - a).cross(&(c - a)).normalize();
            for v in k {
                normals.entry(*v).or_default().push(n);
            }
        }
    }
    let place = |n: u32| match normals.get(&n) {
        None => "inside".to_string(),
        Some(list) => format!("{} plane(s)", distinct_planes(list)),
    };
    let mut rows: Vec<(f64, usize)> = body
        .elements
        .clone()
        .map(|e| (distortion(&m.tets[e].map(|n| x[n as usize])), e))
        .collect();
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (d, e) in rows.iter().take(worst_n) {
        let c = m.tets[*e].map(|n| x[n as usize]);
        let centroid = 0.25e3 * (c[0] + c[1] + c[2] + c[3]);
        let (short, long) = impact_solver::mesh::edge_extremes(&c);
        println!(
            "element {e}: distortion {d:.1}, chi {:.1}, eta {:.3}, volume {:.2e} m^3, centroid \
             ({:.3}, {:.3}, {:.3}) mm, edges {:.3}-{:.3} mm, nodes: {}",
            collapse_ratio(&c),
            mean_ratio(&c),
            impact_solver::kinematics::signed_volume(&c),
            centroid.x,
            centroid.y,
            centroid.z,
            short * 1e3,
            long * 1e3,
            m.tets[*e].map(place).join(", ")
        );
        // The kinematics the material sees: the volume ratio J, the principal stretches and
        // the Green-Lagrange volumetric strain e_V = tr E / 3 (MICROPLANE.md) the volumetric
        // law is driven by.
        let f = p.model.deformation_gradient(*e, &run.state.u);
        let c_right = f.transpose() * f;
        let mut stretches: Vec<f64> = c_right
            .symmetric_eigenvalues()
            .iter()
            .map(|l| l.max(0.0).sqrt())
            .collect();
        stretches.sort_by(f64::total_cmp);
        let e_v = (c_right.trace() - 3.0) / 6.0;
        println!(
            "    J {:.4}, stretches {:.3} {:.3} {:.3}, e_V (Green-Lagrange) {:+.4}, e_V of J \
             ((J^(2/3) - 1) / 2) {:+.4}",
            f.determinant(),
            stretches[0],
            stretches[1],
            stretches[2],
            e_v,
            0.5 * (f.determinant().cbrt().powi(2) - 1.0)
        );
    }
}
