//! Our side: the same scene solved by our implicit static solver and by our explicit solver on
//! a given mesh.

use std::time::Instant;

use impact_solver::problem::Problem;
use impact_solver::scene::{build_problem, Analysis, MeshSource, Scene};
use impact_solver::statics::{solve_static, LinearSolver, StaticSettings};

use super::{values_of, BeamValues, ElasticBeamSpec};
use crate::crosscheck::error::CrosscheckError;

/// The node of body `body` at `point`, or an error (deflections are read at nodes).
fn node_at(problem: &Problem, body: &str, point: &[f64; 3]) -> Result<usize, CrosscheckError> {
    let b = problem
        .model
        .bodies
        .iter()
        .find(|b| b.name == body)
        .ok_or_else(|| CrosscheckError::NoBody { body: body.into() })?;
    b.nodes
        .clone()
        .find(|&n| {
            let x = problem.model.reference[n];
            (0..3).all(|k| (x[k] - point[k]).abs() <= 1e-9)
        })
        .ok_or_else(|| CrosscheckError::NoNodeAt {
            body: body.into(),
            point: *point,
        })
}

fn constraint_index(problem: &Problem, name: &str) -> Result<usize, CrosscheckError> {
    problem
        .constraints
        .iter()
        .position(|c| c.name == name)
        .ok_or_else(|| CrosscheckError::NoConstraint { name: name.into() })
}

/// The scene with the beam's box divisions replaced.
fn at_level(scene: &Scene, body: &str, cells: [usize; 3]) -> Scene {
    let mut s = scene.clone();
    for b in s.bodies.iter_mut().filter(|b| b.name == body) {
        if let MeshSource::Box(m) = &mut b.mesh {
            m.divisions = cells;
        }
    }
    s
}

/// Our implicit static solution on `cells`, by conjugate gradients: the beam is linear elastic,
/// and on its 25 mm cells LU's fill-in took 5.8 GB and a minute on one core for the same
/// solution (docs/performance.md, "Static solves: conjugate gradients against LU").
pub fn implicit(
    spec: &ElasticBeamSpec,
    scene: &Scene,
    cells: [usize; 3],
    delta: f64,
) -> Result<BeamValues, CrosscheckError> {
    let started = Instant::now();
    let mut s = at_level(scene, &spec.body, cells);
    let settings = StaticSettings {
        linear_solver: LinearSolver::conjugate_gradient(),
        ..StaticSettings::default()
    };
    s.analysis = Analysis::Static(settings.clone());
    let problem = build_problem(&s)?;
    let solution = solve_static(&problem, &settings)?;
    let y = |name: &str| -> Result<f64, CrosscheckError> {
        Ok(solution.constraint_reaction(&problem, constraint_index(&problem, name)?)[1])
    };
    let reactions = spec
        .supports
        .iter()
        .map(|n| Ok((n.clone(), y(n)?)))
        .collect::<Result<_, CrosscheckError>>()?;
    let deflections = spec
        .deflection_points
        .iter()
        .map(|(k, p)| Ok((k.clone(), solution.u[node_at(&problem, &spec.body, p)?][1])))
        .collect::<Result<_, CrosscheckError>>()?;
    Ok(values_of(
        format!(
            "ours, implicit static, linear tets {}x{}x{}",
            cells[0], cells[1], cells[2]
        ),
        delta,
        y(&spec.plate)?,
        reactions,
        deflections,
        problem.model.element_count(),
        started.elapsed().as_secs_f64(),
    ))
}

/// Our explicit solution on `cells`: the scene's own analysis, read at its end.
pub fn explicit(
    spec: &ElasticBeamSpec,
    scene: &Scene,
    cells: [usize; 3],
    delta: f64,
    time_limit_s: f64,
) -> Result<(BeamValues, Vec<String>), CrosscheckError> {
    let started = Instant::now();
    let scene = &at_level(scene, &spec.body, cells);
    let mut problem = build_problem(scene)?;
    let options = impact_solver::analysis::ExecuteOptions {
        out: None,
        stem: "explicit",
        final_state: true,
        fields: false,
        time_limit_s: Some(time_limit_s),
        stop: None,
        ranks: None,
        log: &impact_solver::analysis::log_to_stderr,
    };
    let run =
        impact_solver::analysis::execute(&mut problem, &scene.analysis, &options, &mut |_| {})?;
    let history = run.history.as_ref().ok_or(CrosscheckError::NoHistory)?;
    let last = |column: &str| -> Result<f64, CrosscheckError> {
        history
            .column(column)
            .and_then(|c| c.last().copied())
            .ok_or_else(|| CrosscheckError::NoColumn {
                column: column.into(),
            })
    };
    let reactions = spec
        .supports
        .iter()
        .map(|n| Ok((n.clone(), last(&format!("{n}_reaction_y"))?)))
        .collect::<Result<_, CrosscheckError>>()?;
    let deflections = spec
        .deflection_points
        .iter()
        .map(|(k, p)| Ok((k.clone(), run.u[node_at(&problem, &spec.body, p)?][1])))
        .collect::<Result<_, CrosscheckError>>()?;
    // How far from rest the end is: kinetic energy over the work done.
    let notes = match (history.column("kinetic"), history.column("external_work")) {
        (Some(k), Some(w)) => vec![format!(
            "explicit run on {cells:?}: kinetic energy at the end {:.3e} J, {:.2e} of the external work",
            k.last().unwrap_or(&f64::NAN),
            k.last().unwrap_or(&f64::NAN) / w.last().unwrap_or(&f64::NAN).abs()
        )],
        _ => vec![],
    };
    Ok((
        values_of(
            format!(
                "ours, explicit quasi-static (ramp, damped hold), linear tets {}x{}x{}",
                cells[0], cells[1], cells[2]
            ),
            delta,
            last(&format!("{}_reaction_y", spec.plate))?,
            reactions,
            deflections,
            problem.model.element_count(),
            started.elapsed().as_secs_f64(),
        ),
        notes,
    ))
}
