//! From a scene description to a [`Problem`]: meshes made or read, selectors resolved.

use nalgebra::{Matrix3, Unit, Vector3};

use super::{Analysis, BodySpec, Component, MeshSource, MotionSpec, Numbering, Scene, Selector};
use crate::error::{Result, SolverError};
use crate::material::MaterialModel;
use crate::mesh::{
    boundary_faces, boundary_faces_of, boundary_nodes, bounding_box, box_mesh, gmsh::read_msh,
    perturb_interior, Mesh,
};
use crate::model::{Constraint, Model, Motion, NodalLoad, Probe, Region};
use crate::problem::Problem;

fn invalid(entity: impl Into<String>, message: impl Into<String>) -> SolverError {
    SolverError::InvalidScene {
        entity: entity.into(),
        message: message.into(),
    }
}

/// Nodes of a symmetry condition that do not lie on one plane.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "a symmetry plane needs nodes on one plane normal to axis {axis}; they span {mean:.9e} and \
     {off:.9e} m. Fix: pick the nodes of the cut face only"
)]
pub struct SymmetryPlaneError {
    /// The plane's normal axis.
    pub axis: usize,
    /// The nodes' mean coordinate (m).
    pub mean: f64,
    /// A node's coordinate off the plane (m).
    pub off: f64,
}

/// The coordinate `axis` shared by `nodes` (their mean), or why they do not lie on one plane
/// normal to it (to 1e-9 of the model's size).
fn symmetry_plane(
    reference: &[Vector3<f64>],
    nodes: &[u32],
    axis: usize,
) -> std::result::Result<f64, SymmetryPlaneError> {
    let size = reference
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.amax()))
        .max(f64::MIN_POSITIVE);
    let values: Vec<f64> = nodes.iter().map(|&n| reference[n as usize][axis]).collect();
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    match values.iter().find(|v| (*v - mean).abs() > 1e-9 * size) {
        Some(v) => Err(SymmetryPlaneError {
            axis,
            mean,
            off: *v,
        }),
        None => Ok(mean),
    }
}

fn dofs(components: &[Component]) -> [bool; 3] {
    let mut d = [false; 3];
    for c in components {
        d[*c as usize] = true;
    }
    d
}

/// The index of the scene body named `name`, which is also its index in the model (the regions
/// come after the scene's bodies). A region's name is refused with the advice to name its
/// body: a region owns no nodes, it shares its parent's, so a condition, load, probe or contact
/// pair picks them from the parent with a selector.
fn scene_body(scene: &Scene, entity: &str, name: &str) -> Result<usize> {
    if let Some(b) = scene.bodies.iter().position(|b| b.name == name) {
        return Ok(b);
    }
    match scene
        .bodies
        .iter()
        .find(|b| b.regions.iter().any(|r| r.name == name))
    {
        Some(parent) => Err(invalid(
            entity,
            format!(
                "`{name}` is a material region of body `{}`, which owns its nodes: write \
                 `body: {}` and pick the region's nodes with a selector (a box, a plane)",
                parent.name, parent.name
            ),
        )),
        None => Err(invalid(
            entity,
            format!(
                "no body named `{name}`; the bodies are {:?}",
                scene.bodies.iter().map(|b| &b.name).collect::<Vec<_>>()
            ),
        )),
    }
}

/// Builds the model and the conditions of `scene`.
pub fn build_problem(scene: &Scene) -> Result<Problem> {
    build_problem_on_rank(scene, None)
}

