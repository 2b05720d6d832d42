#pragma once
// The reference cells of every cell and facet type: their order, corners, edges (with their
// mid-edge nodes), oriented local faces, reference node coordinates, and the shape functions of
// the second-order types (the isoparametric map, which the cell checks need below fem/).
// Node numbering follows VTK (docs/choices.md, "Second-order node order"): corners first, as
// the first-order cell; then one node per edge in the order of edges(t); then, for Quad9 and
// Hex27, the face centres (Hex27: x−, x+, y−, y+, z−, z+) and the cell centre.
#include <array>
#include <span>

#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// The most nodes a cell has (Hex27) and a facet has (Quad9).
inline constexpr int kMaxCellNodes = 27;
inline constexpr int kMaxFacetNodes = 9;

/// 1 for Tri3, Quad4, Tet4, Hex8, Line2 and the first-order facets, 2 for the others.
[[nodiscard]] int order(CellType t);
[[nodiscard]] int order(FacetType t);
/// The first-order type with the same corners: Tri6 → Tri3, Quad8 and Quad9 → Quad4, …
[[nodiscard]] CellType corner_type(CellType t);
[[nodiscard]] FacetType corner_type(FacetType t);
/// The number of corners (vertices) of t: n_nodes(corner_type(t)).
[[nodiscard]] int n_corners(CellType t);

/// An edge of a reference cell: corners a → b and its mid-edge node (−1 for first order).
struct CellEdge {
  int a = 0, b = 0, mid = -1;
};
[[nodiscard]] std::span<const CellEdge> edges(CellType t);

/// A local face (edge in 2D) of a reference cell: its type and its cell-local nodes, corners
/// first, counter-clockwise seen from outside (in 2D: the cell on the left, n = (t_y, −t_x)),
/// then the mid-edge nodes in the facet's own edge order, then the face centre (Quad9).
struct LocalFace {
  FacetType type = FacetType::Line2;
  std::array<int, kMaxFacetNodes> v{};
};
[[nodiscard]] std::span<const LocalFace> local_faces(CellType t);

/// Reference coordinates of node a of t (the simplex [0,1]-corner cells for Tri/Tet, the
/// cube [−1, 1]^d for Quad/Hex, [−1, 1] for Line).
[[nodiscard]] Point reference_node(CellType t, int a);
[[nodiscard]] Point reference_node(FacetType t, int a);

/// Shape function values n[a] and reference gradients dn[3 a + k] = ∂N_a/∂ξ_k at xi, for
/// every type: Lagrange on the simplices (quadratic: corners L(2L − 1), edges 4 L_a L_b),
/// tensor-product Lagrange on Line3, Quad9, Hex27, serendipity on Quad8, Hex20. n has
/// n_nodes(t) entries, dn 3·n_nodes(t) (columns beyond the type's dimension are 0).
void shape_functions(CellType t, const Point& xi, double* n, double* dn);
void shape_functions(FacetType t, const Point& xi, double* n, double* dn);

}  // namespace tc::mesh
