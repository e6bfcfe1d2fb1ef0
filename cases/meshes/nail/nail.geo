// Steel nail of the thesis' penetration case (chapter 10.4), a QUARTER of it by symmetry (x >= 0,
// z >= 0), axis on the line x = 0, z = 0, pointing down (-y) at the concrete block's top face
// y = 0.5. SI units (metres), linear tetrahedra of about 1 mm. The thesis gives no nail
// dimensions; these are those of a powder-actuated fastener (README.md): a cylindrical shank of
// diameter d = 4 mm and length 40 mm behind a tangent-ogive nose of caliber-radius-head psi = 3
// (arc radius s = psi d = 12 mm, nose length l = d sqrt(psi - 1/4) = 6.633 mm), no head. The tip
// sits 0.5 mm above the block: at (0, 0.5005, 0); the nail extends along +y up to
// y = 0.5005 + l + 0.040.
// From this folder, with Gmsh 4.15.2:
//   gmsh nail.geo -3 -format msh41 -bin -o nail.msh
// (or ./generate.sh). README.md lists what the mesh achieves.
//
// Physical groups (the solver's reader turns each into a node set of the same name):
//   Volume  "nail"  : all tetrahedra, hence all nodes;
//   Surface "sym_x" : the cut face on the plane x = 0;
//   Surface "sym_z" : the cut face on the plane z = 0;
//   Point   "tip"   : the node at the tip (0, 0.5005, 0).
SetFactory("OpenCASCADE");

a = 0.002;                  // shank radius (m), d = 2 a = 4 mm
psi = 3;                    // caliber-radius-head of the ogive
s = psi * 2 * a;            // ogive arc radius, 12 mm
l = Sqrt(s^2 - (s - a)^2);  // nose length, = d sqrt(psi - 1/4) = 6.633 mm
L = 0.040;                  // shank length
y_tip = 0.5005;             // tip, 0.5 mm above the block's top face y = 0.5
h = 0.001;                  // element size on the shank
h_tip = 0.001;              // element size at the tip: h too. With 0.6 mm the smallest altitude
                            // (at the tip) halves, 0.296 -> 0.146 mm, and so does the time step.
r_tip = 0.002;              // h_tip within this distance of the tip, then growing to h
growth = 0.15;              // by at most 0.15 mm per mm of distance

// The profile in the plane z = 0 (x radial, y axial): the tangent-ogive arc from the tip to the
// shank (centre on the far side of the axis, at x = -(s - a), level with the nose's base, so the
// arc meets the shank tangentially), the shank's side, its top, and back down the axis.
Point(1) = {0, y_tip, 0};
Point(2) = {a, y_tip + l, 0};
Point(3) = {-(s - a), y_tip + l, 0};  // the arc's centre (construction only)
Point(4) = {a, y_tip + l + L, 0};
Point(5) = {0, y_tip + l + L, 0};
Circle(1) = {1, 3, 2};
Line(2) = {2, 4};
Line(3) = {4, 5};
Line(4) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// Revolve a quarter turn about the axis. A positive turn about +y takes +x to -z, so the turn is
// negative: the profile sweeps from the plane z = 0 to the plane x = 0 through x, z >= 0.
Extrude {{0, 1, 0}, {0, 0, 0}, -Pi / 2} { Surface{1}; }
Recursive Delete { Point{3}; }

volumes() = Volume{:};
e = 1e-5;  // OCC bounding boxes carry a tolerance: search boxes this much wider
y_top = y_tip + l + L;
sym_x() = Surface In BoundingBox{-e, y_tip - e, -e, e, y_top + e, a + e};
sym_z() = Surface In BoundingBox{-e, y_tip - e, -e, a + e, y_top + e, e};
tip() = Point In BoundingBox{-e, y_tip - e, -e, e, y_tip + e, e};
If (#volumes() != 1 || #sym_x() != 1 || #sym_z() != 1 || #tip() != 1)
  Error("nail: %g volumes, %g sym_x, %g sym_z, %g tip points", #volumes(), #sym_x(), #sym_z(),
        #tip());
  Abort;
EndIf
Physical Volume("nail") = {volumes()};
Physical Surface("sym_x") = {sym_x()};
Physical Surface("sym_z") = {sym_z()};
Physical Point("tip") = {tip()};

// Size: h_tip within r_tip of the tip, growing linearly to h (uniform h as set here).
Field[1] = Distance;
Field[1].PointsList = {tip()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_tip;
Field[2].SizeMax = h;
Field[2].DistMin = r_tip;
Field[2].DistMax = r_tip + (h - h_tip) / growth;
Background Field = 2;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h;
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