/// As [`build_problem`], for rank `rank` of `size` of a distributed run (`Some((rank, size))`):
/// where the scene's analysis can run on several ranks (explicit, without remeshing), the model
/// holds no element's shape-function gradients, volumes or altitudes
/// ([`Model::with_regions_keeping`] of an empty range): the rank's solver computes those of its
/// own elements once it has freed what it does not need
/// ([`crate::dynamics::ExplicitSolver::new_rank_keeping_own_elements`], or before a solver that
/// shares the problem, [`crate::dynamics::keep_rank_element_data`]); until then any element's
/// are computed when read, with the same bits. The problem is otherwise the same.
pub fn build_problem_on_rank(scene: &Scene, rank: Option<(usize, usize)>) -> Result<Problem> {
    scene.validate()?;
    let (bodies, regions, meshes) = scene_bodies(scene)?;
    let distributable = matches!(
        &scene.analysis,
        Analysis::Explicit(a) if a.remeshing.is_none()
    );
    // One process keeps the volumes and altitudes the model computes for its masses.
    let ranked = rank.filter(|&(_, size)| size > 1 && distributable);
    let mut model = match ranked {
        Some(_) => Model::with_regions_keeping(bodies, regions, &|_| 0..0)?,
        None => Model::with_regions(bodies, regions)?,
    };
    scene
        .crack_indicator
        .validate()
        .map_err(|m| invalid("crack_indicator", m.to_string()))?;
    model.crack_indicator = scene.crack_indicator;
    let mut problem = Problem::new(model);
    set_initial_velocities(scene, &mut problem);
    let picker = NodePicker {
        scene,
        model: &problem.model,
        meshes: &meshes,
    };
    let constraints = constraints(scene, &picker)?;
    let loads = loads(scene, &picker)?;
    let probes = probes(scene, &picker)?;
    let contact = contact_pairs(scene)?;
    problem.contact = contact;
    problem.constraints = constraints;
    problem.loads = loads;
    problem.probes = probes;
    problem.gravity = scene.gravity.map(Vector3::from);
    Ok(problem)
}

/// The model's bodies and material regions, and the whole mesh (regions included) of each
/// scene body that has regions, which the selectors see; a body without regions is the model's
/// body, node for node and element for element, so its mesh is not copied (a second copy of the
/// mesh is the largest thing a rank of a distributed run holds while it builds).
#[allow(clippy::type_complexity)]
fn scene_bodies(
    scene: &Scene,
) -> Result<(
    Vec<(String, Mesh, MaterialModel)>,
    Vec<Region>,
    Vec<Option<Mesh>>,
)> {
    let mut bodies = Vec::new();
    let mut regions = Vec::new();
    let mut full_meshes = Vec::new();
    for (i, body) in scene.bodies.iter().enumerate() {
        if scene.bodies[..i].iter().any(|b| b.name == body.name) {
            return Err(invalid(
                format!("body `{}`", body.name),
                "two bodies have this name; names must be unique",
            ));
        }
        let mut mesh = body_mesh(body)?;
        // Selectors (the boundary among them) see the whole mesh, regions included.
        full_meshes.push((!body.regions.is_empty()).then(|| mesh.clone()));
        split_regions(scene, i, &mut mesh, &mut regions)?;
        bodies.push((body.name.clone(), mesh, body.material.model(&body.name)?));
    }
    Ok((bodies, regions, full_meshes))
}

/// The mesh of `body`: made (a box, perturbed if asked) or read, renumbered and placed.
fn body_mesh(body: &BodySpec) -> Result<Mesh> {
    let mesh = match &body.mesh {
        MeshSource::Box(b) => {
            let (spec, perturb) = (&b.spec(), &b.perturb);
            if spec.divisions.contains(&0) || spec.size.iter().any(|s| !(*s > 0.0)) {
                return Err(invalid(
                    format!("body `{}` mesh.box", body.name),
                    "size must be positive and divisions at least 1 per axis",
                ));
            }
            spec.check().map_err(|e| match e {
                SolverError::InvalidScene { entity, message } => {
                    invalid(format!("body `{}` {entity}", body.name), message)
                }
                other => other,
            })?;
            let mut mesh = box_mesh(spec);
            if let Some(p) = perturb {
                if !(0.0..0.5).contains(&p.fraction) {
                    return Err(invalid(
                        format!("body `{}` mesh.box.perturb", body.name),
                        format!(
                            "fraction must lie in [0, 0.5) to keep elements valid, got {}",
                            p.fraction
                        ),
                    ));
                }
                perturb_interior(&mut mesh, spec, p.fraction, p.seed);
            }
            mesh
        }
        MeshSource::Gmsh(path) => read_msh(path)?,
    };
    let mut mesh = mesh;
    if body.numbering == Numbering::Spatial {
        mesh.renumber_spatially();
    }
    if let Some(t) = &body.transform {
        let rotation = match t.rotation_axis {
            Some(axis) => {
                let axis = Unit::try_new(Vector3::from(axis), 1e-300).ok_or_else(|| {
                    invalid(
                        format!("body `{}` transform", body.name),
                        "rotation axis must not be zero",
                    )
                })?;
                nalgebra::Rotation3::from_axis_angle(&axis, t.rotation_angle)
            }
            None => nalgebra::Rotation3::identity(),
        };
        let shift = Vector3::from(t.translation);
        for x in &mut mesh.nodes {
            *x = rotation * *x + shift;
        }
    }
    Ok(mesh)
}

