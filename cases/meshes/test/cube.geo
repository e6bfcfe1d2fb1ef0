// Unit cube meshed with Gmsh, source of cube_gmsh.msh (ASCII) and cube_gmsh_bin.msh (binary).
// Regenerate from this folder (Gmsh 4.8.4) with:
//   gmsh cube.geo -3 -format msh41 -o cube_gmsh.msh
//   gmsh cube.geo -3 -format msh41 -bin -o cube_gmsh_bin.msh
// and the reader's error cases with:
//   gmsh cube.geo -3 -format msh22 -o cube_v22.msh
//   gmsh cube.geo -2 -format msh41 -o cube_surface_only.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
// Coarse on purpose: the files stay small and readable.
Mesh.MeshSizeMin = 1;
Mesh.MeshSizeMax = 1;
Physical Point("origin") = {2};
Physical Surface("bottom") = {5};
Physical Surface(7) = {6};
Physical Volume("solid") = {1};
