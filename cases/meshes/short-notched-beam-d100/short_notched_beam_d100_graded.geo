// Beam D = 100 mm notched to D / 5 of Gregoire, Rojas-Solano & Pijaudier-Cabot (2013), the
// blind prediction of cases/beam/short-notched-gregoire-d100.yaml: 350 x 100 x 50 mm (length
// 3.5 D, width 50 mm), supports 250 mm apart (x = 50 and 300 mm), a notch 20 mm deep and 1.25 mm
// wide at mid-span (x = 175 mm). The graded mesh of ../notched-beam/notched_beam_graded.geo
// scaled to this beam: the ligament over the notch a structured strip of hb x hb squares (the
// crack band), triangles of ht at the notch tip's corners growing to hm within rm of mid-span
// and to hf beyond, extruded across the width in nz layers (three tetrahedra a prism).
// x along the span, y up, z across; SI units (metres); linear tetrahedra.
// From this folder, with Gmsh 4.15.2:
//   gmsh short_notched_beam_d100_graded.geo -3 -format msh41 -bin -o short_notched_beam_d100_graded.msh
// (or ./generate.sh). Each parameter can be set from the command line (-setnumber hb 0.000625).
//
// Physical group (the solver's reader turns it into a node set of the same name):
//   Volume "beam": all tetrahedra, hence all nodes.

L = 0.35;   // length, x
D = 0.1;    // depth, y
W = 0.05;    // width, z
If (!Exists(nw)) nw = 0.00125; EndIf  // notch width, centred on x = 175 mm
x0 = 0.175 - nw / 2;
x1 = 0.175 + nw / 2;
a0 = 0.02;   // notch depth, D / 5
If (!Exists(hb)) hb = 0.00125; EndIf  // the ligament strip's squares (crack band)
If (!Exists(ht)) ht = 0.00125; EndIf  // at the notch tip's corners
If (!Exists(hm)) hm = 0.0025; EndIf    // within rm of the notch's mid-plane
If (!Exists(rm)) rm = 0.05; EndIf     // half-width of the hm box
If (!Exists(hf)) hf = 0.005; EndIf     // elsewhere
If (!Exists(nz)) nz = 5; EndIf         // layers across the width (10 mm)

// The outline less the notch, with points at the supports (x = 50 and 300 mm, y = 0) and the
// notch mouth and tip; the strip's sides 4-11 and 5-10 split the beam in three surfaces.
Point(1) = {0, 0, 0};
Point(2) = {0.05, 0, 0};
Point(3) = {x0, 0, 0};
Point(4) = {x0, a0, 0};
Point(5) = {x1, a0, 0};
Point(6) = {x1, 0, 0};
Point(7) = {0.3, 0, 0};
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
Plane Surface(1) = {1};              // the ligament strip
Curve Loop(2) = {1, 2, 3, 14, 11, 12};
Plane Surface(2) = {2};              // left of it
Curve Loop(3) = {5, 6, 7, 8, 9, -13};
Plane Surface(3) = {3};              // right of it

Transfinite Curve{4, 10} = Round((x1 - x0) / hb) + 1;
Transfinite Curve{13, 14} = Round((D - a0) / hb) + 1;
Transfinite Surface{1};

// Size: ht at the tip's corners growing by 0.15 per unit distance to hf, and at most hm in the
// box |x - 175 mm| < rm (Gmsh's Box field, blending into hf over 10 mm).
Field[1] = Distance;
Field[1].PointsList = {4, 5};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = ht;
Field[2].SizeMax = hf;
Field[2].DistMin = 0.001;
Field[2].DistMax = 0.001 + (hf - ht) / 0.15;
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