/// Moves the elements of each of the scene body `i`'s material regions out of `mesh` into a
/// [`Region`] of its own.
fn split_regions(
    scene: &Scene,
    i: usize,
    mesh: &mut Mesh,
    regions: &mut Vec<Region>,
) -> Result<()> {
    let body = &scene.bodies[i];
    for spec in &body.regions {
        let entity = format!("body `{}` region `{}`", body.name, spec.name);
        if scene.bodies.iter().any(|b| b.name == spec.name)
            || regions.iter().any(|r: &Region| r.name == spec.name)
        {
            return Err(invalid(&entity, "a body or region already has this name"));
        }
        let (lo, hi) = mesh.bounding_box();
        let tol = 1e-9 * (hi - lo).norm();
        let (inside, outside): (Vec<[u32; 4]>, Vec<[u32; 4]>) = mesh.tets.iter().partition(|t| {
            let c = t
                .iter()
                .map(|&n| mesh.nodes[n as usize])
                .sum::<Vector3<f64>>()
                / 4.0;
            let b = &spec.centroid_box;
            (0..3).all(|a| c[a] >= b.min[a] - tol && c[a] <= b.max[a] + tol)
        });
        if inside.is_empty() {
            return Err(invalid(
                &entity,
                "centroid_box holds the centroid of no element; check it against the mesh",
            ));
        }
        mesh.tets = outside;
        regions.push(Region {
            name: spec.name.clone(),
            parent: i,
            tets: inside,
            material: spec.material.model(&spec.name)?,
        });
    }
    Ok(())
}

/// Each body's initial velocity: a translation, a rotation about a centre and a gradient.
fn set_initial_velocities(scene: &Scene, problem: &mut Problem) {
    for (b, body) in scene.bodies.iter().enumerate() {
        if let Some(iv) = &body.initial_velocity {
            let model = &problem.model;
            let (t, w, c) = (
                Vector3::from(iv.translation),
                Vector3::from(iv.angular_velocity),
                Vector3::from(iv.center),
            );
            let g = iv.gradient.map(|g| Matrix3::from_row_slice(&g.concat()));
            for n in model.bodies[b].nodes.clone() {
                let r = model.reference[n] - c;
                problem.initial_velocity[n] =
                    t + w.cross(&r) + g.map_or(Vector3::zeros(), |g| g * r);
            }
        }
    }
}

/// Resolves a selector to the global ids of the nodes it picks on a scene body.
struct NodePicker<'a> {
    scene: &'a Scene,
    model: &'a Model,
    /// The whole mesh (regions included) of each scene body that has regions; the others are
    /// read from the model.
    meshes: &'a [Option<Mesh>],
}

