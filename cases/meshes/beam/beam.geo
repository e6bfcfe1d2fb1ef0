// Plain concrete beam of the thesis (chapter 10.3, Fig. 10.5) meshed with unstructured Delaunay
// tetrahedra of about 50 mm, for the mesh-objectivity check of beam/static-3pt (issue 16):
// 3000 x 600 x 300 mm, x along the span, y up, z across; SI units (metres), linear tetrahedra.
// From this folder, with Gmsh 4.15.2:
//   gmsh beam.geo -3 -format msh41 -bin -o beam_50mm.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// So that the box selectors of the structured case pick the same lines of nodes, lines are
// imprinted on the faces, each divided into six equal segments (nodes every 50 mm in z,
// z = 0.15 included):
//   bottom face y = 0: x = 0.05, 0.10, 0.15 (left support strip; the pin at (0.10, 0, 0.15))
//                      x = 1.50 (mid-span, under the load: the probe `midspan_bottom`);
//                      x = 2.85, 2.90, 2.95 (right support strip; the pin at (2.90, 0, 0.15));
//   top face y = 0.6:  x = 1.35, 1.40, ..., 1.65 (the 300 mm loading plate).
//
// Physical group (the solver's reader turns it into a node set of the same name):
//   Volume "beam": all tetrahedra, hence all nodes.
SetFactory("OpenCASCADE");

L = 3.0;   // span direction x (m)
H = 0.6;   // depth, y
W = 0.3;   // width, z
h = 0.05;  // nominal element size (m)
nz = 6;    // segments of each imprinted line across the width (50 mm)

Box(1) = {0, 0, 0, L, H, W};

// The imprinted lines, across the width (z from 0 to W).
xs_bottom[] = {0.05, 0.10, 0.15, 1.50, 2.85, 2.90, 2.95};
xs_top[] = {1.35, 1.40, 1.45, 1.50, 1.55, 1.60, 1.65};
lines[] = {};
p = 100;
c = 100;
For i In {0 : #xs_bottom[] - 1}
  Point(p) = {xs_bottom[i], 0, 0};
  Point(p + 1) = {xs_bottom[i], 0, W};
  Line(c) = {p, p + 1};
  lines[] += {c};
  p += 2;
  c += 1;
EndFor
For i In {0 : #xs_top[] - 1}
  Point(p) = {xs_top[i], H, 0};
  Point(p + 1) = {xs_top[i], H, W};
  Line(c) = {p, p + 1};
  lines[] += {c};
  p += 2;
  c += 1;
EndFor
// Imprint them: the bottom and top faces split into strips, the volume stays whole, and the
// edges along x of those faces get a vertex at each line's end.
BooleanFragments{ Volume{1}; Delete; }{ Curve{lines[]}; Delete; }
volumes() = Volume{:};
If (#volumes() != 1)
  Error("imprinting the lines failed: %g volumes", #volumes());
  Abort;
EndIf

// Each imprinted line: nz equal segments. A line at x lies in the box {x} x {0 or H} x [0, W];
// the box edges along z sit at x = 0 and x = L, away from every such box.
e = 1e-6;
For i In {0 : #xs_bottom[] - 1}
  cs() = Curve In BoundingBox{xs_bottom[i] - e, -e, -e, xs_bottom[i] + e, e, W + e};
  If (#cs() != 1)
    Error("bottom line x = %g: %g curves", xs_bottom[i], #cs());
    Abort;
  EndIf
  Transfinite Curve{cs()} = nz + 1;
EndFor
For i In {0 : #xs_top[] - 1}
  cs() = Curve In BoundingBox{xs_top[i] - e, H - e, -e, xs_top[i] + e, H + e, W + e};
  If (#cs() != 1)
    Error("top line x = %g: %g curves", xs_top[i], #cs());
    Abort;
  EndIf
  Transfinite Curve{cs()} = nz + 1;
EndFor

// The strips between neighbouring lines (left and right supports, loading plate): structured,
// one 50 mm segment along x and nz across, so that no node falls between two lines (a box
// selector then picks exactly the nodes on the lines, and a strip splits into lines of nodes).
strips[] = {0.05, 0.15, 0,   // {x from, x to, y}
            2.85, 2.95, 0,
            1.35, 1.65, H};
For i In {0 : #strips[] / 3 - 1}
  x0 = strips[3 * i];
  x1 = strips[3 * i + 1];
  y0 = strips[3 * i + 2];
  // The box edges along x between the strip's first and last line, at z = 0 and z = W.
  edges() = Curve In BoundingBox{x0 - e, y0 - e, -e, x1 + e, y0 + e, e};
  edges() += Curve In BoundingBox{x0 - e, y0 - e, W - e, x1 + e, y0 + e, W + e};
  faces() = Surface In BoundingBox{x0 - e, y0 - e, -e, x1 + e, y0 + e, W + e};
  n = Round((x1 - x0) / 0.05);
  If (#edges() != 2 * n || #faces() != n)
    Error("strip x = %g to %g: %g edges, %g faces", x0, x1, #edges(), #faces());
    Abort;
  EndIf
  Transfinite Curve{edges()} = 2;
  Transfinite Surface{faces()};
EndFor

// Sizes: h everywhere, from no other source.
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// Frontal-Delaunay surfaces, Delaunay volumes, linear elements, optimised, on one thread with
// a fixed seed (a rerun with this Gmsh gives the same file).
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.ElementOrder = 1;
Mesh.Optimize = 1;
Mesh.OptimizeThreshold = 0.6;
Mesh.RandomSeed = 1;
General.NumThreads = 1;
Mesh.MaxNumThreads1D = 1;
Mesh.MaxNumThreads2D = 1;
Mesh.MaxNumThreads3D = 1;

Physical Volume("beam") = {volumes()};
