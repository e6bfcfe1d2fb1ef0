//! Gmsh reader (in progress)
