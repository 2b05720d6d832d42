#include "tc/mesh/mesh.hpp"

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"

namespace tc::mesh {

int n_nodes(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return 3;
    case CellType::Quad4:
      return 4;
    case CellType::Tet4:
      return 4;
    case CellType::Hex8:
      return 8;
    case CellType::Tri6:
      return 6;
    case CellType::Quad8:
      return 8;
    case CellType::Quad9:
      return 9;
    case CellType::Tet10:
      return 10;
    case CellType::Hex20:
      return 20;
    case CellType::Hex27:
      return 27;
  }
  return 0;
}

int n_nodes(FacetType t) {
  switch (t) {
    case FacetType::Line2:
      return 2;
    case FacetType::Tri3:
      return 3;
    case FacetType::Quad4:
      return 4;
    case FacetType::Line3:
      return 3;
    case FacetType::Tri6:
      return 6;
    case FacetType::Quad8:
      return 8;
    case FacetType::Quad9:
      return 9;
  }
  return 0;
}

int dimension(CellType t) {
  switch (t) {
    case CellType::Tri3:
    case CellType::Quad4:
    case CellType::Tri6:
    case CellType::Quad8:
    case CellType::Quad9:
      return 2;
    default:
      return 3;
  }
}

const char* name(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return "Tri3";
    case CellType::Quad4:
      return "Quad4";
    case CellType::Tet4:
      return "Tet4";
    case CellType::Hex8:
      return "Hex8";
    case CellType::Tri6:
      return "Tri6";
    case CellType::Quad8:
      return "Quad8";
    case CellType::Quad9:
      return "Quad9";
    case CellType::Tet10:
      return "Tet10";
    case CellType::Hex20:
      return "Hex20";
    case CellType::Hex27:
      return "Hex27";
  }
  return "?";
}

const char* name(FacetType t) {
  switch (t) {
    case FacetType::Line2:
      return "Line2";
    case FacetType::Tri3:
      return "Tri3";
    case FacetType::Quad4:
      return "Quad4";
    case FacetType::Line3:
      return "Line3";
    case FacetType::Tri6:
      return "Tri6";
    case FacetType::Quad8:
      return "Quad8";
    case FacetType::Quad9:
      return "Quad9";
  }
  return "?";
}

int Mesh::add_point(const Point& p) {
  points_.push_back(p);
  return n_nodes() - 1;
}

int Mesh::add_cell(CellType t, std::span<const int> nodes, int group) {
  TC_VERIFY(static_cast<int>(nodes.size()) == mesh::n_nodes(t),
            "a cell lists as many nodes as its type has");
  TC_VERIFY(dimension(t) == dim_, "a cell has the mesh's dimension");
  types_.push_back(t);
  cell_nodes_.insert(cell_nodes_.end(), nodes.begin(), nodes.end());
  offsets_.push_back(static_cast<int>(cell_nodes_.size()));
  groups_.push_back(group);
  return n_cells() - 1;
}

void Mesh::add_facet(const std::string& boundary, const Facet& f) {
  boundaries_[boundary].push_back(f);
}

const std::vector<Facet>& Mesh::boundary(const std::string& name) const {
  const auto it = boundaries_.find(name);
  if (it == boundaries_.end()) throw MeshError("the mesh has no boundary named '" + name + "'");
  return it->second;
}

std::vector<std::string> Mesh::boundary_names() const {
  std::vector<std::string> out;
  for (const auto& [n, f] : boundaries_) out.push_back(n);
  return out;
}

std::vector<int> Mesh::boundary_nodes(const std::string& name) const {
  std::vector<int> out;
  for (const auto& f : boundary(name)) {
    const auto s = f.node_span();
    out.insert(out.end(), s.begin(), s.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void Mesh::transform(const std::array<std::array<double, 3>, 3>& r, const Point& shift) {
  for (auto& p : points_) {
    Point q{};
    for (int i = 0; i < 3; ++i) q[i] = r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + shift[i];
    p = q;
  }
}

}  // namespace tc::mesh
