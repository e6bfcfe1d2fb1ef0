//! The checks a scene passes before anything is built from it: every number finite and in its
//! range, every name unique among its kind and fit to be a file stem, every mesh small enough to
//! allocate. A well-typed number out of range (`safety: 100`, `gravity: [0, 0, .nan]`) would
//! otherwise run and give a wrong answer, or fail far from its cause; here it stops with the key
//! that holds it and the fix.

use super::{
    Analysis, BoundaryCondition, ContactSpec, InitialVelocity, LoadSpec, MeshSource, MotionSpec,
    ProbeSpec, Scene, Selector,
};
use crate::error::{Result, SolverError};

/// The largest mesh a scene may generate (tetrahedra). A tetrahedron with its nodes, lumped
/// masses, forces and a microplane history takes about 2 kB, so this many are some 100 GB:
/// beyond any machine the solver runs on, and far beyond an explicit run's patience. A box
/// with more cells is refused before it is allocated.
pub const MAX_ELEMENTS: usize = 50_000_000;

fn invalid(entity: impl Into<String>, message: impl Into<String>) -> SolverError {
    SolverError::InvalidScene {
        entity: entity.into(),
        message: message.into(),
    }
}

/// `Ok` when every value is finite; else names the first that is not.
fn finite(entity: &str, values: &[f64]) -> Result<()> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(invalid(entity, format!("must be finite, got {v}"))),
        None => Ok(()),
    }
}

/// Why `name` cannot be the stem of a run's output files (`<stem>_history.csv` in `--out`),
/// if it cannot: it must stay inside the output folder and be visible there.
pub fn output_stem_problem(name: &str) -> Option<String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.' | '+');
    if name.is_empty() {
        Some("is empty; a scene's name is the stem of its output files".into())
    } else if name.starts_with('.') {
        Some(format!(
            "`{name}` starts with a dot, which makes hidden files or leaves the output folder"
        ))
    } else {
        name.chars().find(|&c| !allowed(c)).map(|c| {
            format!(
                "`{name}` has the character {c:?}; a scene's name is the stem of its output \
                 files, so it may hold letters, digits and `-_.+` only (write `beam-drop-2ms`, \
                 not `beam/drop-2ms`)"
            )
        })
    }
}

impl Scene {
    /// Checks the scene's names and numbers (see the module documentation); `build_problem`
    /// calls it, and the readers call it so that the error names the file.
    pub fn validate(&self) -> Result<()> {
        if let Some(problem) = output_stem_problem(&self.name) {
            return Err(invalid("name", problem));
        }
        for body in &self.bodies {
            let entity = |key: &str| format!("body `{}` {key}", body.name);
            if let MeshSource::Box(b) = &body.mesh {
                finite(&entity("mesh.box.origin"), &b.origin)?;
                finite(&entity("mesh.box.size"), &b.size)?;
                let cells = b
                    .divisions
                    .iter()
                    .try_fold(1usize, |n, &d| n.checked_mul(d));
                match cells.and_then(|c| c.checked_mul(6)) {
                    Some(tets) if tets <= MAX_ELEMENTS => {}
                    tets => {
                        return Err(invalid(
                            entity("mesh.box.divisions"),
                            format!(
                                "{:?} make {} tetrahedra, more than the {MAX_ELEMENTS} the \
                                 solver allocates; use fewer divisions",
                                b.divisions,
                                tets.map_or("more than 2^64".into(), |t| t.to_string())
                            ),
                        ))
                    }
                }
            }
            if let Some(v) = &body.initial_velocity {
                check_initial_velocity(&entity("initial_velocity"), v)?;
            }
            if let Some(t) = &body.transform {
                finite(
                    &entity("transform.rotation_axis"),
                    &t.rotation_axis.unwrap_or([0.0; 3]),
                )?;
                finite(&entity("transform.rotation_angle"), &[t.rotation_angle])?;
                finite(&entity("transform.translation"), &t.translation)?;
            }
            for region in &body.regions {
                let key = format!("region `{}` centroid_box", region.name);
                let b = &region.centroid_box;
                finite(&entity(&key), &[b.min, b.max].concat())?;
                if (0..3).any(|a| b.min[a] > b.max[a]) {
                    return Err(invalid(entity(&key), "min must not exceed max on any axis"));
                }
            }
        }
        if let Some(g) = &self.gravity {
            finite("gravity", g)?;
        }
        check_conditions(&self.boundary_conditions)?;
        check_loads(&self.loads)?;
        check_probes(&self.probes)?;
        check_contact(&self.contact)?;
        self.analysis.validate()
    }
}

fn check_initial_velocity(entity: &str, v: &InitialVelocity) -> Result<()> {
    finite(&format!("{entity}.translation"), &v.translation)?;
    finite(&format!("{entity}.angular_velocity"), &v.angular_velocity)?;
    finite(&format!("{entity}.center"), &v.center)?;
    finite(
        &format!("{entity}.gradient"),
        &v.gradient.map_or(Vec::new(), |g| g.concat()),
    )
}

