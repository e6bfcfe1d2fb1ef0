// Unnotched beam D = 50 mm of Gregoire, Rojas-Solano & Pijaudier-Cabot (2013) for
// cases/beam/unnotched-gregoire-d50.yaml: 175 x 50 x 50 mm (length 3.5 D, depth D, width 50 mm),
// supports 125 mm apart (2.5 D) at x = 25 and 150 mm, no notch.
// x along the span, y up, z across; SI units (metres); linear tetrahedra.
// From this folder, with Gmsh 4.15.2:
//   gmsh unnotched_beam.geo -3 -format msh41 -bin -o unnotched_beam_d50.msh
// (or ./generate.sh).
//
// Structured as the half-notched beam's mesh (../notched-beam/notched_beam.geo): cells of 5 mm
// in x and y and 10 mm in z (one transfinite block, each cell split into tetrahedra by Gmsh), so
// the two calibration beams of the batch see the same element size (h = (6 V)^(1/3) = 6.3 mm).
// Node lines used by the case: supports x = 25 and 150 mm at y = 0; loading x = 85 and 90 mm at
// y = 50 mm; the CMOD gauge's ends x = 50 and 125 mm at y = 0 (75 mm, centred at mid-span).
//
// Physical group (the solver's reader turns it into a node set of the same name):
//   Volume "beam": all tetrahedra, hence all nodes.
SetFactory("OpenCASCADE");

L = 0.175;   // length, x
D = 0.05;    // depth, y
W = 0.05;    // width, z
hx = 0.005;  // cell sizes
hy = 0.005;
hz = 0.010;

Box(1) = {0, 0, 0, L, D, W};

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

Physical Volume("beam") = {1};
