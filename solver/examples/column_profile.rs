//! Diagnostic for the drop tests (issue 17): the stress state of a vertical column of a beam,
//! layer by layer, over the first part of a run. For each field frame it prints, per layer of
//! one cell height from the bottom, the mean `sigma_xx` and `sigma_yy` (MPa) of the column's
//! elements and their largest crack indicator `eps_1 / eps_r`, as `sxx/syy/ci`.
//!
//! ```text
//! cargo run --release -p impact-solver --example column_profile -- \
//!     cases/beam/drop-8ms.yaml 0.34e-3 1.0e-5 [x = 1.5] [body = beam]
//! ```
//! The arguments: a scene file or a case file's `scene`, the end time and the frame interval (s),
//! the column's abscissa (m; the column holds the elements whose centroid lies within half a
//! cell of it) and the body. The scene's own end time and intervals are replaced; nothing is
//! written to disk. The 8 m/s drop test shows the splitting state of the mid-span column
//! (`sigma_xx` +5 to +10 MPa beside `sigma_yy` -20 to -45 MPa 0.15-0.3 m above the bottom,
//! 0.18-0.25 ms) that docs/validation.md quotes.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use impact_solver::dynamics::{ExplicitSolver, OutputSettings};
use impact_solver::mesh::ops::centroids;
use impact_solver::output::observer::RunObserver;
use impact_solver::output::vtu::{FieldData, FieldFrame};
use impact_solver::remesh::element_volumes;
use impact_solver::scene::{build_problem, Analysis, ExplicitAnalysis, Scene};

/// One layer's sums over a frame.
#[derive(Clone, Copy)]
struct Layer {
    sigma_xx: f64,
    sigma_yy: f64,
    elements: f64,
    crack: f64,
}

/// Prints the column's layers at every field frame.
struct ColumnProfile {
    /// Elements of the column and their layer (0 at the bottom).
    column: Vec<(usize, usize)>,
    layers: usize,
}

impl RunObserver for ColumnProfile {
    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> impact_solver::error::Result<Option<PathBuf>> {
        let (Some(FieldData::SymmetricTensor(sigma)), Some(FieldData::Scalar(crack))) = (
            frame.cell_field("cauchy_stress"),
            frame.cell_field("crack_indicator"),
        ) else {
            return Ok(None);
        };
        let empty = Layer {
            sigma_xx: 0.0,
            sigma_yy: 0.0,
            elements: 0.0,
            crack: f64::NEG_INFINITY,
        };
        let mut sum = vec![empty; self.layers];
        for &(e, layer) in &self.column {
            let s = &mut sum[layer];
            s.sigma_xx += sigma[e][0];
            s.sigma_yy += sigma[e][1];
            s.elements += 1.0;
            s.crack = s.crack.max(crack[e]);
        }
        let row: Vec<String> = sum
            .iter()
            .map(|s| {
                let n = s.elements.max(1.0);
                let (sxx, syy) = (s.sigma_xx / n / 1e6, s.sigma_yy / n / 1e6);
                format!("{sxx:5.1}/{syy:5.1}/{:.2}", s.crack)
            })
            .collect();
        println!("{:.3} ms  {}", frame.time * 1e3, row.join(" "));
        Ok(None)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 4 {
        eprintln!(
            "usage: column_profile <scene or case.yaml> <end time s> <frame interval s> [x] [body]"
        );
        std::process::exit(2);
    }
    let scene = Scene::from_yaml_file_entry(Path::new(&args[1]), "scene").unwrap();
    let end: f64 = args[2].parse().unwrap();
    let every: f64 = args[3].parse().unwrap();
    let x0: f64 = args.get(4).map_or(1.5, |s| s.parse().unwrap());
    let body = args.get(5).map_or("beam", String::as_str);
    let problem = build_problem(&scene).unwrap();
    let Analysis::Explicit(ExplicitAnalysis { mut settings, .. }) = scene.analysis.clone() else {
        panic!("an explicit analysis is needed")
    };
    settings.end_time = end;
    settings.field_interval = Some(every);
    settings.snapshot_interval = None;

    let model = &problem.model;
    let b = model.body_index(body).unwrap();
    let elements: Vec<usize> = model.bodies[b].elements.clone().collect();
    // Centroids and volumes of the whole model, as the remeshing's transfer computes them.
    let centroid = centroids(&model.reference, &model.tets);
    let volumes = element_volumes(&model.reference, &model.tets);
    let volume: f64 = elements.iter().map(|&e| volumes[e]).sum();
    let cell = (6.0 * volume / elements.len() as f64).cbrt();
    let (bottom, top) = elements
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &e| {
            model.tets[e].iter().fold((lo, hi), |(lo, hi), &n| {
                let y = model.reference[n as usize].y;
                (lo.min(y), hi.max(y))
            })
        });
    let layers = (((top - bottom) / cell).round() as usize).max(1);
    let layer_height = (top - bottom) / layers as f64;
    let column: Vec<(usize, usize)> = elements
        .iter()
        .filter_map(|&e| {
            let c = centroid[e];
            ((c.x - x0).abs() < 0.5 * cell).then(|| {
                let layer = ((c.y - bottom) / layer_height).floor().max(0.0) as usize;
                (e, layer.min(layers - 1))
            })
        })
        .collect();
    println!(
        "column x = {x0} m of `{body}`: {} elements in {layers} layers of {:.1} mm; per layer \
         from the bottom: mean sigma_xx / mean sigma_yy (MPa) / largest eps_1/eps_r",
        column.len(),
        layer_height * 1e3
    );
    let mut profile = ColumnProfile { column, layers };
    let mut solver = ExplicitSolver::new(&problem, settings, OutputSettings::default()).unwrap();
    solver.run_with(&mut [&mut profile]).unwrap();
}
