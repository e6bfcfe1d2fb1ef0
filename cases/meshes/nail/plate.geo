// Steel plate of the thesis' penetration case (chapter 10.4): 100 x 100 mm, 10 mm thick, lying on
// the concrete block's top face with a central circular opening of diameter 12 mm for the nail.
// A QUARTER of it by symmetry: x in [0, 0.05], z in [0, 0.05], y in [0.5001, 0.5101] (m): 0.1 mm
// above the block (y = 0.5) so that the faces do not coincide; the opening is centred on the axis
// x = 0, z = 0. The thesis gives no plate dimensions; these are our choice (README.md).
// SI units (metres), linear tetrahedra: h_hole (2 mm) at the opening, growing linearly with the
// distance from the axis to h_edge (5 mm) at the plate's outer edges.
// From this folder, with Gmsh 4.15.2:
//   gmsh plate.geo -3 -format msh41 -bin -o plate.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// Physical groups (the solver's reader turns each into a node set of the same name):
//   Volume  "plate" : all tetrahedra, hence all nodes;
//   Surface "sym_x" : the cut face on the plane x = 0;
//   Surface "sym_z" : the cut face on the plane z = 0;
//   Surface "top"   : y = 0.5101 (the face away from the block).
SetFactory("OpenCASCADE");

B = 0.05;         // half the plate's side (m)
T = 0.010;        // thickness
y0 = 0.5001;      // underside, 0.1 mm above the block
R = 0.006;        // radius of the opening
h_hole = 0.002;   // element size at the opening
h_edge = 0.005;   // element size at the outer edges

Box(1) = {0, y0, 0, B, T, B};
Cylinder(2) = {0, y0 - T, 0, 0, 3 * T, 0, R};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }

volumes() = Volume{:};
e = 1e-6;
sym_x() = Surface In BoundingBox{-e, y0 - e, -e, e, y0 + T + e, B + e};
sym_z() = Surface In BoundingBox{-e, y0 - e, -e, B + e, y0 + T + e, e};
top() = Surface In BoundingBox{-e, y0 + T - e, -e, B + e, y0 + T + e, B + e};
If (#volumes() != 1 || #sym_x() != 1 || #sym_z() != 1 || #top() != 1)
  Error("plate: %g volumes, %g sym_x, %g sym_z, %g top", #volumes(), #sym_x(), #sym_z(), #top());
  Abort;
EndIf
Physical Volume("plate") = {volumes()};
Physical Surface("sym_x") = {sym_x()};
Physical Surface("sym_z") = {sym_z()};
Physical Surface("top") = {top()};

// Size: h_hole at the opening (radius R from the axis), growing linearly with the distance from
// the axis to h_edge at the middle of an outer edge (B from the axis).
Field[1] = MathEval;
Field[1].F = "Sqrt(x * x + z * z)";
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_hole;
Field[2].SizeMax = h_edge;
Field[2].DistMin = R;
Field[2].DistMax = B;
Background Field = 2;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h_edge;
Mesh.Algorithm = 6;             // Frontal-Delaunay surfaces
Mesh.Algorithm3D = 1;           // Delaunay volumes
Mesh.ElementOrder = 1;
Mesh.Optimize = 1;
Mesh.OptimizeThreshold = 0.6;
Mesh.RandomSeed = 1;
General.NumThreads = 1;         // reproducible
Mesh.MaxNumThreads1D = 1;
Mesh.MaxNumThreads2D = 1;
Mesh.MaxNumThreads3D = 1;
