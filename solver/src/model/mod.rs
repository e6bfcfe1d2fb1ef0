//! The discrete model: every body's nodes and elements in global arrays, with the reference
//! geometry, lumped masses and the deterministic internal-force assembly.

mod assembly;
mod body_material;
mod carried;
mod conditions;
mod connectivity;
mod crack_opening;
mod element;
mod fields;
mod history;
mod kept;
mod node_array;
mod probe;
pub mod stable_step;

use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};

pub(crate) use assembly::{first_elements, NO_ELEMENT};

/// Elements per block of the sums over elements (the stored energy): ranks own whole blocks.
pub const ELEMENT_LEAF: usize = 64;
pub use assembly::{ChunkJob, ForceAssembler};
pub use body_material::BodyMaterial;
pub use carried::CarriedState;
pub use conditions::{Component, Constraint, Dofs, Motion, NodalLoad, TimeFunction};
pub use connectivity::Connectivity;
pub use element::{element_forces, ElementForces};
pub use fields::{CrackIndicator, ElementFields};
pub use history::{body_part, BodyHistory, MaterialHistory};
pub use node_array::NodeArray;
pub use probe::{Probe, ProbeQuantity};

use crate::error::{Result, SolverError};
use crate::kinematics::{deformation_gradient, displacement_gradient, shape_gradients};
use crate::material::{LinearElastic, MaterialModel, MicroplaneMaterial, SaintVenantKirchhoff};
use crate::mesh::{element_quality, Mesh, DEFAULT_MIN_ALTITUDE_RATIO};
use crate::nodal::{NodeValues, NodeView, NodeViewMut};

/// Which elements' shape-function gradients a model computes, from its bodies
/// ([`Model::with_regions_keeping`]).
pub type KeptElements<'a> = dyn Fn(&[Body]) -> Range<usize> + 'a;

/// The index of the body of `bodies` that holds `element`: bodies hold consecutive ranges of
/// elements, in the order of the bodies.
pub fn body_of(bodies: &[Body], element: usize) -> usize {
    bodies.partition_point(|b| b.elements.end <= element)
}

/// One body of the model: a mesh of one material.
#[derive(Debug, Clone)]
pub struct Body {
    /// Name of the body (a scene body or region), unique in the model.
    pub name: String,
    /// The constitutive model, prepared for the body's elements.
    pub material: Arc<dyn BodyMaterial>,
    /// Global ids of its nodes.
    pub nodes: Range<usize>,
    /// Global ids of its elements.
    pub elements: Range<usize>,
    /// Named node sets of its mesh, in global ids.
    pub node_sets: BTreeMap<String, Vec<u32>>,
}

/// Where a body's material comes from: a model a scene names (prepared for the body's elements
/// when the model is built), or any [`crate::material::Material`] given ready.
// One per body, consumed when the model is built (see `MaterialModel`).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum MaterialSource {
    /// A built-in model, prepared for the body's elements (crack bands of microplane concrete)
    /// when the model is built.
    Model(MaterialModel),
    /// A material already prepared, used as given (a custom [`crate::material::Material`]).
    Prepared(Arc<dyn BodyMaterial>),
}

impl From<MaterialModel> for MaterialSource {
    fn from(model: MaterialModel) -> Self {
        MaterialSource::Model(model)
    }
}

impl From<Arc<dyn BodyMaterial>> for MaterialSource {
    fn from(material: Arc<dyn BodyMaterial>) -> Self {
        MaterialSource::Prepared(material)
    }
}

impl MaterialSource {
    fn validate(&self, entity: &str) -> Result<()> {
        let constants = match self {
            MaterialSource::Model(m) => m.constants(),
            MaterialSource::Prepared(m) => m.constants(),
        };
        constants.validate().map_err(|e| SolverError::InvalidScene {
            entity: entity.to_string(),
            message: e.to_string(),
        })
    }

