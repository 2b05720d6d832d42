// A brake pad: a block of friction material, 12 mm (x) × 10 mm (y) × 6 mm thick, on the
// outboard (side = +1: z from 5 to 11 mm) or the inboard (side = -1: z from -5 to -11 mm)
// face of the disc. Its friction face "face" (|z| = 5 mm) touches the disc, its back "back"
// (|z| = 11 mm) is bonded to the backing plate, its four "sides" are in air. Tetrahedra of
// size hc on the face growing to 4 hc at 4 mm from it.
// Regenerate: gmsh -3 -format msh41 -setnumber side 1 pad.geo -o pad-out.msh
//             gmsh -3 -format msh41 -setnumber side -1 pad.geo -o pad-in.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {1.0e-3, Name "mesh size on the friction face [m]"} ];
DefineConstant[ side = {1, Name "+1 outboard (z > 0), -1 inboard (z < 0)"} ];
Lx = 12e-3;
Ly = 10e-3;
T = 6e-3;
z0 = 5e-3;
Box(1) = {-Lx / 2, -Ly / 2, (side > 0) ? z0 : -z0 - T, Lx, Ly, T};
e = 1e-6;
face() = Surface In BoundingBox{-Lx, -Ly, side * z0 - e, Lx, Ly, side * z0 + e};
back() = Surface In BoundingBox{-Lx, -Ly, side * (z0 + T) - e, Lx, Ly, side * (z0 + T) + e};
sides() = Abs(Boundary{ Volume{1}; });
sides() -= face();
sides() -= back();
Physical Surface("face") = face();
Physical Surface("back") = back();
Physical Surface("sides") = sides();
Physical Volume("pad") = {1};
Field[1] = Distance;
Field[1].FacesList = {face()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = 4 * hc;
Field[2].DistMin = 0.5e-3;
Field[2].DistMax = 4e-3;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
