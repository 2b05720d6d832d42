// The pin: a steel cylinder Ø 6 mm × 10 mm, axis z, its flat end (z = 0, "face") on the disc
// at x = −100 mm. Its upper 7 mm sit in the holder's collet ("collet": the side for
// 3 mm < z < 10 mm), which drags it along x and holds it in y; its top ("top") carries the
// load; the 3 mm of side below the collet ("side") are in air. Tetrahedra of size hc on the
// face growing to 3 hc at 4 mm above it.
// Regenerate: gmsh -3 -format msh41 pin.geo -o pin.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {1.0e-3, Name "mesh size on the contact face [m]"} ];
R = 3e-3;
L = 10e-3;
H = 3e-3;  // stick-out below the collet
X0 = -0.1;
Cylinder(1) = {X0, 0, 0, 0, 0, H, R};
Cylinder(2) = {X0, 0, H, 0, 0, L - H, R};
v() = BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; };
e = 1e-6;
face() = Surface In BoundingBox{X0 - R - e, -R - e, -e, X0 + R + e, R + e, e};
top() = Surface In BoundingBox{X0 - R - e, -R - e, L - e, X0 + R + e, R + e, L + e};
side() = Surface In BoundingBox{X0 - R - e, -R - e, -e, X0 + R + e, R + e, H + e};
side() -= face();
mid() = Surface In BoundingBox{X0 - R - e, -R - e, H - e, X0 + R + e, R + e, H + e};
side() -= mid();
collet() = Surface In BoundingBox{X0 - R - e, -R - e, H - e, X0 + R + e, R + e, L + e};
collet() -= top();
collet() -= mid();
Physical Surface("face") = face();
Physical Surface("top") = top();
Physical Surface("side") = side();
Physical Surface("collet") = collet();
Physical Volume("pin") = {v()};
Field[1] = Distance;
Field[1].FacesList = {face()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = 3 * hc;
Field[2].DistMin = 0.5e-3;
Field[2].DistMax = 4e-3;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
