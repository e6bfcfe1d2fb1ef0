// Concrete block of the thesis' penetration case (chapter 10.4), 500 x 500 x 500 mm, a QUARTER of
// it by symmetry: x in [0, 0.25], y in [0, 0.5], z in [0, 0.25] (m). The nail hits the top face
// y = 0.5 at the corner (0, 0.5, 0), along -y; the nail's axis is the line x = 0, z = 0.
// SI units (metres), linear tetrahedra, graded: h_fine (1.5 mm) within r_fine (10 mm) of the
// impact point, growing linearly with the distance (0.08 mm per mm) towards h_far (45 mm), which
// it nearly reaches at the far faces (about 40 mm on the bottom face, 0.5 m away).
// Parameter fine_depth (default 0): the fine zone is the set of points within r_fine of the
// segment of the axis from y = 0.5 down to y = 0.5 - fine_depth (a ball about the impact point
// for 0); e.g. -setnumber fine_depth 0.02 refines along the first 20 mm of the nail's path.
// Parameters h_fine (default 0.0015), r_fine (0.010) and growth (0.08): the fine zone's element
// size and radius, and the growth of the size beyond it. block-path.msh, the block of the nail
// case, is 0.5 mm within 4 mm of the nail's path for 25 mm, growing by 0.2 mm per mm:
//   gmsh block.geo -3 -format msh41 -bin -setnumber h_fine 0.0005 -setnumber r_fine 0.004
//        -setnumber growth 0.2 -setnumber fine_depth 0.025 -o block-path.msh
// Parameters pilot_radius, pilot_depth (default 0: none) and h_pilot (0.4 mm): a pilot hole about
// the axis from the top face down to pilot_depth, meshed at h_pilot on its wall (README.md: an
// experiment of issue 21, not used by a case).
// From this folder, with Gmsh 4.15.2:
//   gmsh block.geo -3 -format msh41 -bin -o block.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// Physical groups (the solver's reader turns each into a node set of the same name):
//   Volume  "block"  : all tetrahedra, hence all nodes;
//   Surface "sym_x"  : the symmetry plane x = 0;
//   Surface "sym_z"  : the symmetry plane z = 0;
//   Surface "bottom" : y = 0;
//   Surface "top"    : y = 0.5 (the impacted face).
SetFactory("OpenCASCADE");
DefineConstant[ fine_depth = {0, Name "Parameters/fine_depth"} ];
DefineConstant[ pilot_radius = {0, Name "Parameters/pilot_radius"} ];
DefineConstant[ pilot_depth = {0, Name "Parameters/pilot_depth"} ];
DefineConstant[ h_pilot = {0.0004, Name "Parameters/h_pilot"} ];
DefineConstant[ h_fine = {0.0015, Name "Parameters/h_fine"} ];
DefineConstant[ r_fine = {0.010, Name "Parameters/r_fine"} ];
DefineConstant[ growth = {0.08, Name "Parameters/growth"} ];

B = 0.25;         // half the block's length and width (m)
H = 0.5;          // height
// h_fine: the element size near the impact point, within r_fine of it (parameters, above).
h_far = 0.045;    // element size far from it
// growth: sizes grow by this many mm per mm of distance beyond r_fine (a parameter, above)

Box(1) = {0, 0, 0, B, H, B};
If (pilot_radius > 0)
  // The pilot hole along the nail's path: a cylinder about the axis x = z = 0 from the top face
  // down to pilot_depth, of which the box keeps the quarter.
  Cylinder(2) = {0, H - pilot_depth, 0, 0, pilot_depth + 0.001, 0, pilot_radius};
  BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
EndIf
volumes() = Volume{:};
e = 1e-6;
sym_x() = Surface In BoundingBox{-e, -e, -e, e, H + e, B + e};
sym_z() = Surface In BoundingBox{-e, -e, -e, B + e, H + e, e};
bottom() = Surface In BoundingBox{-e, -e, -e, B + e, e, B + e};
top() = Surface In BoundingBox{-e, H - e, -e, B + e, H + e, B + e};
If (#volumes() != 1 || #sym_x() != 1 || #sym_z() != 1 || #bottom() != 1 || #top() != 1)
  Error("block: %g volumes, %g sym_x, %g sym_z, %g bottom, %g top", #volumes(), #sym_x(),
        #sym_z(), #bottom(), #top());
  Abort;
EndIf
Physical Volume("block") = {volumes()};
Physical Surface("sym_x") = {sym_x()};
Physical Surface("sym_z") = {sym_z()};
Physical Surface("bottom") = {bottom()};
Physical Surface("top") = {top()};

// Distance to the segment x = z = 0, y in [H - fine_depth, H] (exact, analytic), then the size
// h_fine up to r_fine, growing linearly to h_far at r_fine + (h_far - h_fine) / growth.
Field[1] = MathEval;
Field[1].F = Sprintf("Sqrt(x * x + z * z + Max(%.17g - y, 0)^2 + Max(y - %.17g, 0)^2)",
                     H - fine_depth, H);
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_fine;
Field[2].SizeMax = h_far;
Field[2].DistMin = r_fine;
Field[2].DistMax = r_fine + (h_far - h_fine) / growth;
If (pilot_radius > 0)
  // h_pilot on the hole's wall (a few segments on its quarter circle), growing to h_fine.
  Field[3] = MathEval;
  Field[3].F = Sprintf("Sqrt(x * x + z * z) - %.17g + Max(%.17g - y, 0)", pilot_radius, H - pilot_depth);
  Field[4] = Threshold;
  Field[4].InField = 3;
  Field[4].SizeMin = h_pilot;
  Field[4].SizeMax = h_fine;
  Field[4].DistMin = 0;
  Field[4].DistMax = (h_fine - h_pilot) / 0.3;
  Field[4].StopAtDistMax = 1;  // beyond it, the size of Field[2]
  Field[5] = Min;
  Field[5].FieldsList = {2, 4};
  Background Field = 5;
Else
  Background Field = 2;
EndIf

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h_far;
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