impl NodePicker<'_> {
    /// The nodes `selector` picks on body `body`, for `entity`; an error naming it when there
    /// is no such body or node set, a node id is out of range, or nothing is picked.
    fn pick(&self, entity: &str, body: &str, selector: &Selector) -> Result<Vec<u32>> {
        let (scene, model) = (self.scene, self.model);
        let b = scene_body(scene, entity, body)?;
        let range = model.bodies[b].nodes.clone();
        let offset = range.start as u32;
        let whole = self.meshes[b].as_ref();
        let nodes: Vec<u32> = match selector {
            // The model's node sets are the mesh's, offset to global ids (regions keep them).
            Selector::Group(name) => model.bodies[b]
                .node_sets
                .get(name)
                .ok_or_else(|| {
                    invalid(
                        entity,
                        format!(
                            "body `{body}` has no node set `{name}`; it has {:?}",
                            model.bodies[b].node_sets.keys().collect::<Vec<_>>()
                        ),
                    )
                })?
                .clone(),
            // Boundary nodes come sorted and unique, whatever the order of the elements.
            Selector::Boundary => match whole {
                Some(mesh) => boundary_nodes(&boundary_faces(mesh))
                    .iter()
                    .map(|n| n + offset)
                    .collect(),
                None => {
                    let elements = model.bodies[b].elements.clone();
                    boundary_nodes(&boundary_faces_of(&model.tets[elements]))
                }
            },
            Selector::Nodes(ids) => {
                if let Some(bad) = ids.iter().find(|&&n| n as usize >= range.len()) {
                    return Err(invalid(
                        entity,
                        format!(
                            "node {bad} is out of range: body `{body}` has {} nodes",
                            range.len()
                        ),
                    ));
                }
                ids.iter().map(|n| n + offset).collect()
            }
            geometric => {
                let (lo, hi) = bounding_box(&model.reference[range.clone()]);
                let scale = (hi - lo).norm();
                range
                    .clone()
                    .filter(|&n| geometric.contains(&model.reference[n], scale) == Some(true))
                    .map(|n| n as u32)
                    .collect()
            }
        };
        if nodes.is_empty() {
            return Err(invalid(entity, format!("the selector {selector:?} picks no node of body `{body}`; check its coordinates against the mesh")));
        }
        Ok(nodes)
    }
}

/// The scene's boundary conditions on the nodes they select.
fn constraints(scene: &Scene, picker: &NodePicker<'_>) -> Result<Vec<Constraint>> {
    let mut constraints = Vec::new();
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let name = bc.name.clone().unwrap_or_else(|| format!("bc{i}"));
        let entity = format!("boundary condition `{name}`");
        let nodes = picker.pick(&entity, &bc.body, &bc.nodes)?;
        let motion = motion(&bc.motion, &entity, &nodes, &picker.model.reference)?;
        if let MotionSpec::Velocity { value, .. } | MotionSpec::Displacement { value, .. } =
            &bc.motion
        {
            value
                .validate()
                .map_err(|m| invalid(&entity, m.to_string()))?;
        }
        constraints.push(Constraint {
            name,
            nodes,
            motion,
        });
    }
    Ok(constraints)
}

/// The motion a boundary condition prescribes on `nodes`.
fn motion(
    spec: &MotionSpec,
    entity: &str,
    nodes: &[u32],
    reference: &[Vector3<f64>],
) -> Result<Motion> {
    Ok(match spec {
        MotionSpec::Fixed(c) => Motion::Fixed(dofs(c)),
        MotionSpec::Symmetry(c) => {
            let axis = *c as usize;
            symmetry_plane(reference, nodes, axis)
                .map(|value| Motion::Symmetry { axis, value })
                .map_err(|m| invalid(entity, m.to_string()))?
        }
        MotionSpec::Velocity { components, value } => {
            Motion::Velocity(dofs(components), value.clone())
        }
        MotionSpec::Displacement { components, value } => {
            Motion::Displacement(dofs(components), value.clone())
        }
        MotionSpec::AffineVelocity {
            translation,
            gradient,
            center,
        } => Motion::AffineVelocity {
            translation: Vector3::from(*translation),
            gradient: Matrix3::from_row_slice(&gradient.concat()),
            center: Vector3::from(*center),
        },
        MotionSpec::AffineDisplacement {
            translation,
            gradient,
            center,
            scale,
        } => Motion::AffineDisplacement {
            translation: Vector3::from(*translation),
            gradient: Matrix3::from_row_slice(&gradient.concat()),
            center: Vector3::from(*center),
            scale: scale.clone(),
        },
        MotionSpec::Rotation {
            axis,
            center,
            angle,
        } => {
            let axis = Unit::try_new(Vector3::from(*axis), 1e-300)
                .ok_or_else(|| invalid(entity, "rotation axis must not be zero"))?;
            Motion::Rotation {
                axis,
                center: Vector3::from(*center),
                angle: angle.clone(),
            }
        }
    })
}

