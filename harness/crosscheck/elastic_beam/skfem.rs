//! The scikit-fem side: the request to `skfem_beam.py` built from the scene, and the reference
//! values read from its answer.

use impact_solver::scene::{Component, MaterialSpec, MeshSource, MotionSpec, Scene, Selector};
use serde_json::{json, Value};

use super::{values_of, BeamValues, ElasticBeamSpec};
use crate::crosscheck::error::CrosscheckError;

/// A box selector's corners, or an error naming the condition.
fn box_of<'s>(
    scene: &'s Scene,
    name: &str,
) -> Result<([f64; 3], [f64; 3], &'s MotionSpec), CrosscheckError> {
    let c = scene
        .boundary_conditions
        .iter()
        .find(|c| c.name.as_deref() == Some(name))
        .ok_or_else(|| CrosscheckError::NoCondition { name: name.into() })?;
    match &c.nodes {
        Selector::Box { min, max } => Ok((*min, *max, &c.motion)),
        other => Err(CrosscheckError::NotABoxSelector {
            name: name.into(),
            selector: format!("{other:?}"),
        }),
    }
}

/// A condition whose motion the reference script cannot reproduce.
fn motion_error(role: &'static str, name: &str, requirement: &'static str) -> CrosscheckError {
    CrosscheckError::Motion {
        role,
        name: name.into(),
        requirement,
    }
}

fn component_index(c: &Component) -> usize {
    *c as usize
}

/// The request to `skfem_beam.py`: the scene's beam, material, supports, plate and pins.
pub fn request(spec: &ElasticBeamSpec, scene: &Scene) -> Result<Value, CrosscheckError> {
    let body = scene
        .bodies
        .iter()
        .find(|b| b.name == spec.body)
        .ok_or_else(|| CrosscheckError::NoSceneBody {
            body: spec.body.clone(),
        })?;
    let MeshSource::Box(mesh) = &body.mesh else {
        return Err(CrosscheckError::BodyNotBox {
            body: spec.body.clone(),
        });
    };
    if mesh.origin != [0.0; 3] {
        return Err(CrosscheckError::NotAtOrigin {
            body: spec.body.clone(),
            origin: mesh.origin,
        });
    }
    let MaterialSpec::LinearElastic(c) = &body.material else {
        return Err(CrosscheckError::NotElastic {
            body: spec.body.clone(),
        });
    };
    let [_, depth, width] = mesh.size;
    let strip = |name: &str, y: f64| -> Result<[f64; 2], CrosscheckError> {
        let (min, max, _) = box_of(scene, name)?;
        let full_width = min[2] <= 0.0 && max[2] >= width;
        if min[1] != y || max[1] != y || !full_width {
            return Err(CrosscheckError::NotAStrip {
                name: name.into(),
                y,
                min,
                max,
            });
        }
        Ok([min[0], max[0]])
    };
    let supports = spec
        .supports
        .iter()
        .map(|s| {
            let (_, _, motion) = box_of(scene, s)?;
            if !matches!(motion, MotionSpec::Fixed(c) if c == &[Component::Y]) {
                return Err(motion_error("support", s, "be `fixed: [y]`"));
            }
            Ok(json!({"name": s, "x": strip(s, 0.0)?}))
        })
        .collect::<Result<Vec<_>, CrosscheckError>>()?;
    let (_, _, motion) = box_of(scene, &spec.plate)?;
    let MotionSpec::Displacement { components, value } = motion else {
        return Err(motion_error(
            "plate",
            &spec.plate,
            "prescribe a displacement",
        ));
    };
    if components != &[Component::Y] {
        return Err(motion_error("plate", &spec.plate, "move along y only"));
    }
    // The static solver evaluates the function at load factor 1; the explicit run ends holding
    // the same value.
    let displacement = value.eval(1.0);
    let pins = spec
        .pins
        .iter()
        .map(|p| {
            let (min, max, motion) = box_of(scene, p)?;
            let MotionSpec::Fixed(components) = motion else {
                return Err(motion_error("pin", p, "be `fixed`"));
            };
            if min != max {
                return Err(motion_error("pin", p, "select one point (min = max)"));
            }
            Ok(json!({"point": min, "components": components.iter().map(component_index).collect::<Vec<_>>()}))
        })
        .collect::<Result<Vec<_>, CrosscheckError>>()?;
    Ok(json!({
        "size": mesh.size,
        "young": c.youngs_modulus,
        "poisson": c.poisson_ratio,
        "supports": supports,
        "plate": {"name": spec.plate, "x": strip(&spec.plate, depth)?, "displacement": displacement},
        "pins": pins,
        "deflection_points": spec.deflection_points,
        "levels": spec.reference_levels,
    }))
}

/// The reference values from scikit-fem's answer: its converged values, and one row per level.
pub fn reference_values(
    spec: &ElasticBeamSpec,
    answer: &Value,
    delta: f64,
) -> Result<(BeamValues, Vec<BeamValues>, String), CrosscheckError> {
    let number = |v: &Value, what: &str| {
        v.as_f64()
            .ok_or_else(|| CrosscheckError::AnswerNumber { at: what.into() })
    };
    let values = |v: &Value,
                  label: String,
                  elements: usize,
                  seconds: f64|
     -> Result<BeamValues, CrosscheckError> {
        let deflections = spec
            .deflection_points
            .keys()
            .map(|k| {
                Ok((
                    k.clone(),
                    number(&v["deflection"][k], &format!("deflection.{k}"))?,
                ))
            })
            .collect::<Result<_, CrosscheckError>>()?;
        let reactions = spec
            .supports
            .iter()
            .map(|s| Ok((s.clone(), number(&v[s], s)?)))
            .collect::<Result<_, CrosscheckError>>()?;
        Ok(values_of(
            label,
            delta,
            number(&v["plate_force"], "plate_force")?,
            reactions,
            deflections,
            elements,
            seconds,
        ))
    };
    let converged = &answer["converged"];
    let method = converged["method"].as_str().unwrap_or("").to_string();
    let levels = answer["levels"]
        .as_array()
        .ok_or(CrosscheckError::AnswerField {
            script: "scikit-fem",
            field: "levels",
        })?
        .iter()
        .map(|l| {
            let cells: Vec<u64> = l["cells"]
                .as_array()
                .map(|c| c.iter().filter_map(Value::as_u64).collect())
                .unwrap_or_default();
            let label = format!(
                "scikit-fem, quadratic tets {}",
                cells
                    .iter()
                    .map(u64::to_string)
                    .collect::<Vec<_>>()
                    .join("x")
            );
            values(
                l,
                label,
                l["elements"].as_u64().unwrap_or(0) as usize,
                l["seconds"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect::<Result<Vec<_>, CrosscheckError>>()?;
    let total: f64 = levels.iter().map(|l| l.seconds).sum();
    let elements = levels.last().map_or(0, |l| l.elements);
    Ok((
        values(
            converged,
            "scikit-fem, converged (extrapolated)".into(),
            elements,
            total,
        )?,
        levels,
        method,
    ))
}
