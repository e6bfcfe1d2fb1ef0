//! Point-triangle continuous collision detection queries for a cross-check of our vertex-face
//! CCD (`impact_solver::contact::ccd::vertex_face_ccd`) against an independent implementation
//! (ipctk's Tight-Inclusion point-triangle CCD): queries recorded from real runs of catalogue
//! cases, and random ones built to be hard, with our answers.
//!
//! A query is the straight-line motion over one step of a point `v` and a triangle
//! `(f0, f1, f2)`, given by the 8 positions in ipctk's argument order
//! `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1` (`t0`: start of the step, `t1`: its
//! end; `f0..f2` in the face's node order).
//!
//! # File format (`CCDQ0001`)
//!
//! Little-endian, packed, no padding:
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"CCDQ0001"` |
//! | 8 | 8 | `u64` number of queries `n` |
//! | 16 | `193 n` | per query: `u8` source code ([`QuerySource::code`]), then 24 `f64`: the 8 points above, `x y z` each |
//!
//! In Python: `numpy.fromfile(path, dtype=numpy.dtype([('source', 'u1'), ('x', '<f8', (8, 3))]),
//! offset=16)` (the structured dtype is packed, itemsize 193).

mod file;
mod random;
mod record;

pub use file::{read_queries, write_queries, HEADER_BYTES, MAGIC, QUERY_BYTES};
pub use random::{random_family, random_queries, RandomFamily};
pub use record::{record_case, record_from_case, Recording};

use impact_references::queries::Query;
use impact_solver::contact::ccd::{vertex_face_ccd, Trajectory};

/// Where a query comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QuerySource {
    /// Recorded from `contact/spheres-headon` (code 0).
    Sphere,
    /// Recorded from `beam/drop-2ms` (code 1).
    Beam,
    /// Built by [`random_queries`] (code 2).
    Random,
}

impl QuerySource {
    /// Every source, in code order.
    pub const ALL: [QuerySource; 3] = [QuerySource::Sphere, QuerySource::Beam, QuerySource::Random];

    /// The source's name in tables (`sphere`, `beam`, `random`).
    pub fn name(self) -> &'static str {
        match self {
            QuerySource::Sphere => "sphere",
            QuerySource::Beam => "beam",
            QuerySource::Random => "random",
        }
    }

    /// The byte stored in the file.
    pub fn code(self) -> u8 {
        match self {
            QuerySource::Sphere => 0,
            QuerySource::Beam => 1,
            QuerySource::Random => 2,
        }
    }

    /// The source of a stored byte; `None` for an unknown code.
    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.code() == code)
    }
}

/// One point-triangle CCD query: `points` in ipctk's order
/// `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdQuery {
    /// Where the query comes from.
    pub source: QuerySource,
    /// Vertex and face positions at the start and end of the step (m), in ipctk's order.
    pub points: [[f64; 3]; 8],
}

impl CcdQuery {
    /// The query of a node's and a face's trajectories.
    pub fn from_trajectories(
        source: QuerySource,
        node: &Trajectory,
        face: &[Trajectory; 3],
    ) -> Self {
        let query = Query {
            node: *node,
            face: *face,
        };
        Self {
            source,
            points: query.points(),
        }
    }

    /// The node's trajectory and the face's three.
    pub fn trajectories(&self) -> (Trajectory, [Trajectory; 3]) {
        let query = Query::from_points(&self.points);
        (query.node, query.face)
    }

    /// The bit patterns of the points: equal exactly when the queries' geometry is.
    fn key(&self) -> [u64; 24] {
        let mut k = [0u64; 24];
        for (slot, x) in k.iter_mut().zip(self.points.iter().flatten()) {
            *slot = x.to_bits();
        }
        k
    }
}

/// Our answer: the step fraction of the first contact found by `vertex_face_ccd` with the
/// barycentric `tolerance` (the solver's detection passes `1e-9`), or `None`.
pub fn our_time_of_impact(q: &CcdQuery, tolerance: f64) -> Option<f64> {
    let (node, face) = q.trajectories();
    vertex_face_ccd(&node, [&face[0], &face[1], &face[2]], tolerance).map(|h| h.t)
}