/// The scene's nodal loads on the nodes they select.
fn loads(scene: &Scene, picker: &NodePicker<'_>) -> Result<Vec<NodalLoad>> {
    let mut loads = Vec::new();
    for (i, load) in scene.loads.iter().enumerate() {
        let name = load.name.clone().unwrap_or_else(|| format!("load{i}"));
        let entity = format!("load `{name}`");
        loads.push(NodalLoad {
            nodes: picker.pick(&entity, &load.body, &load.nodes)?,
            name,
            force_per_node: Vector3::from(load.force_per_node),
            function: load.function.clone(),
        });
    }
    Ok(loads)
}

/// The scene's probes on the nodes they select.
fn probes(scene: &Scene, picker: &NodePicker<'_>) -> Result<Vec<Probe>> {
    let mut probes = Vec::new();
    for p in &scene.probes {
        let entity = format!("probe `{}`", p.name);
        probes.push(Probe {
            nodes: picker.pick(&entity, &p.body, &p.nodes)?,
            name: p.name.clone(),
            quantity: p.quantity,
        });
    }
    Ok(probes)
}

/// The scene's contact pairs, their settings checked.
fn contact_pairs(scene: &Scene) -> Result<Vec<crate::contact::ContactPair>> {
    let mut contact = Vec::new();
    for c in &scene.contact {
        let entity = format!("contact `{}`", c.name);
        let index = |name: &str| scene_body(scene, &entity, name);
        let bodies = [index(&c.bodies[0])?, index(&c.bodies[1])?];
        if bodies[0] == bodies[1] {
            return Err(invalid(
                &entity,
                "a pair needs two different bodies (self-contact is not supported)",
            ));
        }
        if !(c.friction >= 0.0) || !(c.beta_0 >= 0.0) {
            return Err(invalid(&entity, "friction and beta_0 must not be negative"));
        }
        if !(0.0..=180.0).contains(&c.crease_angle) {
            return Err(invalid(
                &entity,
                format!(
                    "crease_angle {} is not an angle in degrees between 0 and 180",
                    c.crease_angle
                ),
            ));
        }
        if c.record_problems_every == Some(0) {
            return Err(invalid(
                &entity,
                "record_problems_every is 0; give the step interval (1 records every step) or \
                 leave it out"
                    .to_string(),
            ));
        }
        if c.record_ccd_every == Some(0) {
            return Err(invalid(
                &entity,
                "record_ccd_every is 0; give the step interval (1 records every step) or leave \
                 it out"
                    .to_string(),
            ));
        }
        if let Some(speed) = c.penetration_release_speed {
            if !(speed > 0.0) {
                return Err(invalid(
                    &entity,
                    format!(
                        "penetration_release_speed {speed} must be positive (m/s); leave it out \
                         to close every penetration at once"
                    ),
                ));
            }
        }
        let solver = c.solver.choice();
        if !(solver.limits.tolerance > 0.0 && solver.limits.tolerance < 1.0)
            || solver.limits.max_iterations == 0
        {
            return Err(invalid(
                &entity,
                format!(
                    "{} tolerance {} must lie in (0, 1) and max_iterations {} be positive",
                    solver.kind, solver.limits.tolerance, solver.limits.max_iterations
                ),
            ));
        }
        contact.push(crate::contact::ContactPair {
            name: c.name.clone(),
            bodies,
            friction: c.friction,
            beta_0: c.beta_0,
            solver,
            record_every: c.record_problems_every,
            record_ccd_every: c.record_ccd_every,
            detection_tolerance: 1e-9,
            two_pass: c.two_pass,
            normals: crate::contact::normals::NormalSettings {
                kind: c.normals,
                crease_angle: c.crease_angle.to_radians(),
            },
            skip_symmetry_faces: c.skip_symmetry_faces,
            penetration_release_speed: c.penetration_release_speed.unwrap_or(f64::INFINITY),
        });
    }
    Ok(contact)
}
