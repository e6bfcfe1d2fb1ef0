//! The first steps of a remeshing: the remeshed body as the run left it ([`OldBody`]), its new
//! mesh ([`generate`]) and where each new node and element takes its fields from
//! ([`field_sources`]).

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

use super::{fail, largest_stretch};
use crate::dynamics::RunState;
use crate::error::Result;
use crate::mesh::boundary_faces_of;
use crate::mesh::ops::locate::{centroid, centroids, Location, Locator};
use crate::mesh::ops::mesher::{remesh_region_keeping_edges, MesherOptions, RemeshedRegion};
use crate::problem::Problem;

/// The remeshed body at the pause: its node and element ranges, the current configuration of
/// the whole model, its connectivity and region in its own ids, and every element's
/// deformation gradient since the stress-free configuration.
pub(super) struct OldBody {
    /// The body's index.
    pub b: usize,
    /// Its global node ids.
    pub nodes: Range<usize>,
    /// Its global element ids.
    pub elements: Range<usize>,
    /// The current position of every node of the model (m).
    pub x_all: Vec<Vector3<f64>>,
    /// The body's connectivity in its own node ids.
    pub local_tets: Vec<[u32; 4]>,
    /// The region in the body's own element ids.
    pub local_region: Vec<usize>,
    /// `F` of every element of the model (the carried `F_0` included).
    pub old_f: Vec<Matrix3<f64>>,
}

impl OldBody {
    /// Body `b` of `problem` at the running state `state`, with `region` (global element ids).
    pub fn at(problem: &Problem, state: &RunState, b: usize, region: &[usize]) -> Self {
        let model = &problem.model;
        let body = &model.bodies[b];
        let (nodes, elements) = (body.nodes.clone(), body.elements.clone());
        let x_all = model.positions(&state.u);
        let local_tets: Vec<[u32; 4]> = model.tets[elements.clone()]
            .iter()
            .map(|t| t.map(|n| n - nodes.start as u32))
            .collect();
        let local_region: Vec<usize> = region.iter().map(|e| e - elements.start).collect();
        // Element fields: F since the stress-free configuration (carried below), and the
        // current density.
        let old_f: Vec<Matrix3<f64>> = (0..model.element_count())
            .map(|e| model.deformation_gradient(e, &state.u))
            .collect();
        Self {
            b,
            nodes,
            elements,
            x_all,
            local_tets,
            local_region,
            old_f,
        }
    }

    /// The current positions of the body's nodes (m).
    pub fn x(&self) -> &[Vector3<f64>] {
        &self.x_all[self.nodes.clone()]
    }

    /// `F` of the body's elements.
    pub fn local_f(&self) -> &[Matrix3<f64>] {
        &self.old_f[self.elements.clone()]
    }
}

/// The bodies in contact with the remeshed one, each with a locator over its current mesh.
pub(super) fn partner_locators<'a>(
    problem: &'a Problem,
    old: &'a OldBody,
) -> Result<Vec<(usize, Locator<'a>)>> {
    let model = &problem.model;
    let b = old.b;
    let partners: Vec<usize> = problem
        .contact
        .iter()
        .filter_map(|pair| match pair.bodies {
            [p, q] if p == b => Some(q),
            [p, q] if q == b => Some(p),
            _ => None,
        })
        .collect();
    partners
        .into_iter()
        .map(|o| {
            let tets = &model.tets[model.bodies[o].elements.clone()];
            Ok((o, Locator::new(&old.x_all, tets)?))
        })
        .collect::<Result<Vec<_>>>()
}

/// The body's new mesh: its region remeshed by [`remesh_region_keeping_edges`], keeping the
/// edges whose midpoint lies inside a contact partner and eroding the region's elements that
/// lie in failed material.
pub(super) fn generate(
    old: &OldBody,
    partners: &[(usize, Locator)],
    locator: &Locator,
    options: &MesherOptions,
) -> Result<RemeshedRegion> {
    let x = old.x();
    // An edge whose midpoint lies inside a partner is not split: its new node would have to be
    // moved out, by the chord's sagitta, and can invert the element behind it.
    let inside_partner = |a: u32, c: u32| {
        let mid = 0.5 * (x[a as usize] + x[c as usize]);
        partners.iter().any(|(_, l)| l.holds_strictly(&mid))
    };
    // Failed material (`MesherOptions::erode_stretch`): the old elements whose carried
    // deformation stretches past the limit; a region element lying in one is eroded.
    let torn: Vec<bool> = if options.erode && options.erode_stretch > 0.0 {
        old.local_f()
            .iter()
            .map(|f| largest_stretch(f) > options.erode_stretch)
            .collect()
    } else {
        Vec::new()
    };
    let failed = |corners: &[Vector3<f64>; 4]| {
        !torn.is_empty() && torn[locator.locate(&centroid(corners)).element]
    };
    remesh_region_keeping_edges(
        x,
        &old.local_tets,
        &old.local_region,
        options,
        &inside_partner,
        &failed,
    )
}

/// Which of the new mesh's nodes lie on its boundary, and the new ones among them: the
/// candidates to be moved out of a contact partner.
pub(super) fn boundary_nodes(new: &RemeshedRegion) -> (Vec<bool>, Vec<u32>) {
    let mut on_boundary = vec![false; new.nodes.len()];
    for f in boundary_faces_of(&new.tets) {
        for n in f.nodes {
            on_boundary[n as usize] = true;
        }
    }
    let candidates: Vec<u32> = new
        .new_nodes()
        .into_iter()
        .filter(|&n| on_boundary[n as usize])
        .collect();
    (on_boundary, candidates)
}

/// Where the new mesh takes its fields from: each new node's place in the old mesh, as
/// generated (a node moved later takes the values of where it was generated, on the old
/// surface), and each new element's parent, the old element holding its centroid (a copied
/// element is its own parent; only new ones are searched).
pub(super) fn field_sources(
    old: &OldBody,
    locator: &Locator,
    new: &RemeshedRegion,
    options: &MesherOptions,
) -> Result<(Vec<Location>, Vec<usize>)> {
    let x = old.x();
    let size = x
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.amax()))
        .max(f64::MIN_POSITIVE);
    // The remesher may move a curved part of the surface by up to `surface_deviation`, outward
    // too (a node sliding on the old surface bends the faces around it off it), and an inner
    // node smoothed next to it may follow: such a node lies that far outside the old mesh at
    // most, and takes the fields of the nearest old element, extrapolated over that distance
    // (1.2 um in the nail run at 63 us, where this stopped the run).
    let outside = (1e-9 * size).max(options.surface_deviation);
    let locations = locator.locate_remeshed_nodes(&old.local_tets, new, outside)?;
    let parents: Vec<usize> = centroids(&new.nodes, &new.tets)
        .iter()
        .zip(&new.element_origin)
        .map(|(c, origin)| match origin {
            Some(o) => *o as usize,
            None => locator.locate(c).element,
        })
        .collect();
    Ok((locations, parents))
}

/// An error when a load acts on a node of the body that the new mesh does not keep: a force
/// per node would change its resultant on a refined face.
pub(super) fn check_loads(problem: &Problem, old: &OldBody, new: &RemeshedRegion) -> Result<()> {
    let nodes = &old.nodes;
    for load in &problem.loads {
        if let Some(n) = load.nodes.iter().find(|&&n| {
            nodes.contains(&(n as usize)) && new.kept_nodes[n as usize - nodes.start].is_none()
        }) {
            return Err(fail(
                &format!("load `{}`", load.name),
                format!("acts on node {n}, which the remeshing replaces"),
            ));
        }
    }
    Ok(())
}
