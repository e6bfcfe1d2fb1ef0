// Half-notched beam D = 50 mm of Gregoire, Rojas-Solano & Pijaudier-Cabot (2013) for
// cases/beam/notched-gregoire-d50.yaml: 175 x 50 x 50 mm (length 3.5 D, depth D, width 50 mm),
// supports 125 mm apart (2.5 D) at x = 25 and 150 mm, a notch of depth D / 2 at mid-span.
// x along the span, y up, z across; SI units (metres); linear tetrahedra.
// From this folder, with Gmsh 4.15.2:
//   gmsh notched_beam.geo -3 -format msh41 -bin -o notched_beam_d50.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// Structured: cells of 5 mm in x and y and 10 mm in z (transfinite blocks, each cell split into
// tetrahedra by Gmsh). The notch is one cell wide, x = 85 to 90 mm (the saw cut of the tests
// was narrower; the notch tip is what the peak load sees), from y = 0 to 25 mm: the beam is
// the union of five blocks that leave the notch out, so its faces are free surfaces.
// Node lines used by the case: supports x = 25 and 150 mm at y = 0; loading x = 85 and 90 mm
// at y = 50 mm (above the notch); crack mouth x = 85 and 90 mm at y = 0 (the CMOD).
//
// Physical group (the solver's reader turns it into a node set of the same name):
//   Volume "beam": all tetrahedra, hence all nodes.
SetFactory("OpenCASCADE");

L = 0.175;   // length, x
D = 0.05;    // depth, y
W = 0.05;    // width, z
x0 = 0.085;  // notch from x0 to x1, y from 0 to a0
x1 = 0.090;
a0 = 0.025;
hx = 0.005;  // cell sizes
hy = 0.005;
hz = 0.010;

Box(1) = {0, 0, 0, x0, a0, W};            // left, below the notch tip
Box(2) = {0, a0, 0, x0, D - a0, W};       // left, above
Box(3) = {x0, a0, 0, x1 - x0, D - a0, W}; // over the notch
Box(4) = {x1, 0, 0, L - x1, a0, W};       // right, below
Box(5) = {x1, a0, 0, L - x1, D - a0, W};  // right, above
BooleanFragments{ Volume{1:5}; Delete; }{}
volumes() = Volume{:};
If (#volumes() != 5)
  Error("fragmenting the blocks gave %g volumes", #volumes());
  Abort;
EndIf

// Every curve is parallel to an axis: divide it into cells of that axis's size.
curves() = Curve{:};
For i In {0 : #curves() - 1}
  bb() = BoundingBox Curve{curves(i)};
  lx = bb(3) - bb(0);
  ly = bb(4) - bb(1);
  lz = bb(5) - bb(2);
  n = Round(lx / hx + ly / hy + lz / hz);
  Transfinite Curve{curves(i)} = n + 1;
EndFor
Transfinite Surface{:};
Transfinite Volume{:};

Mesh.ElementOrder = 1;
Mesh.RandomSeed = 1;
General.NumThreads = 1;

Physical Volume("beam") = {volumes()};
