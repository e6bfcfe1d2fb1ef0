//! A remeshed run's problem in a checkpoint. After a remeshing the run goes on over a problem
//! the scene does not describe: the new mesh, the masses and mass scaling it got, the
//! deformation and displacement carried from before, the materials' data per element (the
//! crack bands), and the node sets, conditions and probes on the new node ids. All of it
//! depends on every remeshing before, so it is stored ([`write_problem`]) and read back onto
//! the scene's problem ([`read_problem`]), which gives what the remeshings do not change: the
//! materials' models, the conditions' motions, the loads' forces, the probes' quantities,
//! gravity and the contact pairs. Every number is stored as its raw bits, and the model is
//! rebuilt from the same meshes by the same constructor as the remeshing built it, so its
//! shape-function gradients, volumes and stable steps come out bit for bit.

use nalgebra::{Matrix3, Vector3};

use super::bytes::{Read, Reader, Short, Writer};
use crate::mesh::Mesh;
use crate::model::{Body, CarriedState, MaterialSource, Model};
use crate::problem::Problem;

/// Writes the parts of `problem` that a remeshing makes (see the module's documentation).
pub fn write_problem(w: &mut Writer, problem: &Problem) {
    let model = &problem.model;
    w.usize(model.bodies.len());
    for body in &model.bodies {
        w.str(&body.name);
        for v in [
            body.nodes.start,
            body.nodes.end,
            body.elements.start,
            body.elements.end,
        ] {
            w.usize(v);
        }
        w.usize(body.node_sets.len());
        for (name, set) in &body.node_sets {
            w.str(name);
            w.u32s(set);
        }
        let data = body.material.element_data();
        w.bool(data.is_some());
        if let Some(d) = data {
            w.f64s(&d);
        }
    }
    w.vectors(&model.reference);
    let tets: Vec<u32> = model.tets.iter().flatten().copied().collect();
    w.u32s(&tets);
    w.f64s(&model.mass);
    w.bool(model.mass_scale.is_some());
    if let Some(s) = &model.mass_scale {
        w.f64s(s);
    }
    w.bool(model.carried.is_some());
    if let Some(c) = &model.carried {
        let f: Vec<f64> = c
            .deformation
            .iter()
            .flat_map(|m| m.iter().copied())
            .collect();
        w.f64s(&f);
        w.vectors(&c.displacement);
        w.f64s(&c.element_mass);
    }
    let lists = |w: &mut Writer, lists: &mut dyn Iterator<Item = &Vec<u32>>| {
        let lists: Vec<&Vec<u32>> = lists.collect();
        w.usize(lists.len());
        lists.iter().for_each(|l| w.u32s(l));
    };
    lists(w, &mut problem.constraints.iter().map(|c| &c.nodes));
    lists(w, &mut problem.loads.iter().map(|l| &l.nodes));
    lists(w, &mut problem.probes.iter().map(|p| &p.nodes));
    w.vectors(&problem.initial_velocity);
}

/// Reads what [`write_problem`] wrote onto `scene`, the problem the scene builds: its bodies'
/// materials, its conditions, loads and probes (in the same order, by name), its gravity and
/// contact pairs. An error says what does not fit.
pub fn read_problem(r: &mut Reader, scene: &Problem) -> Read<Problem> {
    let layout = read_layout(r, scene)?;
    let bodies = layout.len();
    let reference = r.vectors("reference coordinates")?;
    let tets: Vec<[u32; 4]> = r
        .u32s("connectivity")?
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2], t[3]])
        .collect();
    let mass = r.f64s("nodal masses")?;
    let mass_scale = if r.bool("mass scaling")? {
        Some(r.f64s("mass scaling")?)
    } else {
        None
    };
    let carried = if r.bool("carried state")? {
        let f = r.f64s("carried deformation")?;
        let deformation: Vec<Matrix3<f64>> =
            f.chunks_exact(9).map(Matrix3::from_column_slice).collect();
        let displacement = r.vectors("carried displacement")?;
        let element_mass = r.f64s("element masses")?;
        Some((deformation, displacement, element_mass))
    } else {
        None
    };

    let ranges: Vec<[usize; 4]> = layout.iter().map(|(r, _, _)| *r).collect();
    let mut parts = Vec::with_capacity(bodies);
    for (body, (range, node_sets, data)) in scene.model.bodies.iter().zip(layout) {
        parts.push(body_part(body, range, node_sets, data, &reference, &tets)?);
    }
    let mut model = Model::new(parts).map_err(|e| Short(format!("the model: {e}")))?;
    for (body, [n0, n1, e0, e1]) in model.bodies.iter().zip(ranges) {
        if body.nodes != (n0..n1) || body.elements != (e0..e1) {
            return Err(Short(format!(
                "body `{}`: its nodes and elements are not the ranges stored",
                body.name
            )));
        }
    }
    if mass.len() != model.node_count() {
        return Err(Short(format!(
            "{} nodal masses for {} nodes",
            mass.len(),
            model.node_count()
        )));
    }
    model.crack_indicator = scene.model.crack_indicator;
    model.mass = mass.into();
    model.mass_scale = mass_scale;
    if let Some((deformation, displacement, element_mass)) = carried {
        model.carried = Some(
            CarriedState::new(deformation, displacement, element_mass)
                .map_err(|e| Short(format!("the carried state: {e}")))?,
        );
    }

    let mut problem = Problem::new(model);
    read_conditions(r, scene, &mut problem)?;
    Ok(problem)
}

