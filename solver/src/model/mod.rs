//! The discrete model: every body's nodes and elements in global arrays, with the reference
//! geometry, lumped masses and the deterministic internal-force assembly.

mod assembly;
mod conditions;
mod fields;
mod history;
mod problem;

use std::collections::BTreeMap;
use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

pub use assembly::ForceAssembler;
pub use conditions::{Constraint, Dofs, Motion, NodalLoad, TimeFunction};
pub use fields::{field_frame, field_frame_with_history, CrackIndicator, ElementFields};
pub use history::{
    microplane_element_forces, BodyHistory, MaterialHistory, MicroplaneBody,
    MicroplaneElementUpdate,
};
pub use problem::{Probe, ProbeQuantity, Problem};

use crate::error::{Result, SolverError};
use crate::kinematics::{deformation_gradient, displacement_gradient, shape_gradients};
use crate::material::{Material, MaterialModel};
use crate::mesh::{element_quality, Mesh, DEFAULT_MIN_ALTITUDE_RATIO};
use crate::with_material;

/// One body of the model: a mesh of one material.
#[derive(Debug, Clone)]
pub struct Body {
    pub name: String,
    pub material: MaterialModel,
    /// Global ids of its nodes.
    pub nodes: Range<usize>,
    /// Global ids of its elements.
    pub elements: Range<usize>,
    /// Named node sets of its mesh, in global ids.
    pub node_sets: BTreeMap<String, Vec<u32>>,
    /// For a body of microplane concrete: the model and each element's crack band.
    pub microplane: Option<MicroplaneBody>,
}

/// Elements of a body that take another material (see [`Model::with_regions`]).
#[derive(Debug, Clone)]
pub struct Region {
    pub name: String,
    /// Index of the parent body in the list given to [`Model::with_regions`].
    pub parent: usize,
    /// Connectivity in the parent mesh's local node ids.
    pub tets: Vec<[u32; 4]>,
    pub material: MaterialModel,
}

/// The assembled model in its reference configuration.
#[derive(Debug)]
pub struct Model {
    /// Reference coordinates `X` (m).
    pub reference: Vec<Vector3<f64>>,
    /// Global connectivity.
    pub tets: Vec<[u32; 4]>,
    /// Reference shape-function gradients `grad_X N_a` per element (3.44).
    pub grad_n: Vec<[Vector3<f64>; 4]>,
    /// Reference volumes `V` (m^3).
    pub volume: Vec<f64>,
    /// Smallest altitude `3 V / A_max` per element (m), the length of the stable step.
    pub min_altitude: Vec<f64>,
    /// Lumped nodal masses (kg): a quarter of each element's mass to each of its nodes.
    pub mass: Vec<f64>,
    pub bodies: Vec<Body>,
    /// Body index of each element.
    pub element_body: Vec<u16>,
    /// How the crack indicator of the field output is computed (FORMULATION 5).
    pub crack_indicator: CrackIndicator,
    assembler: ForceAssembler,
}

impl Model {
    /// Assembles bodies `(name, mesh, material)`; each mesh is validated first so that an
    /// inverted or degenerate element is reported with its body and id.
    pub fn new(bodies: Vec<(String, Mesh, MaterialModel)>) -> Result<Self> {
        Self::with_regions(bodies, Vec::new())
    }

