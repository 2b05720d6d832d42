// The pin: a bronze cylinder, radius 3 mm, 12 mm out of its holder, axis z; its flat end
// (z = 0) is the contact face ("face"), its top ("top") is held by the holder, its side
// ("side") is in air. Tetrahedra, size hc on the face growing to 4 hc at 4 mm above it.
// Regenerate (default) : gmsh -3 -format msh41 pin.geo -o pin.msh
// Refined (hc = 0.22 mm, case-refined.toml): gmsh -3 -format msh41 -setnumber hc 0.22e-3 pin.geo -o pin-refined.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {0.5e-3, Name "mesh size on the contact face [m]"} ];
R = 3e-3;
L = 12e-3;
Cylinder(1) = {0, 0, 0, 0, 0, L, R};
e = 1e-6;
face() = Surface In BoundingBox{-R - e, -R - e, -e, R + e, R + e, e};
top() = Surface In BoundingBox{-R - e, -R - e, L - e, R + e, R + e, L + e};
side() = Abs(Boundary{ Volume{1}; });
side() -= face();
side() -= top();
Physical Surface("face") = face();
Physical Surface("top") = top();
Physical Surface("side") = side();
Physical Volume("pin") = {1};
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
