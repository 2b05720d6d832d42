// The disc: a straight segment of a solid cast-iron brake disc, 50 mm (x, the sliding
// direction) × 30 mm (y, radial) × 10 mm thick (z), mid-plane z = 0. Its two friction faces
// "face_out" (z = +5 mm, the outboard pad's side) and "face_in" (z = -5 mm, the inboard pad's),
// "hub" (x = -25 mm: where it joins the hat and is driven) and "sides" (the three other faces,
// in air). Tetrahedra of size hc in the two track regions |x| < 9 mm, |y| < 6.5 mm within 1 mm
// of each friction face (the 12 × 10 mm pads over their ±1.5 mm stroke, with a margin),
// growing to 5 hc over 4 mm.
// Regenerate: gmsh -3 -format msh41 disc.geo -o disc.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {0.9e-3, Name "mesh size in the track regions [m]"} ];
Lx = 50e-3;
Ly = 30e-3;
Lz = 10e-3;
Box(1) = {-Lx / 2, -Ly / 2, -Lz / 2, Lx, Ly, Lz};
e = 1e-6;
out() = Surface In BoundingBox{-Lx, -Ly, Lz / 2 - e, Lx, Ly, Lz / 2 + e};
in() = Surface In BoundingBox{-Lx, -Ly, -Lz / 2 - e, Lx, Ly, -Lz / 2 + e};
hub() = Surface In BoundingBox{-Lx / 2 - e, -Ly, -Lz, -Lx / 2 + e, Ly, Lz};
sides() = Abs(Boundary{ Volume{1}; });
sides() -= out();
sides() -= in();
sides() -= hub();
Physical Surface("face_out") = out();
Physical Surface("face_in") = in();
Physical Surface("hub") = hub();
Physical Surface("sides") = sides();
Physical Volume("disc") = {1};
For k In {0:1}
  Field[1 + k] = Box;
  Field[1 + k].VIn = hc;
  Field[1 + k].VOut = 5 * hc;
  Field[1 + k].XMin = -9e-3;
  Field[1 + k].XMax = 9e-3;
  Field[1 + k].YMin = -6.5e-3;
  Field[1 + k].YMax = 6.5e-3;
  Field[1 + k].ZMin = (k == 0) ? 4e-3 : -6e-3;
  Field[1 + k].ZMax = (k == 0) ? 6e-3 : -4e-3;
  Field[1 + k].Thickness = 4e-3;
EndFor
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