/// The bodies' names (checked against the scene's), node and element ranges, node sets and
/// data per element.
#[allow(clippy::type_complexity)]
fn read_layout(
    r: &mut Reader,
    scene: &Problem,
) -> Read<Vec<([usize; 4], Vec<(String, Vec<u32>)>, Option<Vec<f64>>)>> {
    let bodies = r.usize("bodies")?;
    if bodies != scene.model.bodies.len() {
        return Err(Short(format!(
            "{bodies} bodies, where the scene has {}",
            scene.model.bodies.len()
        )));
    }
    let mut layout = Vec::with_capacity(bodies);
    for body in &scene.model.bodies {
        let name = r.str("body name")?;
        if name != body.name {
            return Err(Short(format!(
                "body `{name}` where the scene has `{}`",
                body.name
            )));
        }
        let mut range = [0usize; 4];
        for v in &mut range {
            *v = r.usize("body ranges")?;
        }
        let sets = r.usize("node sets")?;
        let mut node_sets = Vec::with_capacity(sets);
        for _ in 0..sets {
            node_sets.push((r.str("node set name")?, r.u32s("node set")?));
        }
        let data = if r.bool("element data")? {
            Some(r.f64s("element data")?)
        } else {
            None
        };
        layout.push((range, node_sets, data));
    }
    Ok(layout)
}

/// Body `body`'s mesh (its nodes, elements and node sets in its own ids) and its material with
/// its data per element restored.
fn body_part(
    body: &Body,
    [n0, n1, e0, e1]: [usize; 4],
    node_sets: Vec<(String, Vec<u32>)>,
    data: Option<Vec<f64>>,
    reference: &[Vector3<f64>],
    tets: &[[u32; 4]],
) -> Read<(String, Mesh, MaterialSource)> {
    if n0 > n1 || n1 > reference.len() || e0 > e1 || e1 > tets.len() {
        return Err(Short(format!(
            "body `{}`: nodes {n0}..{n1} and elements {e0}..{e1} do not fit {} nodes and \
             {} elements",
            body.name,
            reference.len(),
            tets.len()
        )));
    }
    let local = |n: u32| n.checked_sub(n0 as u32).filter(|&l| (l as usize) < n1 - n0);
    let body_tets = tets[e0..e1]
        .iter()
        .map(|t| {
            let l = t.map(local);
            match l {
                [Some(a), Some(b), Some(c), Some(d)] => Ok([a, b, c, d]),
                _ => Err(Short(format!(
                    "body `{}`: element {t:?} has a node outside the body",
                    body.name
                ))),
            }
        })
        .collect::<Read<Vec<_>>>()?;
    let node_sets = node_sets
        .into_iter()
        .map(|(name, set)| {
            let set = set
                .iter()
                .map(|&n| local(n))
                .collect::<Option<Vec<u32>>>()
                .ok_or_else(|| {
                    Short(format!(
                        "body `{}`: node set `{name}` has a node outside the body",
                        body.name
                    ))
                })?;
            Ok((name, set))
        })
        .collect::<Read<_>>()?;
    let material = match data {
        None => body.material.clone(),
        Some(d) => body
            .material
            .with_element_data_material(&d)
            .map_err(|e| Short(format!("body `{}`: {e}", body.name)))?
            .unwrap_or_else(|| body.material.clone()),
    };
    let mesh = Mesh {
        nodes: reference[n0..n1].to_vec(),
        tets: body_tets,
        node_sets,
    };
    Ok((body.name.clone(), mesh, MaterialSource::Prepared(material)))
}

/// The conditions', loads' and probes' node lists onto the scene's, the initial velocities,
/// and the scene's gravity and contact pairs, into `problem`.
fn read_conditions(r: &mut Reader, scene: &Problem, problem: &mut Problem) -> Read<()> {
    let mut lists = |what: &str, count: usize| -> Read<Vec<Vec<u32>>> {
        let n = r.usize(what)?;
        if n != count {
            return Err(Short(format!("{n} {what}, where the scene has {count}")));
        }
        (0..n).map(|_| r.u32s(what)).collect()
    };
    let constraints = lists("boundary conditions", scene.constraints.len())?;
    let loads = lists("loads", scene.loads.len())?;
    let probes = lists("probes", scene.probes.len())?;
    problem.constraints = scene.constraints.clone();
    for (c, nodes) in problem.constraints.iter_mut().zip(constraints) {
        c.nodes = nodes;
    }
    problem.loads = scene.loads.clone();
    for (l, nodes) in problem.loads.iter_mut().zip(loads) {
        l.nodes = nodes;
    }
    problem.probes = scene.probes.clone();
    for (p, nodes) in problem.probes.iter_mut().zip(probes) {
        p.nodes = nodes;
    }
    problem.initial_velocity = r.vectors("initial velocities")?.into();
    problem.gravity = scene.gravity;
    problem.contact = scene.contact.clone();
    let n = problem.model.node_count();
    let out_of_range = problem
        .constraints
        .iter()
        .map(|c| &c.nodes)
        .chain(problem.loads.iter().map(|l| &l.nodes))
        .chain(problem.probes.iter().map(|p| &p.nodes))
        .flatten()
        .any(|&i| i as usize >= n);
    if out_of_range || problem.initial_velocity.len() != n {
        return Err(Short(format!(
            "a condition, load or probe names a node past the model's {n}, or the initial \
             velocities are not one per node"
        )));
    }
    Ok(())
}
