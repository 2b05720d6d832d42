#include "tc/io/vtk/vtk_grid.hpp"

namespace tc::io {

int vtk_type(mesh::CellType t) {
  switch (t) {
    case mesh::CellType::Tri3:
      return 5;
    case mesh::CellType::Quad4:
      return 9;
    case mesh::CellType::Tet4:
      return 10;
    case mesh::CellType::Hex8:
      return 12;
    // VTK's quadratic cells, whose node order mesh/ keeps (reference_cell.hpp).
    case mesh::CellType::Tri6:
      return 22;  // VTK_QUADRATIC_TRIANGLE
    case mesh::CellType::Quad8:
      return 23;  // VTK_QUADRATIC_QUAD
    case mesh::CellType::Quad9:
      return 28;  // VTK_BIQUADRATIC_QUAD
    case mesh::CellType::Tet10:
      return 24;  // VTK_QUADRATIC_TETRA
    case mesh::CellType::Hex20:
      return 25;  // VTK_QUADRATIC_HEXAHEDRON
    case mesh::CellType::Hex27:
      return 29;  // VTK_TRIQUADRATIC_HEXAHEDRON
  }
  return 0;
}

namespace {

std::vector<int> iota(int n) {
  std::vector<int> v(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<size_t>(i)] = i;
  return v;
}

/// The grid of `cells` of m with the points `points` (ascending; local[global] their new
/// numbers, or identity when empty) and the fields restricted to them.
VtkGrid make_grid(const mesh::Mesh& m, const std::vector<int>& points,
                  const std::vector<int>& cells, const std::vector<int>& local,
                  const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  VtkGrid g;
  g.points.reserve(3 * points.size());
  for (const int a : points) g.points.insert(g.points.end(), m.point(a).begin(), m.point(a).end());
  for (const int c : cells) {
    for (const int n : m.cell(c)) g.connectivity.push_back(local.empty() ? n : local[n]);
    g.offsets.push_back(static_cast<std::int64_t>(g.connectivity.size()));
    g.types.push_back(static_cast<std::uint8_t>(vtk_type(m.cell_type(c))));
  }
  auto restricted = [&g](const Field& f, const std::vector<int>& rows, size_t all) {
    if (rows.size() == all) return &f;
    Field& r = g.owned.emplace_back(Field{f.name, f.components, {}});
    r.values.reserve(rows.size() * static_cast<size_t>(f.components));
    for (const int i : rows)
      for (int k = 0; k < f.components; ++k)
        r.values.push_back(f.values[static_cast<size_t>(f.components * i + k)]);
    return static_cast<const Field*>(&r);
  };
  for (const auto& f : point_data)
    g.point_data.push_back(restricted(f, points, static_cast<size_t>(m.n_nodes())));
  for (const auto& f : cell_data)
    g.cell_data.push_back(restricted(f, cells, static_cast<size_t>(m.n_cells())));
  return g;
}

}  // namespace

VtkGrid whole_grid(const mesh::Mesh& m, const std::vector<Field>& point_data,
                   const std::vector<Field>& cell_data) {
  return make_grid(m, iota(m.n_nodes()), iota(m.n_cells()), {}, point_data, cell_data);
}

VtkGrid piece_grid(const mesh::Mesh& m, const std::vector<int>& cells,
                   const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  std::vector<int> local(static_cast<size_t>(m.n_nodes()), -1), points;
  for (const int c : cells)
    for (const int n : m.cell(c)) local[static_cast<size_t>(n)] = 0;
  for (int a = 0; a < m.n_nodes(); ++a)
    if (local[static_cast<size_t>(a)] == 0) {
      local[static_cast<size_t>(a)] = static_cast<int>(points.size());
      points.push_back(a);
    }
  return make_grid(m, points, cells, local, point_data, cell_data);
}

}  // namespace tc::io
