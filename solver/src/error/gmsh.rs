//! What is wrong with a Gmsh mesh file (`crate::mesh::gmsh`), and the fix: the reason a
//! [`super::SolverError::MeshRead`] carries.

const REEXPORT: &str = "re-export it from Gmsh as format 4.1 (`gmsh -3 -format msh41 model.geo`)";

/// What is wrong with a mesh file, and the fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GmshError {
    /// The file could not be read (the system's message).
    #[error(
        "{0}. Fix: check the path (a relative path is taken from the folder of the scene or case \
         file that names it)"
    )]
    Read(String),
    /// The file does not start with `$MeshFormat`: not a Gmsh mesh.
    #[error("not a Gmsh mesh: it does not start with `$MeshFormat`; {r}", r = REEXPORT)]
    NotGmsh,
    /// A format version other than 4.1.
    #[error(
        "Gmsh format {0} is not supported: re-export with `-format msh41` \
         (or `Mesh.MshFileVersion = 4.1;`)"
    )]
    UnsupportedVersion(String),
    /// The file ends before `$EndMeshFormat`.
    #[error("the file ends inside `$MeshFormat`; {r}", r = REEXPORT)]
    TruncatedHeader,
    /// A `$PhysicalNames` section without its `$EndPhysicalNames`.
    #[error("`$PhysicalNames` has no `$EndPhysicalNames`; {r}", r = REEXPORT)]
    UnterminatedPhysicalNames,
    /// A `$PhysicalNames` line that is not `dim tag "name"`.
    #[error("`$PhysicalNames` line `{0}` is not `dim tag \"name\"`; {r}", r = REEXPORT)]
    BadPhysicalName(String),
    #[error(
        "`$PhysicalNames` announces {announced} names but lists {listed}; {r}",
        r = REEXPORT
    )]
    /// The count on the first line of `$PhysicalNames` differs from the lines that follow.
    PhysicalNameCount {
        /// The number of names the section's first line announces.
        announced: usize,
        /// The number of name lines the section holds.
        listed: usize,
    },
    /// The parser stopped at `place` (a line, or a byte of a binary file, and the sections
    /// around it) for the reason `reason`.
    #[error(
        "parse error at {place}: {reason}. The file is damaged or truncated; {r}",
        r = REEXPORT
    )]
    Parse {
        /// Where the parser stopped: a line (ASCII) or byte offset (binary), with the section.
        place: String,
        /// What the parser expected there.
        reason: String,
    },
    /// The parser failed without saying where.
    #[error("the file is malformed; {r}", r = REEXPORT)]
    Malformed,
    /// The parser crashed (a panic in `mshio`, caught) on a malformed file.
    #[error("the file is malformed (the parser gave up); {r}", r = REEXPORT)]
    ParserGaveUp,
    /// A node tag listed twice in the `$Nodes` block of entity `dim:tag`.
    #[error(
        "a node tag appears twice in the `$Nodes` block of entity {dim}:{tag}; {r}",
        r = REEXPORT
    )]
    RepeatedTagInBlock {
        /// Dimension of the entity (0 to 3).
        dim: i32,
        /// Tag of the entity.
        tag: i32,
    },
    /// A node tag defined twice in `$Nodes`; holds the tag.
    #[error(
        "node tag {0} is defined twice in `$Nodes`: every node needs a tag of its own; {r}",
        r = REEXPORT
    )]
    RepeatedNodeTag(u64),
    /// Node tag 0 in the `$Nodes` block of entity `dim:tag`; Gmsh reserves it.
    #[error(
        "the `$Nodes` block of entity {dim}:{tag} lists node tag 0, which Gmsh reserves (tags \
         start at 1); {r}",
        r = REEXPORT
    )]
    ZeroNodeTag {
        /// Dimension of the entity (0 to 3).
        dim: i32,
        /// Tag of the entity.
        tag: i32,
    },
    /// The node tags of `$Nodes` could not be read back from the file after mshio parsed it
    /// (mshio drops them when they are dense); a bug of this reader, or a file it cannot follow.
    #[error("the node tags of `$Nodes` could not be read back from the file; {r}", r = REEXPORT)]
    NodeTagsUnreadable,
    /// Quadratic tetrahedra in volume `entity`.
    #[error(
        "volume {entity} holds quadratic tetrahedra (type 11); only linear tetrahedra \
         (type 4) are supported: re-mesh with `-order 1` (`Mesh.ElementOrder = 1;`)"
    )]
    QuadraticTetrahedra {
        /// Tag of the volume entity.
        entity: i32,
    },
    /// Volume elements other than tetrahedra (`kind`, Gmsh type `code`) in volume `entity`.
    #[error(
        "volume {entity} holds {kind} elements (type {code}); only linear tetrahedra (type 4) \
         are supported: re-mesh the volume with tetrahedra (no `Recombine`)"
    )]
    OtherVolumeElements {
        /// Tag of the volume entity.
        entity: i32,
        /// Name of the element type, e.g. "hexahedron".
        kind: String,
        /// Gmsh's element type number.
        code: i32,
    },
    /// Element `element` refers to node tag `tag`, which `$Nodes` does not define.
    #[error(
        "element {element} refers to node tag {tag}, which `$Nodes` does not define; {r}",
        r = REEXPORT
    )]
    UnknownNode {
        /// Tag of the element in the file.
        element: u64,
        /// The node tag it refers to.
        tag: u64,
    },
    #[error(
        "the file holds no linear tetrahedra (type 4): mesh the volume in 3D (`gmsh -3`) and, \
         when physical groups are defined, put the volume in one (Gmsh then saves only elements \
         of physical groups)"
    )]
    /// The file holds no linear tetrahedra (a surface mesh, or the volume outside every
    /// physical group).
    NoTetrahedra,
    /// More nodes than `u32` node indices can address.
    #[error("the mesh has more than 2^32 nodes, beyond u32 node ids")]
    TooManyNodes,
}