    /// The material of a body whose elements have the reference volumes `volumes` and the
    /// connectivity `tets` over `reference` (`first_element` is the global id of the first):
    /// the elastic models need nothing from them, microplane concrete the crack band of each
    /// element (and its strength at the element's reference centroid where a strength field is
    /// given), and with the band across the crack each element's reference nodes. An element too
    /// large for the crack band is an error naming the body and the element.
    fn prepare(
        self,
        body: &str,
        volumes: &[f64],
        tets: &[[u32; 4]],
        reference: &[Vector3<f64>],
        first_element: usize,
    ) -> Result<Arc<dyn BodyMaterial>> {
        match self {
            MaterialSource::Model(MaterialModel::LinearElastic(c)) => {
                Ok(Arc::new(LinearElastic::new(c)))
            }
            MaterialSource::Model(MaterialModel::SaintVenantKirchhoff(c)) => {
                Ok(Arc::new(SaintVenantKirchhoff::new(c)))
            }
            MaterialSource::Model(MaterialModel::Microplane(p)) => {
                // Only this body's, and only for concrete: a million elements' centroids are
                // 23 MiB that the elastic bodies never read.
                let centroids: Vec<[f64; 3]> = tets
                    .iter()
                    .map(|tet| {
                        let x = tet.map(|n| reference[n as usize]);
                        std::array::from_fn(|i| 0.25 * (x[0][i] + x[1][i] + x[2][i] + x[3][i]))
                    })
                    .collect();
                let centroids = &centroids[..];
                let corners = tets.iter().map(|t| t.map(|n| reference[n as usize].into()));
                Ok(Arc::new(
                    MicroplaneMaterial::new(body, p, volumes, centroids, first_element)?
                        .with_shapes(body, corners, first_element)?,
                ))
            }
            MaterialSource::Prepared(m) => Ok(m),
        }
    }
}

/// Elements of a body that take another material (see [`Model::with_regions`]).
#[derive(Debug, Clone)]
pub struct Region {
    /// Name of the body the region becomes, unique among the model's bodies.
    pub name: String,
    /// Index of the parent body in the list given to [`Model::with_regions`].
    pub parent: usize,
    /// Connectivity in the parent mesh's local node ids.
    pub tets: Vec<[u32; 4]>,
    /// The material of the region's elements.
    pub material: MaterialModel,
}

/// The assembled model in its reference configuration.
#[derive(Debug)]
pub struct Model {
    /// Reference coordinates `X` (m): every node's, or one rank's own during a distributed run
    /// without contact ([`NodeArray::keep`]).
    pub reference: NodeArray<Vector3<f64>>,
    /// Global connectivity: every element's, or one rank's own during a distributed run.
    pub tets: Connectivity,
    /// Reference shape-function gradients, volumes and smallest altitudes of the elements
    /// [`Self::kept_elements`]: every element's, or one rank's own in a distributed run
    /// ([`Self::keep_element_data`]); [`Self::grad_n`], [`Self::volume`] and
    /// [`Self::min_altitude`] read them.
    kept: kept::KeptElementData,
    /// Lumped nodal masses (kg): a quarter of each element's mass to each of its nodes (every
    /// node's, or one rank's own as [`Self::reference`]).
    pub mass: NodeArray<f64>,
    /// The bodies, in the order given; their nodes and elements are consecutive global ranges
    /// (the body of an element: [`Self::body_of`]).
    pub bodies: Vec<Body>,
    /// How the crack indicator of the field output is computed (FORMULATION 5).
    pub crack_indicator: CrackIndicator,
    /// The deformation and displacement carried from before a remeshing ([`CarriedState`]);
    /// `None` for a model that was never remeshed (`F_0 = I`, nothing computed).
    pub carried: Option<CarriedState>,
    /// Per element, the factor `s_e >= 1` by which selective mass scaling raised its density
    /// (its mass is in [`Self::mass`]; `crate::remesh::mass_scale_factors`), which lengthens
    /// its stable step by `sqrt(s_e)`; `None`: no element is scaled.
    pub mass_scale: Option<Vec<f64>>,
    assembler: ForceAssembler,
}

