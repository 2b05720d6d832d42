// A segment of the disc's track: cast iron, 230 mm (x) × 30 mm (y) × 10 mm (z), top z = 0
// ("top": the track the pin slides on, and air), bottom z = −10 mm ("bottom": bolted to the
// spindle), four sides ("sides", air). Tetrahedra of size hc in the track |x| < 105 mm,
// |y| < 4 mm, z > −2 mm (the pin's path, with a margin), growing to 5 hc over 6 mm.
// Regenerate: gmsh -3 -format msh41 disc.geo -o disc.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {1.5e-3, Name "mesh size in the track [m]"} ];
Lx = 230e-3;
Ly = 30e-3;
Lz = 10e-3;
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
Physical Volume("disc") = {1};
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = 5 * hc;
Field[1].XMin = -105e-3;
Field[1].XMax = 105e-3;
Field[1].YMin = -4e-3;
Field[1].YMax = 4e-3;
Field[1].ZMin = -2e-3;
Field[1].ZMax = 1e-3;
Field[1].Thickness = 6e-3;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
