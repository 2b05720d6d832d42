// Structured boxes: nodes numbered lexicographically (x fastest), cells likewise, VTK node
// order inside each cell, boundary facets oriented with the outward normal (mesh.hpp).
#include "tc/mesh/box.hpp"

#include <string>

#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/mesh/second_order.hpp"

namespace tc::mesh {

namespace {

Mesh make_box_2d(const Point& lo, const Point& hi, int nx, int ny) {
  Mesh m(2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.add_point({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, 0.0});
  auto node = [&](int i, int j) { return i + (nx + 1) * j; };
  auto cell = [&](int i, int j) { return i + nx * j; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int c[4] = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
      m.add_cell(CellType::Quad4, c);
    }
  // Edges ordered so that, walking along them, the cell lies on the left (outward normal).
  for (int i = 0; i < nx; ++i) {
    m.add_facet("ymin", {FacetType::Line2, {node(i, 0), node(i + 1, 0), -1, -1}, cell(i, 0)});
    m.add_facet("ymax",
                {FacetType::Line2, {node(i + 1, ny), node(i, ny), -1, -1}, cell(i, ny - 1)});
  }
  for (int j = 0; j < ny; ++j) {
    m.add_facet("xmin", {FacetType::Line2, {node(0, j + 1), node(0, j), -1, -1}, cell(0, j)});
    m.add_facet("xmax",
                {FacetType::Line2, {node(nx, j), node(nx, j + 1), -1, -1}, cell(nx - 1, j)});
  }
  return m;
}

Mesh make_box_3d(const Point& lo, const Point& hi, int nx, int ny, int nz) {
  Mesh m(3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.add_point({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny,
                     lo[2] + (hi[2] - lo[2]) * k / nz});
  auto node = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  auto cell = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int c[8] = {node(i, j, k),
                          node(i + 1, j, k),
                          node(i + 1, j + 1, k),
                          node(i, j + 1, k),
                          node(i, j, k + 1),
                          node(i + 1, j, k + 1),
                          node(i + 1, j + 1, k + 1),
                          node(i, j + 1, k + 1)};
        m.add_cell(CellType::Hex8, c);
      }
  // Faces counter-clockwise seen from outside: the right-hand normal points out.
  auto face = [&](const std::string& name, int a, int b, int c, int d, int owner) {
    m.add_facet(name, {FacetType::Quad4, {a, b, c, d}, owner});
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      face("xmin", node(0, j, k), node(0, j, k + 1), node(0, j + 1, k + 1), node(0, j + 1, k),
           cell(0, j, k));
      face("xmax", node(nx, j, k), node(nx, j + 1, k), node(nx, j + 1, k + 1), node(nx, j, k + 1),
           cell(nx - 1, j, k));
    }
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i) {
      face("ymin", node(i, 0, k), node(i + 1, 0, k), node(i + 1, 0, k + 1), node(i, 0, k + 1),
           cell(i, 0, k));
      face("ymax", node(i, ny, k), node(i, ny, k + 1), node(i + 1, ny, k + 1), node(i + 1, ny, k),
           cell(i, ny - 1, k));
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      face("zmin", node(i, j, 0), node(i, j + 1, 0), node(i + 1, j + 1, 0), node(i + 1, j, 0),
           cell(i, j, 0));
      face("zmax", node(i, j, nz), node(i + 1, j, nz), node(i + 1, j + 1, nz), node(i, j + 1, nz),
           cell(i, j, nz - 1));
    }
  return m;
}

}  // namespace

Mesh make_box(int dim, const Point& min, const Point& max, const std::array<int, 3>& cells) {
  if (dim != 2 && dim != 3)
    throw MeshError("make_box: dimension must be 2 or 3, got " + std::to_string(dim));
  for (int k = 0; k < dim; ++k) {
    if (cells[k] < 1) throw MeshError("make_box: at least one cell per axis is needed");
    // A degenerate or reversed box would give inverted cells.
    if (!(max[k] > min[k])) throw MeshError("make_box: max must exceed min on every axis");
  }
  return dim == 2 ? make_box_2d(min, max, cells[0], cells[1])
                  : make_box_3d(min, max, cells[0], cells[1], cells[2]);
}

Mesh make_box(int dim, const Point& min, const Point& max, const std::array<int, 3>& cells,
              CellType element) {
  if (dimension(element) != dim)
    throw MeshError(std::string("make_box: a ") + std::to_string(dim) + "D box cannot have " +
                    name(element) + " cells");
  Mesh m = make_box(dim, min, max, cells);
  const CellType corners = corner_type(element);
  if (corners == CellType::Tri3 || corners == CellType::Tet4) m = split_into_simplices(m);
  return order(element) == 2 ? to_second_order(m, element) : m;
}

}  // namespace tc::mesh