impl Model {
    /// Assembles bodies `(name, mesh, material)`; each mesh is validated first so that an
    /// inverted or degenerate element is reported with its body and id.
    pub fn new<M: Into<MaterialSource>>(bodies: Vec<(String, Mesh, M)>) -> Result<Self> {
        Self::with_regions(bodies, Vec::new())
    }

    /// As [`Self::new`], plus material regions: each [`Region`] becomes a body of its own (its
    /// own material, history and element range, after all the bodies) whose elements use the
    /// nodes of its parent body, so it is bonded to the parent's remaining elements node by node.
    /// A region body owns no nodes (its `nodes` range is empty): conditions, probes and contact
    /// select nodes through the parent.
    pub fn with_regions<M: Into<MaterialSource>>(
        bodies: Vec<(String, Mesh, M)>,
        regions: Vec<Region>,
    ) -> Result<Self> {
        Self::with_regions_keeping(bodies, regions, &|bodies| {
            0..bodies.last().map_or(0, |b| b.elements.end)
        })
    }

    /// As [`Self::with_regions`], computing the shape-function gradients of the elements
    /// `kept(bodies)` only (the range [`Self::keep_element_data`] would keep): a rank of a distributed run passes its own range
    /// (`crate::dynamics::rank_ranges_of`), so that no rank holds every element's gradients even
    /// while the model is built (96 bytes per element: 92 MiB for a million).
    pub fn with_regions_keeping<M: Into<MaterialSource>>(
        bodies: Vec<(String, Mesh, M)>,
        regions: Vec<Region>,
        kept: &KeptElements<'_>,
    ) -> Result<Self> {
        let mut reference = Vec::new();
        let mut tets = Vec::new();
        // Name, nodes, elements, node sets and material of each body, prepared below.
        let mut parts = Vec::new();
        for (name, mesh, material) in bodies {
            mesh.validate(&name, DEFAULT_MIN_ALTITUDE_RATIO)?;
            let material: MaterialSource = material.into();
            material.validate(&format!("body `{name}` material"))?;
            let offset = reference.len() as u32;
            let first_element = tets.len();
            if reference.is_empty() && tets.is_empty() {
                // The first body's arrays become the model's, not copied: a rank of a
                // distributed run builds the whole model and holds no second mesh meanwhile.
                reference = mesh.nodes;
                tets = mesh.tets;
            } else {
                reference.extend_from_slice(&mesh.nodes);
                tets.extend(mesh.tets.iter().map(|t| t.map(|n| n + offset)));
            }
            let node_sets = mesh
                .node_sets
                .iter()
                .map(|(k, v)| (k.clone(), v.iter().map(|n| n + offset).collect()))
                .collect();
            parts.push((
                name,
                offset as usize..reference.len(),
                first_element..tets.len(),
                node_sets,
                material,
            ));
        }
        for region in regions {
            let Some((_, parent_nodes, ..)) = parts.get(region.parent) else {
                return Err(SolverError::InvalidScene {
                    entity: format!("region `{}`", region.name),
                    message: format!("no parent body {}", region.parent),
                });
            };
            let parent_nodes: Range<usize> = parent_nodes.clone();
            let offset = parent_nodes.start as u32;
            let end = parent_nodes.end;
            let local = Mesh {
                nodes: reference[parent_nodes].to_vec(),
                tets: region.tets.clone(),
                node_sets: BTreeMap::new(),
            };
            local.validate(&region.name, DEFAULT_MIN_ALTITUDE_RATIO)?;
            let material = MaterialSource::Model(region.material);
            material.validate(&format!("region `{}` material", region.name))?;
            let first_element = tets.len();
            tets.extend(region.tets.iter().map(|t| t.map(|n| n + offset)));
            parts.push((
                region.name,
                end..end,
                first_element..tets.len(),
                BTreeMap::new(),
                material,
            ));
        }
        let mut volume = Vec::with_capacity(tets.len());
        let mut min_altitude = Vec::with_capacity(tets.len());
        for tet in &tets {
            let x = tet.map(|n| reference[n as usize]);
            let (_, v) = shape_gradients(&x).expect("validated meshes have positive volumes");
            volume.push(v);
            min_altitude.push(element_quality(&x).min_altitude);
        }
        let mut model_bodies = Vec::with_capacity(parts.len());
        for (name, nodes, elements, node_sets, material) in parts {
            let material = material.prepare(
                &name,
                &volume[elements.clone()],
                &tets[elements.clone()],
                &reference,
                elements.start,
            )?;
            model_bodies.push(Body {
                name,
                material,
                nodes,
                elements,
                node_sets,
            });
        }
        let kept = kept(&model_bodies);
        // Element by element in ascending order, as the bodies hold consecutive ranges.
        let mut mass = vec![0.0; reference.len()];
        for body in &model_bodies {
            let density = body.material.constants().density;
            for e in body.elements.clone() {
                let m = density * volume[e] / 4.0;
                for &n in &tets[e] {
                    mass[n as usize] += m;
                }
            }
        }
        let ranges: Vec<Range<usize>> = model_bodies.iter().map(|b| b.elements.clone()).collect();
        let tets = Connectivity::from(tets);
        let costs: Vec<f64> = model_bodies
            .iter()
            .map(|b| b.material.relative_cost())
            .collect();
        let assembler = ForceAssembler::with_costs(&tets, reference.len(), &ranges, &costs);
        let kept = kept::KeptElementData::new(&tets, &reference, kept, volume, min_altitude);
        Ok(Self {
            reference: reference.into(),
            tets,
            kept,
            mass: mass.into(),
            bodies: model_bodies,
            crack_indicator: CrackIndicator::default(),
            carried: None,
            mass_scale: None,
            assembler,
        })
    }

