#pragma once
// The Gmsh size field of the Hertz tests (contact_hertz_test, hertz_rates_2d.hpp,
// contact_hertz_3d_rates_slow): cells of size h near the point of first contact.
#include <gmsh.h>

namespace tc::test::hertz {

/// Size h within 1.5 a of Gmsh point `point`, growing to `coarse` at 0.8 R, as the background
/// mesh, with the sizes of points, boundaries and curvature switched off.
inline void size_towards(int point, double h, double coarse, double half_width, double radius) {
  namespace field = gmsh::model::mesh::field;
  const int d = field::add("Distance");
  try {
    field::setNumbers(d, "PointsList", {static_cast<double>(point)});
  } catch (...) {  // Gmsh before 4.9 names it NodesList
    field::setNumbers(d, "NodesList", {static_cast<double>(point)});
  }
  const int t = field::add("Threshold");
  field::setNumber(t, "InField", d);
  field::setNumber(t, "SizeMin", h);
  field::setNumber(t, "SizeMax", coarse);
  field::setNumber(t, "DistMin", 1.5 * half_width);
  field::setNumber(t, "DistMax", 0.8 * radius);
  field::setAsBackgroundMesh(t);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
}

}  // namespace tc::test::hertz
