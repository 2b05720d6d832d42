// The plate: steel, 40 mm × 20 mm × 8 mm, top face z = 0 ("top": the track the pin slides on,
// and air), bottom z = -8 mm ("bottom": clamped on the machine bed), four sides ("sides",
// air). Tetrahedra of size hc in the track region |x| < 4.5 mm, |y| < 3.5 mm, -1 mm < z
// (the pin's footprint over its ±1 mm stroke, with a margin), growing to 5 hc over 5 mm.
// Regenerate (default) : gmsh -3 -format msh41 plate.geo -o plate.msh
// Refined (hc = 0.17 mm, case-refined.toml): gmsh -3 -format msh41 -setnumber hc 0.17e-3 plate.geo -o plate-refined.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {0.4e-3, Name "mesh size in the track region [m]"} ];
Lx = 40e-3;
Ly = 20e-3;
Lz = 8e-3;
Box(1) = {-Lx / 2, -Ly / 2, -Lz, Lx, Ly, Lz};
e = 1e-6;
top() = Surface In BoundingBox{-Lx, -Ly, -e, Lx, Ly, e};
bottom() = Surface In BoundingBox{-Lx, -Ly, -Lz - e, Lx, Ly, -Lz + e};
sides() = Abs(Boundary{ Volume{1}; });
sides() -= top();
sides() -= bottom();
Physical Surface("top") = top();
Physical Surface("bottom") = bottom();
Physical Surface("sides") = sides();
Physical Volume("plate") = {1};
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = 5 * hc;
Field[1].XMin = -4.5e-3;
Field[1].XMax = 4.5e-3;
Field[1].YMin = -3.5e-3;
Field[1].YMax = 3.5e-3;
Field[1].ZMin = -1e-3;
Field[1].ZMax = 1e-3;
Field[1].Thickness = 5e-3;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