/// The first name that appears twice among `names`, if one does.
fn repeated<'a>(names: impl Iterator<Item = String> + 'a) -> Option<String> {
    let mut seen = std::collections::BTreeSet::new();
    names.into_iter().find(|n| !seen.insert(n.clone()))
}

fn check_selector(entity: &str, selector: &Selector) -> Result<()> {
    let key = format!("{entity} nodes");
    match selector {
        Selector::Box { min, max } => finite(&key, &[*min, *max].concat()),
        Selector::Plane {
            point,
            normal,
            tolerance,
        } => {
            finite(&key, &[*point, *normal].concat())?;
            if normal.iter().all(|&c| c == 0.0) {
                return Err(invalid(key, "the plane's normal must not be zero"));
            }
            match tolerance {
                Some(t) if !(*t > 0.0 && t.is_finite()) => Err(invalid(
                    key,
                    format!("the plane's tolerance must be positive and finite (m), got {t}"),
                )),
                _ => Ok(()),
            }
        }
        _ => Ok(()),
    }
}

fn check_conditions(conditions: &[BoundaryCondition]) -> Result<()> {
    let name = |i: usize, bc: &BoundaryCondition| bc.name.clone().unwrap_or(format!("bc{i}"));
    if let Some(n) = repeated(conditions.iter().enumerate().map(|(i, bc)| name(i, bc))) {
        return Err(invalid(
            format!("boundary condition `{n}`"),
            "two boundary conditions have this name (it labels their reaction columns); give \
             each its own",
        ));
    }
    for (i, bc) in conditions.iter().enumerate() {
        let entity = format!("boundary condition `{}`", name(i, bc));
        check_selector(&entity, &bc.nodes)?;
        let motion = format!("{entity} motion");
        let function = |f: &crate::model::TimeFunction| {
            f.validate().map_err(|m| invalid(&motion, m.to_string()))
        };
        match &bc.motion {
            MotionSpec::Fixed(_) | MotionSpec::Symmetry(_) => {}
            MotionSpec::Velocity { value, .. } | MotionSpec::Displacement { value, .. } => {
                function(value)?
            }
            MotionSpec::AffineVelocity {
                translation,
                gradient,
                center,
            } => finite(
                &motion,
                &[&translation[..], &gradient.concat(), center].concat(),
            )?,
            MotionSpec::AffineDisplacement {
                translation,
                gradient,
                center,
                scale,
            } => {
                finite(
                    &motion,
                    &[&translation[..], &gradient.concat(), center].concat(),
                )?;
                function(scale)?
            }
            MotionSpec::Rotation {
                axis,
                center,
                angle,
            } => {
                finite(&motion, &[*axis, *center].concat())?;
                function(angle)?
            }
        }
    }
    Ok(())
}

fn check_loads(loads: &[LoadSpec]) -> Result<()> {
    let name = |i: usize, l: &LoadSpec| l.name.clone().unwrap_or(format!("load{i}"));
    if let Some(n) = repeated(loads.iter().enumerate().map(|(i, l)| name(i, l))) {
        return Err(invalid(
            format!("load `{n}`"),
            "two loads have this name; give each its own",
        ));
    }
    for (i, load) in loads.iter().enumerate() {
        let entity = format!("load `{}`", name(i, load));
        check_selector(&entity, &load.nodes)?;
        finite(&format!("{entity} force_per_node"), &load.force_per_node)?;
        load.function
            .validate()
            .map_err(|m| invalid(format!("{entity} function"), m.to_string()))?;
    }
    Ok(())
}

fn check_probes(probes: &[ProbeSpec]) -> Result<()> {
    if let Some(n) = repeated(probes.iter().map(|p| p.name.clone())) {
        return Err(invalid(
            format!("probe `{n}`"),
            "two probes have this name, which would give two history columns of one name; give \
             each its own",
        ));
    }
    for p in probes {
        check_selector(&format!("probe `{}`", p.name), &p.nodes)?;
    }
    Ok(())
}

fn check_contact(pairs: &[ContactSpec]) -> Result<()> {
    if let Some(n) = repeated(pairs.iter().map(|p| p.name.clone())) {
        return Err(invalid(
            format!("contact pair `{n}`"),
            "two contact pairs have this name; give each its own (a pair listed twice would be \
             resolved twice per step)",
        ));
    }
    Ok(())
}

impl Analysis {
    /// Checks the settings of the analysis, naming each key under `analysis`.
    pub fn validate(&self) -> Result<()> {
        match self {
            Analysis::Explicit(s) => s.validate("analysis.explicit"),
            Analysis::Static(s) => s.validate("analysis.static"),
            Analysis::Release { preload, explicit } => {
                preload.validate("analysis.release.preload")?;
                explicit.validate("analysis.release.explicit")
            }
        }
    }
}
