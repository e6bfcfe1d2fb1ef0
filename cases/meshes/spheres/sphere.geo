// Elastic sphere of the Hertz impact benchmark (contact table of the CATALOGUE): radius 50 mm,
// centred at the origin, SI units (metres), linear tetrahedra, refined around the contact pole
// P = (R, 0, 0) on +x. The other sphere of the benchmark is this mesh turned half a turn (about y
// or z) by the harness: a reflection (x -> -x) would turn every tetrahedron inside out.
//
// Parameter `level` (0 = coarse, 1 = medium, 2 = fine), set on the command line; from this
// folder, with Gmsh 4.8.4:
//   gmsh sphere.geo -setnumber level 0 -3 -format msh41 -bin -o sphere_coarse.msh
//   gmsh sphere.geo -setnumber level 1 -3 -format msh41 -bin -o sphere_medium.msh
//   gmsh sphere.geo -setnumber level 2 -3 -format msh41 -bin -o sphere_fine.msh
// (or ./generate.sh). README.md lists what each level achieves.
//
// Physical groups (the solver's reader turns each into a node set of the same name):
//   Volume  "sphere"   : the whole ball;
//   Surface "pole"     : the spherical cap within 20 mm (straight-line distance) of P, that is
//                        x >= 46 mm (rim radius 19.6 mm);
//   Point   "pole_tip" : the node at P itself.
SetFactory("OpenCASCADE");
DefineConstant[ level = {1, Choices{0 = "coarse", 1 = "medium", 2 = "fine"},
                         Name "Parameters/level"} ];
If (level != 0 && level != 1 && level != 2)
  Error("level must be 0 (coarse), 1 (medium) or 2 (fine), not %g", level);
  Abort;
EndIf

R = 0.05;                       // sphere radius (m)
d_cap = 0.02;                   // the "pole" cap: surface points within d_cap of P
x_cap = R - d_cap^2 / (2 * R);  // = 0.046 m: the plane of the cap's rim

// Per level: element size at the pole, inside the ball far from it, and on the surface far
// from it. The surface size is capped below the interior one because flat facets cut the ball's
// volume by about 3 h^2 / (8 R^2) (1.5 % for h = 12 mm, as the coarse level first had).
h_pole_l[] = {0.003, 0.002, 0.0014};
h_far_l[]  = {0.012, 0.009, 0.007};
h_surf_l[] = {0.008, 0.006, 0.0045};
h_pole = h_pole_l[level];
h_far = h_far_l[level];
h_surf = h_surf_l[level];
r_fine = 0.015;                 // uniform h_pole within 15 mm of P (Hertz contact radius ~ 8 mm)
growth = 0.15;                  // sizes grow by at most 0.15 mm per mm of distance

// The OCC sphere's seam curve runs through (R, 0, 0) and its parametric poles sit on the z axis:
// turn it half a turn about z so that the seam lies on the far side (-x), away from the contact.
Sphere(1) = {0, 0, 0, R};
Rotate {{0, 0, 1}, {0, 0, 0}, Pi} { Volume{1}; }
// Imprint the rim of the cap (the circle x = x_cap on the sphere) on the surface: the surface
// splits in two, the volume stays whole. (Cutting the volume with the plane x = x_cap instead
// would leave a 23 degree wedge along the rim, where the worst tetrahedra then sat.)
r_rim = Sqrt(R^2 - x_cap^2);
Circle(10) = {x_cap, 0, 0, r_rim};
Rotate {{0, 1, 0}, {x_cap, 0, 0}, Pi / 2} { Curve{10}; }
BooleanFragments{ Volume{1}; Delete; }{ Curve{10}; Delete; }
// OCC bounding boxes of curved surfaces are loose (the cap's reaches down to x = 42 mm), hence the
// generous box; the rest of the sphere reaches x = -R, so it is not caught.
cap() = Surface In BoundingBox{0, -2 * R, -2 * R, 2 * R, 2 * R, 2 * R};
volumes() = Volume{:};
surfaces() = Surface{:};
If (#volumes() != 1 || #surfaces() != 2 || #cap() != 1)
  Error("imprinting the cap failed: %g volumes, %g surfaces, %g caps", #volumes(), #surfaces(),
        #cap());
  Abort;
EndIf

// The pole node, embedded in the cap so that a node sits exactly at P.
Point(100) = {R, 0, 0};
Point{100} In Surface{cap(0)};

Physical Volume("sphere") = {volumes()};
Physical Surface("pole") = {cap(0)};
Physical Point("pole_tip") = {100};

// Size: the smaller of
// - h_pole within r_fine of P, then growing linearly to h_far (Distance is exact for a point);
// - h_surf on the sphere, growing linearly to h_far with the depth R - |x| (exact, analytic).
Field[1] = Distance;
Field[1].PointsList = {100};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_pole;
Field[2].SizeMax = h_far;
Field[2].DistMin = r_fine;
Field[2].DistMax = r_fine + (h_far - h_pole) / growth;
Field[3] = MathEval;
Field[3].F = Sprintf("%.17g - Sqrt(x * x + y * y + z * z)", R);
Field[4] = Threshold;
Field[4].InField = 3;
Field[4].SizeMin = h_surf;
Field[4].SizeMax = h_far;
Field[4].DistMin = 0;
Field[4].DistMax = (h_far - h_surf) / growth;
Field[5] = Min;
Field[5].FieldsList = {2, 4};
Background Field = 5;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h_far;
Mesh.Algorithm = 6;             // Frontal-Delaunay surfaces
Mesh.Algorithm3D = 1;           // Delaunay volumes
Mesh.ElementOrder = 1;
Mesh.Optimize = 1;
// Optimise every tetrahedron of quality below 0.6 (default 0.3): raises the smallest altitude,
// hence the critical time step, by about 1.6x, for under a second of meshing. (Netgen's optimiser is not
// compiled into Debian's Gmsh 4.8.4; HXT, Algorithm3D = 10, is as good here but not reproducible.)
Mesh.OptimizeThreshold = 0.6;
Mesh.RandomSeed = 1;
General.NumThreads = 1;         // reproducible
