// Unnotched beam D = 50 mm of Gregoire, Rojas-Solano & Pijaudier-Cabot (2013), graded toward
// mid-span: the geometry and node lines of unnotched_beam.geo, meshed as the half-notched beam's
// graded mesh (../notched-beam/notched_beam_graded.geo) so that both beams of the batch see the
// same crack band.
// x along the span, y up, z across; SI units (metres); linear tetrahedra.
// From this folder, with Gmsh 4.15.2:
//   gmsh unnotched_beam_graded.geo -3 -format msh41 -bin -o unnotched_beam_d50_graded.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// In the plane x-y: the column under the loading platen, x = 85 to 90 mm over the full depth
// (where the crack runs up from the bottom face), is a structured strip of hb x hb squares, so
// that every element of the crack band has one size; elsewhere triangles of size hb at the
// strip's corners growing to hm within rm of mid-span and to hf beyond (Frontal-Delaunay). The
// plane mesh is extruded across the width in nz layers, each prism split into three tetrahedra.
// Each parameter can be set from the command line (gmsh ... -setnumber hb 0.00125).
//
// Physical group (the solver's reader turns it into a node set of the same name):
//   Volume "beam": all tetrahedra, hence all nodes.

L = 0.175;   // length, x
D = 0.05;    // depth, y
If (!Exists(W)) W = 0.05; EndIf  // width, z
x0 = 0.085;  // the strip (and the loading platen) from x0 to x1
x1 = 0.090;
If (!Exists(hb)) hb = 0.000625; EndIf  // the strip's squares (crack band)
If (!Exists(hm)) hm = 0.0025; EndIf    // within rm of mid-span
If (!Exists(rm)) rm = 0.025; EndIf
If (!Exists(hf)) hf = 0.005; EndIf     // elsewhere
If (!Exists(nz)) nz = 5; EndIf         // layers across the width (10 mm)
If (!Exists(gr)) gr = 0.15; EndIf      // growth of the size per unit distance from the strip

// The outline with points at the supports (x = 25 and 150 mm, y = 0) and the CMOD gauge's ends
// (x = 50 and 125 mm, y = 0); the strip's sides 4-13 and 5-12 split the beam in three surfaces.
Point(1) = {0, 0, 0};
Point(2) = {0.025, 0, 0};
Point(3) = {0.050, 0, 0};
Point(4) = {x0, 0, 0};
Point(5) = {x1, 0, 0};
Point(6) = {0.125, 0, 0};
Point(7) = {0.150, 0, 0};
Point(8) = {L, 0, 0};
Point(9) = {L, D, 0};
Point(10) = {x1, D, 0};
Point(11) = {x0, D, 0};
Point(12) = {0, D, 0};
For i In {1 : 11}
  Line(i) = {i, i + 1};
EndFor
Line(12) = {12, 1};
Line(13) = {5, 10};
Line(14) = {4, 11};
Curve Loop(1) = {4, 13, 10, -14};
Plane Surface(1) = {1};              // the strip
Curve Loop(2) = {1, 2, 3, 14, 11, 12};
Plane Surface(2) = {2};              // left of it
Curve Loop(3) = {5, 6, 7, 8, 9, -13};
Plane Surface(3) = {3};              // right of it

Transfinite Curve{4, 10} = Round((x1 - x0) / hb) + 1;
Transfinite Curve{13, 14} = Round(D / hb) + 1;
Transfinite Surface{1};

// Size: hb on the strip's sides growing by 0.15 per unit distance to hf, and at most hm in the
// box |x - 87.5 mm| < rm (Gmsh's Box field, blending into hf over 10 mm).
Field[1] = Distance;
Field[1].CurvesList = {13, 14};
Field[1].Sampling = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hb;
Field[2].SizeMax = hf;
Field[2].DistMin = 0.0005;
Field[2].DistMax = 0.0005 + (hf - hb) / gr;
Field[3] = Box;
Field[3].VIn = hm;
Field[3].VOut = hf;
Field[3].XMin = (x0 + x1) / 2 - rm;
Field[3].XMax = (x0 + x1) / 2 + rm;
Field[3].YMin = 0;
Field[3].YMax = D;
Field[3].ZMin = -1;
Field[3].ZMax = 1;
Field[3].Thickness = 0.01;
Field[4] = Min;
Field[4].FieldsList = {2, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;

volumes[] = {};
For s In {1 : 3}
  out[] = Extrude {0, 0, W} { Surface{s}; Layers{nz}; };
  volumes[] += out[1];
EndFor

Mesh.ElementOrder = 1;
Mesh.RandomSeed = 1;
General.NumThreads = 1;

Physical Volume("beam") = {volumes[]};