    /// As [`Self::new`], plus material regions: each [`Region`] becomes a body of its own (its
    /// own material, history and element range, after all the bodies) whose elements use the
    /// nodes of its parent body, so it is bonded to the parent's remaining elements node by node.
    /// A region body owns no nodes (its `nodes` range is empty): conditions, probes and contact
    /// select nodes through the parent.
    pub fn with_regions(
        bodies: Vec<(String, Mesh, MaterialModel)>,
        regions: Vec<Region>,
    ) -> Result<Self> {
        let mut reference = Vec::new();
        let mut tets = Vec::new();
        let mut model_bodies = Vec::new();
        let mut element_body = Vec::new();
        for (index, (name, mesh, material)) in bodies.into_iter().enumerate() {
            mesh.validate(&name, DEFAULT_MIN_ALTITUDE_RATIO)?;
            material
                .constants()
                .validate()
                .map_err(|message| SolverError::InvalidScene {
                    entity: format!("body `{name}` material"),
                    message,
                })?;
            let offset = reference.len() as u32;
            let first_element = tets.len();
            reference.extend_from_slice(&mesh.nodes);
            tets.extend(mesh.tets.iter().map(|t| t.map(|n| n + offset)));
            element_body.extend(std::iter::repeat_n(index as u16, mesh.tets.len()));
            let node_sets = mesh
                .node_sets
                .iter()
                .map(|(k, v)| (k.clone(), v.iter().map(|n| n + offset).collect()))
                .collect();
            model_bodies.push(Body {
                name,
                material,
                nodes: offset as usize..reference.len(),
                elements: first_element..tets.len(),
                node_sets,
                microplane: None,
            });
        }
        for region in regions {
            let Some(parent) = model_bodies.get(region.parent) else {
                return Err(SolverError::InvalidScene {
                    entity: format!("region `{}`", region.name),
                    message: format!("no parent body {}", region.parent),
                });
            };
            let offset = parent.nodes.start as u32;
            let end = parent.nodes.end;
            let local = Mesh {
                nodes: reference[parent.nodes.clone()].to_vec(),
                tets: region.tets.clone(),
                node_sets: BTreeMap::new(),
            };
            local.validate(&region.name, DEFAULT_MIN_ALTITUDE_RATIO)?;
            region.material.constants().validate().map_err(|message| {
                SolverError::InvalidScene {
                    entity: format!("region `{}` material", region.name),
                    message,
                }
            })?;
            let first_element = tets.len();
            let index = model_bodies.len();
            tets.extend(region.tets.iter().map(|t| t.map(|n| n + offset)));
            element_body.extend(std::iter::repeat_n(index as u16, region.tets.len()));
            model_bodies.push(Body {
                name: region.name,
                material: region.material,
                nodes: end..end,
                elements: first_element..tets.len(),
                node_sets: BTreeMap::new(),
                microplane: None,
            });
        }
        let mut grad_n = Vec::with_capacity(tets.len());
        let mut volume = Vec::with_capacity(tets.len());
        let mut min_altitude = Vec::with_capacity(tets.len());
        let mut mass = vec![0.0; reference.len()];
        for (e, tet) in tets.iter().enumerate() {
            let x = tet.map(|n| reference[n as usize]);
            let (g, v) = shape_gradients(&x).expect("validated meshes have positive volumes");
            grad_n.push(g);
            volume.push(v);
            min_altitude.push(element_quality(&x).min_altitude);
            let m = model_bodies[element_body[e] as usize].material.density() * v / 4.0;
            for &n in tet {
                mass[n as usize] += m;
            }
        }
        for body in &mut model_bodies {
            if let MaterialModel::Microplane(parameters) = body.material {
                body.microplane = Some(MicroplaneBody::new(
                    &body.name,
                    parameters,
                    &volume[body.elements.clone()],
                    body.elements.start,
                )?);
            }
        }
        let ranges: Vec<Range<usize>> = model_bodies.iter().map(|b| b.elements.clone()).collect();
        let assembler = ForceAssembler::new(&tets, reference.len(), &ranges);
        Ok(Self {
            reference,
            tets,
            grad_n,
            volume,
            min_altitude,
            mass,
            bodies: model_bodies,
            element_body,
            crack_indicator: CrackIndicator::default(),
            assembler,
        })
    }

    pub fn node_count(&self) -> usize {
        self.reference.len()
    }

    pub fn element_count(&self) -> usize {
        self.tets.len()
    }

    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    pub fn material_of(&self, element: usize) -> &MaterialModel {
        &self.bodies[self.element_body[element] as usize].material
    }

