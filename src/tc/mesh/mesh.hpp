#pragma once
// The mesh of one body: nodes, cells of possibly mixed type, and named boundaries made of
// facets. No physics here. Node ordering of cells and facets follows VTK (= Gmsh for the
// linear types): Quad4 and the faces of Hex8 counter-clockwise seen from outside; the
// second-order types (reference_cell.hpp) list their corners first, as the linear type does.
#include <array>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace tc::mesh {

// The first-order values come first: tables indexed by the type start with them.
enum class CellType { Tri3, Quad4, Tet4, Hex8, Tri6, Quad8, Quad9, Tet10, Hex20, Hex27 };
enum class FacetType { Line2, Tri3, Quad4, Line3, Tri6, Quad8, Quad9 };

[[nodiscard]] int n_nodes(CellType t);
[[nodiscard]] int n_nodes(FacetType t);
[[nodiscard]] int dimension(CellType t);  // 2 for Tri/Quad, 3 for Tet/Hex
[[nodiscard]] const char* name(CellType t);
[[nodiscard]] const char* name(FacetType t);

using Point = std::array<double, 3>;  // z = 0 in 2D

/// A boundary facet (edge in 2D, face in 3D), oriented with its normal pointing out of `cell`:
/// Tri3/Quad4 counter-clockwise seen from outside; Line2 with n = (t_y, −t_x), t = x1 − x0
/// (the edge runs counter-clockwise around its cell). Second-order facets: the corners so,
/// then the mid-edge nodes (and the Quad9 centre), as reference_cell.hpp's LocalFace.
struct Facet {
  FacetType type = FacetType::Line2;
  std::array<int, 9> nodes{-1, -1, -1, -1, -1, -1, -1, -1, -1};  // first n_nodes(type) used
  int cell = -1;                                                 // the cell it bounds
  [[nodiscard]] std::span<const int> node_span() const {
    return {nodes.data(), static_cast<size_t>(n_nodes(type))};
  }
};

class Mesh {
 public:
  Mesh() = default;
  explicit Mesh(int dim) : dim_(dim) {}

  [[nodiscard]] int dim() const { return dim_; }
  [[nodiscard]] int n_nodes() const { return static_cast<int>(points_.size()); }
  [[nodiscard]] int n_cells() const { return static_cast<int>(types_.size()); }
  [[nodiscard]] const Point& point(int i) const { return points_[i]; }
  [[nodiscard]] const std::vector<Point>& points() const { return points_; }
  [[nodiscard]] CellType cell_type(int c) const { return types_[c]; }
  [[nodiscard]] std::span<const int> cell(int c) const {
    return {cell_nodes_.data() + offsets_[c], static_cast<size_t>(offsets_[c + 1] - offsets_[c])};
  }

  /// The Gmsh physical group of cell c (its tag), −1 when it has none (a box mesh).
  [[nodiscard]] int cell_group(int c) const { return groups_[c]; }

  int add_point(const Point& p);
  int add_cell(CellType t, std::span<const int> nodes, int group = -1);
  void add_facet(const std::string& boundary, const Facet& f);

  [[nodiscard]] bool has_boundary(const std::string& name) const {
    return boundaries_.count(name) != 0;
  }
  [[nodiscard]] const std::vector<Facet>& boundary(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> boundary_names() const;
  /// Sorted, unique nodes of a boundary.
  [[nodiscard]] std::vector<int> boundary_nodes(const std::string& name) const;
  /// Translates every point (used by tests and by body placement).
  void transform(const std::array<std::array<double, 3>, 3>& rotation, const Point& shift);

 private:
  int dim_ = 3;
  std::vector<Point> points_;
  std::vector<CellType> types_;
  std::vector<int> offsets_{0};
  std::vector<int> cell_nodes_;
  std::vector<int> groups_;  // per cell
  std::map<std::string, std::vector<Facet>> boundaries_;
};

/// Signed measure (area in 2D, volume in 3D) of cell c; negative means inverted. Exact for
/// the first-order cells and for second-order cells whose Jacobian determinant has degree ≤ 7
/// per reference direction (every Tri6, Tet10, Quad8, Quad9, Hex20, Hex27: 4-point Gauss).
[[nodiscard]] double cell_measure(const Mesh& m, int c);

/// Throws MeshError naming the first bad cells (inverted or zero measure, a Jacobian not
/// positive at a corner, or, for second-order cells, at a node or a point of the 4^d Gauss
/// rule; at most 10 listed), or the first node whose coordinates are not finite or beyond
/// kMaxCoordinate.
void check_cells(const Mesh& m, const std::string& source);

/// The largest |coordinate| a mesh may have [m]: cell measures and the contact geometry take
/// products of up to three coordinates, which overflow from ~1e102 and lose every digit of a
/// cell of ordinary size long before (docs/choices.md, "Node coordinates bounded").
inline constexpr double kMaxCoordinate = 1e12;

/// Throws MeshError when a 2D mesh folds over itself: two cells on the same side of an edge
/// they share (each cell taken counter-clockwise). A mesh read with cells of both orientations
/// (some listed clockwise, some counter-clockwise, which read_gmsh turns one by one) overlaps
/// itself where the two kinds meet; a mesh whose cells are all clockwise, turned as a whole,
/// does not. Names the first cells (at most 10 pairs).
void check_no_fold(const Mesh& m, const std::string& source);

/// Pairs (i, j), i < j, sorted, of distinct nodes at the same place: every coordinate within
/// 1e-12 times the bounding-box diagonal. Not an error in itself (separately meshed parts glued
/// by hand have them); the caller decides whether to warn. O(n log n).
[[nodiscard]] std::vector<std::pair<int, int>> find_duplicate_nodes(const Mesh& m);

}  // namespace tc::mesh
