// split_into_simplices and to_second_order (second_order.hpp).
#include "tc/mesh/second_order.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::mesh {

namespace {

// Kuhn's six tetrahedra of a hexahedron around its diagonal 0–6 (VTK numbering), each
// positively oriented: the shared faces are cut along the same diagonals in neighbouring cells.
constexpr int kKuhn[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                             {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
constexpr int kQuadSplit[2][3] = {{0, 1, 2}, {0, 2, 3}};

/// The facets of each cell, by boundary name, so that the cells replacing it find theirs.
std::vector<std::vector<std::pair<std::string, Facet>>> facets_by_cell(const Mesh& m) {
  std::vector<std::vector<std::pair<std::string, Facet>>> out(static_cast<size_t>(m.n_cells()));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name))
      out.at(static_cast<size_t>(f.cell)).emplace_back(name, f);
  return out;
}

bool corners_within(const LocalFace& lf, std::span<const int> cell, std::span<const int> nodes) {
  const int nc = n_nodes(corner_type(lf.type));
  for (int i = 0; i < nc; ++i)
    if (std::find(nodes.begin(), nodes.end(), cell[lf.v[i]]) == nodes.end()) return false;
  return true;
}

Facet face_of(const LocalFace& lf, std::span<const int> cell, int c) {
  Facet f;
  f.type = lf.type;
  f.cell = c;
  for (int i = 0; i < n_nodes(lf.type); ++i) f.nodes[i] = cell[lf.v[i]];
  return f;
}

}  // namespace

Mesh split_into_simplices(const Mesh& m) {
  Mesh out(m.dim());
  for (const auto& p : m.points()) out.add_point(p);
  const auto facets = facets_by_cell(m);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto v = m.cell(c);
    const CellType t = m.cell_type(c);
    if (order(t) != 1) throw MeshError("split_into_simplices: the mesh has second-order cells");
    const int first = out.n_cells();
    if (t == CellType::Quad4) {
      for (const auto& s : kQuadSplit) {
        const int tri[3] = {v[s[0]], v[s[1]], v[s[2]]};
        out.add_cell(CellType::Tri3, tri, m.cell_group(c));
      }
    } else if (t == CellType::Hex8) {
      for (const auto& s : kKuhn) {
        const int tet[4] = {v[s[0]], v[s[1]], v[s[2]], v[s[3]]};
        out.add_cell(CellType::Tet4, tet, m.cell_group(c));
      }
    } else {
      out.add_cell(t, v, m.cell_group(c));
    }
    // A facet of the old cell is covered by the faces of the new cells whose corners all lie
    // on it (on a planar facet, a new face with its corners there is in it).
    for (const auto& [name, f] : facets[static_cast<size_t>(c)])
      for (int s = first; s < out.n_cells(); ++s)
        for (const auto& lf : local_faces(out.cell_type(s)))
          if (corners_within(lf, out.cell(s), f.node_span()))
            out.add_facet(name, face_of(lf, out.cell(s), s));
  }
  return out;
}

Mesh to_second_order(const Mesh& m, CellType target) {
  if (order(target) != 2) throw MeshError("to_second_order: the target must be of second order");
  Mesh out(m.dim());
  for (const auto& p : m.points()) out.add_point(p);
  std::map<std::array<int, 2>, int> edge_node;
  std::map<std::array<int, 4>, int> face_node;
  const auto centroid = [&](std::span<const int> nodes) {
    Point x{0, 0, 0};
    for (const int a : nodes)
      for (int k = 0; k < 3; ++k) x[k] += out.point(a)[k] / static_cast<double>(nodes.size());
    return x;
  };
  const auto facets = facets_by_cell(m);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto v = m.cell(c);
    const CellType lin = m.cell_type(c);
    if (order(lin) != 1) throw MeshError("to_second_order: the mesh has second-order cells");
    CellType t = target;
    if (lin == CellType::Tri3) t = CellType::Tri6;
    if (lin == CellType::Tet4) t = CellType::Tet10;
    if (corner_type(t) != lin)
      throw MeshError(std::string("to_second_order: a ") + name(lin) + " cell cannot become " +
                      name(target));
    std::array<int, kMaxCellNodes> nodes{};
    std::copy(v.begin(), v.end(), nodes.begin());
    for (const auto& e : edges(t)) {
      const std::array<int, 2> key{std::min(v[e.a], v[e.b]), std::max(v[e.a], v[e.b])};
      auto [it, fresh] = edge_node.emplace(key, -1);
      if (fresh) {
        const int ends[2] = {v[e.a], v[e.b]};
        it->second = out.add_point(centroid(ends));
      }
      nodes[e.mid] = it->second;
    }
    if (t == CellType::Hex27)
      for (const auto& lf : local_faces(t)) {
        std::array<int, 4> key{v[lf.v[0]], v[lf.v[1]], v[lf.v[2]], v[lf.v[3]]};
        std::sort(key.begin(), key.end());
        auto [it, fresh] = face_node.emplace(key, -1);
        if (fresh) it->second = out.add_point(centroid(key));
        nodes[lf.v[8]] = it->second;
      }
    if (t == CellType::Quad9 || t == CellType::Hex27)
      nodes[n_nodes(t) - 1] = out.add_point(centroid(v));
    const std::span<const int> cell(nodes.data(), static_cast<size_t>(n_nodes(t)));
    out.add_cell(t, cell, m.cell_group(c));
    for (const auto& [bname, f] : facets[static_cast<size_t>(c)])
      for (const auto& lf : local_faces(t))
        if (corners_within(lf, cell, f.node_span())) out.add_facet(bname, face_of(lf, cell, c));
  }
  return out;
}

}  // namespace tc::mesh