    /// Critical time step `dt_cr = min_e L_e / c_e` with `L_e` the smallest altitude and `c_e`
    /// the dilatational wave speed (FORMULATION 2), and the element that sets it.
    pub fn critical_time_step(&self) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        for (e, &l) in self.min_altitude.iter().enumerate() {
            let dt = l / self.material_of(e).dilatational_wave_speed();
            if dt < best.0 {
                best = (dt, e);
            }
        }
        best
    }

    /// Displacements of element `e`'s nodes.
    #[inline]
    pub fn element_displacements(&self, e: usize, u: &[Vector3<f64>]) -> [Vector3<f64>; 4] {
        self.tets[e].map(|n| u[n as usize])
    }

    /// Deformation gradient `F` of element `e`.
    pub fn deformation_gradient(&self, e: usize, u: &[Vector3<f64>]) -> Matrix3<f64> {
        deformation_gradient(&self.element_displacements(e, u), &self.grad_n[e])
    }

    /// Internal nodal forces `f_a = V P grad_X N_a` summed per node, written into `f`, for a
    /// model whose materials have no history.
    ///
    /// The sum at every node runs over its elements in ascending order whatever the number of
    /// threads, so the result is bitwise reproducible. Returns the lowest-numbered element with
    /// `det F <= 0` (or a non-finite `F`) if any: the caller stops the run.
    ///
    /// # Panics
    /// If a body's material has a history (microplane concrete): its forces advance that history
    /// and come from [`Self::advance_internal_forces`], once per step.
    pub fn internal_forces(&self, u: &[Vector3<f64>], f: &mut [Vector3<f64>]) -> Option<usize> {
        self.assembler.assemble(self, u, None, f)
    }

    /// Internal nodal forces at displacement `u_n` as [`Self::internal_forces`], for any model:
    /// elements of materials with history compute their stress from it and commit the update,
    /// with the strain rate from the nodal velocities `v` of the half step before (`v_{n-1/2}`,
    /// see [`microplane_element_forces`]) and the time step `dt`. Call it exactly once per step:
    /// every call advances the history. Bitwise reproducible whatever the number of threads: each
    /// element's history is written only by the assembly chunk that holds the element. An
    /// inverted element keeps its history.
    pub fn advance_internal_forces(
        &self,
        u: &[Vector3<f64>],
        v: &[Vector3<f64>],
        dt: f64,
        history: &mut MaterialHistory,
        f: &mut [Vector3<f64>],
    ) -> Option<usize> {
        assert_eq!(v.len(), u.len());
        assert_eq!(
            history.bodies.len(),
            self.bodies.len(),
            "history of another model"
        );
        self.assembler
            .assemble(self, u, Some(assembly::Stateful { v, dt, history }), f)
    }

    /// Elastic energy stored in all elements, `sum_e V_e W(E_e)`.
    ///
    /// Microplane concrete defines no potential: its elements count zero here. Their internal
    /// work (the energy ledger's `internal_work`, from the forces) is what they stored plus what
    /// they dissipated, and the energy balance uses it for every material.
    pub fn stored_energy(&self, u: &[Vector3<f64>]) -> f64 {
        self.bodies
            .iter()
            .map(|body| {
                with_material!(&body.material, |m| {
                    body.elements
                        .clone()
                        .map(|e| {
                            let h = displacement_gradient(
                                &self.element_displacements(e, u),
                                &self.grad_n[e],
                            );
                            self.volume[e] * m.strain_energy_density(&h)
                        })
                        .sum::<f64>()
                }, microplane(_) => 0.0)
            })
            .sum()
    }

    /// Element size `(6 V)^(1/3)` (m): the edge of a cube cut into six tetrahedra of this
    /// volume, the crack band's `h` and the default length of the crack indicator.
    pub fn element_size(&self, e: usize) -> f64 {
        (6.0 * self.volume[e]).cbrt()
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
        let per_element = std::mem::size_of::<[u32; 4]>()
            + std::mem::size_of::<[Vector3<f64>; 4]>()
            + 2 * std::mem::size_of::<f64>()
            + std::mem::size_of::<u16>();
        let per_node = std::mem::size_of::<Vector3<f64>>() + std::mem::size_of::<f64>();
        (per_element * self.element_count()
            + per_node * self.node_count()
            + self.assembler.heap_bytes()) as f64
            / self.element_count().max(1) as f64
    }
}

/// Element kernel shared by dynamics and statics: forces `V P grad N_a` of one element and its
/// `det F` (to detect inversion).
///
/// This is the innermost loop of every explicit step. The four gradients sum to zero
/// (`grad N_0 = -(grad N_1 + grad N_2 + grad N_3)`, see `shape_gradients`), so
/// `H = sum_a u_a grad N_a^T` is computed as `sum_{a=1..3} (u_a - u_0) grad N_a^T`: the same
/// tensor with a quarter fewer products, exactly zero for a rigid translation, and, in the
/// assembly loop of the benchmark (480 000 elements, one thread), 20.5 instead of 27 ns per
/// linear-elastic element (the four-term sum, also written out by rows or by columns, compiled
/// to slower code). `det F` is the triple product `F_0 . (F_1 x F_2)` of the columns of `F`,
/// whose cross product is also the first column of `cof F` in the linear-elastic stress (1.5 ns
/// per element faster than `determinant()` there).
#[inline(always)]
pub fn element_internal_forces<M: Material>(
    material: &M,
    grad_n: &[Vector3<f64>; 4],
    volume: f64,
    u: &[Vector3<f64>; 4],
) -> ([Vector3<f64>; 4], f64) {
    let [g0, g1, g2, g3] = grad_n;
    let h = (u[1] - u[0]) * g1.transpose()
        + (u[2] - u[0]) * g2.transpose()
        + (u[3] - u[0]) * g3.transpose();
    let f = Matrix3::identity() + h;
    let det = f.column(0).dot(&f.column(1).cross(&f.column(2)));
    let p = material.first_piola(&f, &h) * volume;
    ([p * g0, p * g1, p * g2, p * g3], det)
}
