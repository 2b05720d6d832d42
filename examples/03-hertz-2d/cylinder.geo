// The lower half of a steel cylinder of radius 1 m, centre (0, 1): its arc touches the block
// at the origin. Mesh size 1.8 mm within 32 mm of the origin (a ≈ 21.6 mm), 0.2 m far away.
// Regenerate: gmsh -2 -format msh41 cylinder.geo -o cylinder.msh
Point(1) = {0, 0, 0};
Point(2) = {0, 1, 0};
Point(3) = {-1, 1, 0};
Point(4) = {1, 1, 0};
Circle(1) = {3, 2, 1};
Circle(2) = {1, 2, 4};
Line(3) = {4, 2};
Line(4) = {2, 3};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("arc") = {1, 2};
Physical Curve("top") = {3, 4};
Physical Surface("cylinder") = {1};
Field[1] = Distance;
Field[1].NodesList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.0018;
Field[2].SizeMax = 0.2;
Field[2].DistMin = 0.032;
Field[2].DistMax = 0.8;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