    /// Number of nodes over all bodies.
    pub fn node_count(&self) -> usize {
        self.reference.len()
    }

    /// Number of elements over all bodies.
    pub fn element_count(&self) -> usize {
        self.tets.len()
    }

    /// Index of the body named `name`, if there is one.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The index of the body that holds `element` (a global element index).
    pub fn body_of(&self, element: usize) -> usize {
        body_of(&self.bodies, element)
    }

    /// The material of the body that holds `element` (a global element index).
    pub fn material_of(&self, element: usize) -> &dyn BodyMaterial {
        &*self.bodies[self.body_of(element)].material
    }

    /// Critical time step `dt_cr = min_e L_e / c_e` with `L_e` the smallest altitude and `c_e`
    /// the dilatational wave speed (FORMULATION 2), and the element that sets it. An element
    /// whose density mass scaling raised by `s_e` ([`Self::mass_scale`]) has `c_e / sqrt(s_e)`;
    /// one lighter than its material's density has its own wave speed
    /// (`Self::stable_length`).
    pub fn critical_time_step(&self) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        for e in 0..self.element_count() {
            let dt = self.stable_length(e, self.min_altitude(e), self.volume(e))
                / self.material_of(e).constants().dilatational_wave_speed();
            if dt < best.0 {
                best = (dt, e);
            }
        }
        best
    }

    /// The stable limit in the configuration `X + u` (s) and the element that sets it: the
    /// smallest current altitude over the dilatational wave speed at the element's current
    /// density. Elements that a penetrator flattens, and the dilated ones a remeshing leaves
    /// light, bring it down well below [`Self::critical_time_step`] of the reference.
    pub fn current_critical_time_step(&self, u: &[Vector3<f64>]) -> (f64, usize) {
        use rayon::prelude::*;
        // Per element in parallel (a remeshing run asks every few steps), then the first
        // smallest in element order, as a serial scan finds it.
        let steps: Vec<f64> = (0..self.tets.len())
            .into_par_iter()
            .map(|e| {
                let x = self.tets[e].map(|n| self.reference[n as usize] + u[n as usize]);
                let q = crate::mesh::element_quality(&x);
                self.stable_length(e, q.min_altitude, q.volume)
                    / self.material_of(e).constants().dilatational_wave_speed()
            })
            .collect();
        let mut best = (f64::INFINITY, 0);
        for (e, &dt) in steps.iter().enumerate() {
            if dt < best.0 {
                best = (dt, e);
            }
        }
        best
    }

    /// The length `l sqrt(s_e r_e)` that sets element `e`'s stable step `l sqrt(s_e r_e) / c`,
    /// with `c` its material's nominal wave speed, `s_e` its mass scale and
    /// `r_e = min(1, m_e / (rho_0 v))` ([`light_density_ratio`]) at the element's `volume`
    /// `v` (`l` itself where both are 1, bitwise).
    ///
    /// The wave speed `sqrt(M / rho)` is taken at the element's current density `m_e / v`
    /// (Belytschko, Liu & Moran 2000, sec. 6.3: the element's eigenvalue bound in the current
    /// configuration). A remeshing gives a new element its parent's current density
    /// (`crate::remesh`), and the concrete the nail tears open at the cavity wall has dilated
    /// to a hundredth of `rho_0`: its step is a tenth of the nominal estimate, and a step
    /// between the two throws its nodes (issue 21). A denser element keeps the nominal
    /// estimate: compacted concrete stiffens, so its speed is not taken to fall.
    #[inline]
    fn stable_length(&self, e: usize, l: f64, volume: f64) -> f64 {
        let scale = self.mass_scale.as_ref().map_or(1.0, |s| s[e]);
        let rho_0 = self.material_of(e).constants().density;
        let mass = match &self.carried {
            Some(c) => c.element_mass[e],
            None => rho_0 * self.volume(e),
        };
        let factor = scale * light_density_ratio(mass, rho_0, volume);
        if factor == 1.0 {
            l
        } else {
            l * factor.sqrt()
        }
    }

    /// The reference corners of element `e`.
    #[inline]
    fn reference_corners(&self, e: usize) -> [Vector3<f64>; 4] {
        self.tets[e].map(|n| self.reference[n as usize])
    }

    /// Reference shape-function gradients `grad_X N_a` of element `e` (3.44): the stored ones,
    /// or for an element whose data this rank does not keep ([`Self::keep_element_data`]), the
    /// same ones computed again from the reference coordinates by the same function.
    #[inline]
    pub fn grad_n(&self, e: usize) -> [Vector3<f64>; 4] {
        self.kept.grad_n(e, || self.reference_corners(e))
    }

    /// Reference volume `V` of element `e` (m^3), stored or computed again as [`Self::grad_n`].
    #[inline]
    pub fn volume(&self, e: usize) -> f64 {
        self.kept.volume(e, || self.reference_corners(e))
    }

    /// Smallest altitude `3 V / A_max` of element `e` (m), the length of its stable step, stored
    /// or computed again as [`Self::grad_n`].
    #[inline]
    pub fn min_altitude(&self, e: usize) -> f64 {
        self.kept.min_altitude(e, || self.reference_corners(e))
    }

    /// The stored shape-function gradients of the elements of `range`, which must be kept
    /// ([`Self::keep_element_data`]).
    pub(crate) fn kept_grad_n(&self, range: Range<usize>) -> &[[Vector3<f64>; 4]] {
        self.kept.grad_n_of(range)
    }

    /// The stored volumes of the elements of `range`, which must be kept.
    pub(crate) fn kept_volumes(&self, range: Range<usize>) -> &[f64] {
        self.kept.volumes_of(range)
    }

    /// The elements whose gradients, volumes and altitudes are stored.
    pub fn kept_elements(&self) -> Range<usize> {
        self.kept.range()
    }

    /// Keeps the per-element data that the elements' own force computation reads (the
    /// shape-function gradients, volumes and smallest altitudes, 112 bytes per element) for the
    /// elements of `elements` only: a rank of a distributed run computes the forces of its own
    /// elements, and reads any other element's rarely (its stable step once, output, an error
    /// message), through [`Self::grad_n`], [`Self::volume`] and [`Self::min_altitude`].
    pub fn keep_element_data(&mut self, elements: Range<usize>) {
        self.kept.keep(elements);
    }

    /// Computes and keeps the per-element data of `elements` ([`Self::keep_element_data`]) in
    /// place of what is kept: the data of a model built keeping none
    /// ([`Self::with_regions_keeping`] of an empty range), computed once what built it (the
    /// meshes it was copied from, the other ranks' connectivity and nodes) is freed, so that a
    /// rank's setup never holds both. Reads the connectivity of `elements` and the reference
    /// coordinates of their nodes only.
    pub fn compute_element_data(&mut self, elements: Range<usize>) {
        self.kept = kept::KeptElementData::compute(&self.tets, &self.reference, elements);
    }

    /// The per-element data of exactly `elements`: the part of what is kept where it holds them
    /// ([`Self::keep_element_data`]), computed otherwise ([`Self::compute_element_data`]).
    pub fn keep_or_compute_element_data(&mut self, elements: Range<usize>) {
        let kept = self.kept_elements();
        if kept.start <= elements.start && elements.end <= kept.end {
            self.keep_element_data(elements);
        } else {
            self.compute_element_data(elements);
        }
    }

    /// The current position `X + u` of every node at the displacement `u` of every node.
    pub fn positions(&self, u: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        assert_eq!(u.len(), self.reference.len(), "one displacement per node");
        self.reference.iter().zip(u).map(|(x, u)| x + u).collect()
    }

    /// [`Self::positions`] on a rank that keeps its own nodes' reference coordinates only
    /// ([`NodeArray::keep`]): `NaN` at the nodes it does not store, which its piece of a field
    /// frame (its own elements and their nodes) never reads.
    pub fn positions_where_stored(&self, u: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        assert_eq!(u.len(), self.reference.len(), "one displacement per node");
        let field = self.reference.field();
        (0..u.len())
            .map(|a| field.get(a).map_or(Vector3::repeat(f64::NAN), |x| x + u[a]))
            .collect()
    }

    /// Displacements of element `e`'s nodes.
    #[inline]
    pub fn element_displacements<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        e: usize,
        u: &U,
    ) -> [Vector3<f64>; 4] {
        // Spelled out: through `map`, a field's lookup stayed a call (`array::try_map`: 7 % of the
        // elastic drop test's samples, which reads every element's displacements per history row).
        let [a, b, c, d] = self.tets[e];
        [u[a as usize], u[b as usize], u[c as usize], u[d as usize]]
    }

    /// Deformation gradient `F` of element `e` from the stress-free configuration: `F_r F_0`
    /// after a remeshing ([`CarriedState`]), else `I + grad_X u`.
    pub fn deformation_gradient<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        e: usize,
        u: &U,
    ) -> Matrix3<f64> {
        let f = deformation_gradient(&self.element_displacements(e, u), &self.grad_n(e));
        match &self.carried {
            Some(c) => f * c.deformation[e],
            None => f,
        }
    }

    /// Displacement gradient `H = F - I` of element `e` from the stress-free configuration: the
    /// one every strain measure reads. `grad_X u` itself before any remeshing (so bitwise what
    /// it always was); after one, `F_r F_0 - I` with [`Self::deformation_gradient`], not the
    /// gradient of the displacement since the remeshing, which knows nothing of the
    /// deformation reached before it.
    pub fn strain_gradient<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        e: usize,
        u: &U,
    ) -> Matrix3<f64> {
        match &self.carried {
            Some(_) => self.deformation_gradient(e, u) - Matrix3::identity(),
            None => displacement_gradient(&self.element_displacements(e, u), &self.grad_n(e)),
        }
    }

    /// Internal nodal forces `f_a = V P grad_X N_a` summed per node, written into `f`, for a
    /// model whose materials have no history.
    ///
    /// The sum at every node runs over its elements in ascending order whatever the number of
    /// threads, so the result is bitwise reproducible. Returns the lowest-numbered element with
    /// `det F <= 0` (or a non-finite `F`) if any: the caller stops the run. A body whose material
    /// keeps a history is an error ([`SolverError::ForcesAdvanceHistory`]): its forces advance
    /// that history and come from [`Self::advance_internal_forces`], once per step.
    pub fn internal_forces<'a>(
        &self,
        u: impl Into<NodeView<'a, Vector3<f64>>>,
        f: impl Into<NodeViewMut<'a, Vector3<f64>>>,
    ) -> Result<Option<usize>> {
        if let Some(body) = self.bodies.iter().find(|b| b.material.history_len() > 0) {
            return Err(SolverError::ForcesAdvanceHistory {
                body: body.name.clone(),
                material: body.material.name(),
            });
        }
        Ok(self.assembler.assemble(self, u.into(), None, f.into()))
    }

    /// Internal nodal forces at displacement `u_n` as [`Self::internal_forces`], for any model:
    /// elements of materials with history compute their stress from it and commit the update,
    /// with the strain rate from the nodal velocities `v` of the half step before (`v_{n-1/2}`,
    /// see [`crate::material::Deformation`]) and the time step `dt`. Call it exactly once per step:
    /// every call advances the history. Bitwise reproducible whatever the number of threads: each
    /// element's history is written only by the assembly chunk that holds the element. An
    /// inverted element keeps its history.
    pub fn advance_internal_forces<'a>(
        &self,
        u: impl Into<NodeView<'a, Vector3<f64>>>,
        v: impl Into<NodeView<'a, Vector3<f64>>>,
        dt: f64,
        history: &mut MaterialHistory,
        f: impl Into<NodeViewMut<'a, Vector3<f64>>>,
    ) -> Option<usize> {
        let (u, v, f) = (u.into(), v.into(), f.into());
        assert_eq!(v.storage().len(), u.storage().len());
        assert_eq!(
            history.bodies.len(),
            self.bodies.len(),
            "history of another model"
        );
        self.assembler
            .assemble(self, u, Some(assembly::Stateful { v, dt, history }), f)
    }

    /// From now on [`Self::advance_internal_forces`] and [`Self::internal_forces`] compute only
    /// the elements of `range`, one rank's share of a distributed run (`crate::distributed`): a
    /// node whose first element lies in `range` gets the fold of the range's contributions, the
    /// contributions to nodes of earlier elements are kept apart
    /// ([`Self::append_foreign_contributions`]).
    pub fn restrict_assembly(&self, range: std::ops::Range<usize>) {
        self.assembler.restrict_to(self, range);
    }

    /// Appends to `out` the last assembly's contributions to nodes whose first element precedes
    /// its range, node by node ascending and each in element order, three components each
    /// ([`Self::restrict_assembly`]).
    pub fn append_foreign_contributions(&self, out: &mut Vec<f64>) {
        self.assembler.append_foreign_contributions(out);
    }

    /// The mass of each element (kg): the body's density times its reference volume, or the
    /// carried mass after a remeshing ([`CarriedState::element_mass`]).
    pub fn element_masses(&self) -> Vec<f64> {
        match &self.carried {
            Some(c) => c.element_mass.clone(),
            None => self
                .bodies
                .iter()
                .flat_map(|body| {
                    let density = body.material.constants().density;
                    body.elements.clone().map(move |e| density * self.volume(e))
                })
                .collect(),
        }
    }

    /// Elastic energy stored in all elements, `sum_e V_e W(E_e)` (after a remeshing, `V_e` the
    /// stress-free volume `V_r / det F_0` and `E_e` from `F = F_r F_0`).
    ///
    /// Microplane concrete defines no potential: its elements count zero here. Their internal
    /// work (the energy ledger's `internal_work`, from the forces) is what they stored plus what
    /// they dissipated, and the energy balance uses it for every material.
    ///
    /// The sum is the fold, in order, of the shares of blocks of [`ELEMENT_LEAF`] elements
    /// ([`Self::stored_energy_shares`]), so that ranks holding whole blocks give the same bits.
    pub fn stored_energy<U: NodeValues<Vector3<f64>> + ?Sized>(&self, u: &U) -> f64 {
        let leaves = 0..self.element_count().div_ceil(ELEMENT_LEAF);
        self.stored_energy_shares(u, leaves).iter().sum()
    }

    /// The elastic energy of each block `j` of elements `j L..(j + 1) L` in `leaves`
    /// (`L` = [`ELEMENT_LEAF`]), each the fold over its elements in ascending order; reads the
    /// displacement of those elements' nodes only.
    pub fn stored_energy_shares<U: NodeValues<Vector3<f64>> + ?Sized>(
        &self,
        u: &U,
        leaves: Range<usize>,
    ) -> Vec<f64> {
        let mut shares = vec![0.0; leaves.len()];
        let elements =
            leaves.start * ELEMENT_LEAF..(leaves.end * ELEMENT_LEAF).min(self.element_count());
        // Body by body: the elements still come in ascending order (consecutive ranges).
        for body in &self.bodies {
            let material = &body.material;
            if material.strain_energy_density(&Matrix3::zeros()).is_none() {
                continue;
            }
            let ours = body.elements.start.max(elements.start)..body.elements.end.min(elements.end);
            for e in ours {
                let energy = match &self.carried {
                    // The stress-free volume is V_r / det F_0.
                    Some(c) => {
                        let h = self.deformation_gradient(e, u) - Matrix3::identity();
                        material
                            .strain_energy_density(&h)
                            .map(|w| self.volume(e) / c.deformation[e].determinant() * w)
                    }
                    None => {
                        let h = displacement_gradient(
                            &self.element_displacements(e, u),
                            &self.grad_n(e),
                        );
                        material
                            .strain_energy_density(&h)
                            .map(|w| self.volume(e) * w)
                    }
                };
                if let Some(energy) = energy {
                    shares[e / ELEMENT_LEAF - leaves.start] += energy;
                }
            }
        }
        shares
    }

    /// Element size `(6 V)^(1/3)` (m): the edge of a cube cut into six tetrahedra of this
    /// volume, the crack band's `h` and the default length of the crack indicator.
    pub fn element_size(&self, e: usize) -> f64 {
        (6.0 * self.volume(e)).cbrt()
    }

    /// Nodes of `body` that lie in the node set named `set` (a Gmsh physical group).
    pub fn body_node_set(&self, body: usize, set: &str) -> Option<&[u32]> {
        self.bodies[body].node_sets.get(set).map(Vec::as_slice)
    }

    /// Total mass of the model (kg).
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Bytes held per element by the model's element arrays (connectivity, gradients, volume,
    /// altitude, body id, assembly slots), for the memory report of the benchmarks.
    pub fn bytes_per_element(&self) -> f64 {
        let per_element = std::mem::size_of::<[u32; 4]>() + std::mem::size_of::<u16>();
        let per_node = std::mem::size_of::<Vector3<f64>>() + std::mem::size_of::<f64>();
        (per_element * self.element_count()
            + self.kept.heap_bytes()
            + per_node * self.node_count()
            + self.assembler.heap_bytes()) as f64
            / self.element_count().max(1) as f64
    }
}

/// `min(1, m / (rho_0 v))`: the density of an element of mass `m` and volume `v` over its
/// material's `rho_0`, where it is lighter (1 otherwise, exactly when `m = rho_0 v`).
/// It scales the element's stable step by its square root ([`Model::critical_time_step`]).
pub fn light_density_ratio(mass: f64, rho_0: f64, volume: f64) -> f64 {
    let reference = rho_0 * volume;
    if mass < reference {
        mass / reference
    } else {
        1.0
    }
}
