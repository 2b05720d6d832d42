// Reference cells (reference_cell.hpp): tables of corners, edges and faces, and the shape
// functions of every type. The first-order tables are those the Gmsh reader always used; the
// second-order faces are derived from them (a face's mid-edge nodes are its cell's nodes on
// the face's edges), so that one table per cell shape is written by hand.
#include "tc/mesh/reference_cell.hpp"

#include <vector>

#include "tc/core/verify.hpp"

namespace tc::mesh {

namespace {

using F = FacetType;

// ---- Corners, edges, faces ------------------------------------------------------------------

constexpr CellEdge kTriEdges[] = {{0, 1, 3}, {1, 2, 4}, {2, 0, 5}};
constexpr CellEdge kQuadEdges[] = {{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}};
constexpr CellEdge kTetEdges[] = {{0, 1, 4}, {1, 2, 5}, {2, 0, 6}, {0, 3, 7}, {1, 3, 8}, {2, 3, 9}};
constexpr CellEdge kHexEdges[] = {{0, 1, 8},  {1, 2, 9},  {2, 3, 10}, {3, 0, 11},
                                  {4, 5, 12}, {5, 6, 13}, {6, 7, 14}, {7, 4, 15},
                                  {0, 4, 16}, {1, 5, 17}, {2, 6, 18}, {3, 7, 19}};
// First-order edges: the same corners without mid-edge nodes.
constexpr CellEdge kTriEdges1[] = {{0, 1, -1}, {1, 2, -1}, {2, 0, -1}};
constexpr CellEdge kQuadEdges1[] = {{0, 1, -1}, {1, 2, -1}, {2, 3, -1}, {3, 0, -1}};
constexpr CellEdge kTetEdges1[] = {{0, 1, -1}, {1, 2, -1}, {2, 0, -1},
                                   {0, 3, -1}, {1, 3, -1}, {2, 3, -1}};
constexpr CellEdge kHexEdges1[] = {{0, 1, -1}, {1, 2, -1}, {2, 3, -1}, {3, 0, -1},
                                   {4, 5, -1}, {5, 6, -1}, {6, 7, -1}, {7, 4, -1},
                                   {0, 4, -1}, {1, 5, -1}, {2, 6, -1}, {3, 7, -1}};

// Oriented first-order faces: the normal (counter-clockwise seen from outside) points out of
// a positively oriented cell.
constexpr LocalFace kTriFaces[] = {{F::Line2, {0, 1}}, {F::Line2, {1, 2}}, {F::Line2, {2, 0}}};
constexpr LocalFace kQuadFaces[] = {
    {F::Line2, {0, 1}}, {F::Line2, {1, 2}}, {F::Line2, {2, 3}}, {F::Line2, {3, 0}}};
constexpr LocalFace kTetFaces[] = {
    {F::Tri3, {0, 2, 1}}, {F::Tri3, {0, 1, 3}}, {F::Tri3, {0, 3, 2}}, {F::Tri3, {1, 2, 3}}};
constexpr LocalFace kHexFaces[] = {{F::Quad4, {0, 3, 2, 1}}, {F::Quad4, {4, 5, 6, 7}},
                                   {F::Quad4, {0, 1, 5, 4}}, {F::Quad4, {1, 2, 6, 5}},
                                   {F::Quad4, {2, 3, 7, 6}}, {F::Quad4, {0, 4, 7, 3}}};
// The Hex27 centre node of each face of kHexFaces (z−, z+, y−, x+, y+, x−).
constexpr int kHexFaceCentre[] = {24, 25, 22, 21, 23, 20};

std::span<const LocalFace> corner_faces(CellType t) {
  switch (corner_type(t)) {
    case CellType::Tri3:
      return kTriFaces;
    case CellType::Quad4:
      return kQuadFaces;
    case CellType::Tet4:
      return kTetFaces;
    default:
      return kHexFaces;
  }
}

FacetType second_order_facet(FacetType corner, CellType cell) {
  switch (corner) {
    case F::Line2:
      return F::Line3;
    case F::Tri3:
      return F::Tri6;
    default:
      return cell == CellType::Hex27 ? F::Quad9 : F::Quad8;
  }
}

int mid_node(CellType t, int a, int b) {
  for (const auto& e : edges(t))
    if ((e.a == a && e.b == b) || (e.a == b && e.b == a)) return e.mid;
  TC_VERIFY(false, "a face's consecutive corners are joined by an edge of its cell");
  return -1;
}

/// The second-order faces from the first-order ones: corners, then the node on each edge of
/// the face (from corner i to corner i + 1), then the face centre.
std::vector<LocalFace> derive_faces(CellType t) {
  std::vector<LocalFace> out;
  const auto corners = corner_faces(t);
  for (std::size_t f = 0; f < corners.size(); ++f) {
    LocalFace face;
    face.type = second_order_facet(corners[f].type, t);
    const int k = n_nodes(corners[f].type);
    for (int i = 0; i < k; ++i) face.v[i] = corners[f].v[i];
    if (k == 2) {
      face.v[2] = mid_node(t, face.v[0], face.v[1]);
    } else {
      for (int i = 0; i < k; ++i) face.v[k + i] = mid_node(t, face.v[i], face.v[(i + 1) % k]);
    }
    if (face.type == F::Quad9) face.v[8] = kHexFaceCentre[f];
    out.push_back(face);
  }
  return out;
}

// ---- Reference coordinates ------------------------------------------------------------------

constexpr Point kTriCorner[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
constexpr Point kTetCorner[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
constexpr Point kQuadCorner[] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
constexpr Point kHexCorner[] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
constexpr Point kHexFaceCentres[] = {{-1, 0, 0}, {1, 0, 0},  {0, -1, 0},
                                     {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};

Point corner(CellType t, int a) {
  switch (corner_type(t)) {
    case CellType::Tri3:
      return kTriCorner[a];
    case CellType::Quad4:
      return kQuadCorner[a];
    case CellType::Tet4:
      return kTetCorner[a];
    default:
      return kHexCorner[a];
  }
}

/// The cell type whose reference cell a facet type shares (Line is handled apart).
CellType as_cell(FacetType t) {
  switch (t) {
    case F::Tri3:
      return CellType::Tri3;
    case F::Tri6:
      return CellType::Tri6;
    case F::Quad4:
      return CellType::Quad4;
    case F::Quad8:
      return CellType::Quad8;
    case F::Quad9:
      return CellType::Quad9;
    default:
      TC_VERIFY(false, "a line facet has no 2D reference cell");
      return CellType::Tri3;
  }
}

bool is_simplex(CellType t) {
  const CellType c = corner_type(t);
  return c == CellType::Tri3 || c == CellType::Tet4;
}

// ---- Shape functions ------------------------------------------------------------------------

/// The 1D Lagrange function of the node at s ∈ {−1, 0, 1} on the nodes {−1, 0, 1} (order 2)
/// or {−1, 1} (order 1), and its derivative.
void lagrange_1d(int order, double s, double x, double& l, double& dl) {
  if (order == 1) {
    l = 0.5 * (1 + s * x);
    dl = 0.5 * s;
  } else if (s == 0) {
    l = 1 - x * x;
    dl = -2 * x;
  } else {
    l = 0.5 * x * (x + s);
    dl = x + 0.5 * s;
  }
}

/// Tensor-product Lagrange functions on [−1, 1]^d (Line, Quad4, Quad9, Hex8, Hex27).
template <class Node>
void tensor_lagrange(int dim, int order, int nn, Node node, const Point& xi, double* n,
                     double* dn) {
  for (int a = 0; a < nn; ++a) {
    const Point s = node(a);
    double l[3] = {1, 1, 1}, dl[3] = {0, 0, 0};
    for (int k = 0; k < dim; ++k) lagrange_1d(order, s[k], xi[k], l[k], dl[k]);
    n[a] = 1;
    for (int k = 0; k < dim; ++k) n[a] *= l[k];
    for (int j = 0; j < 3; ++j) {
      double g = j < dim ? dl[j] : 0.0;
      for (int k = 0; k < dim && j < dim; ++k)
        if (k != j) g *= l[k];
      dn[3 * a + j] = g;
    }
  }
}

/// Serendipity functions on [−1, 1]^d (Quad8, Hex20). Corner s ∈ {±1}^d:
/// 2^−d Π(1 + s_k ξ_k) (Σ s_k ξ_k − (d − 1)); edge node with s_m = 0:
/// 2^{1−d} (1 − ξ_m²) Π_{k≠m} (1 + s_k ξ_k).
void serendipity(CellType t, const Point& xi, double* n, double* dn) {
  const int dim = dimension(t), nn = n_nodes(t);
  for (int a = 0; a < nn; ++a) {
    const Point s = reference_node(t, a);
    int m = -1;
    for (int k = 0; k < dim; ++k)
      if (s[k] == 0) m = k;
    double f[3], df[3];  // the factors along each axis and their derivatives
    double scale = 0;
    for (int k = 0; k < dim; ++k) {
      if (k == m) {
        f[k] = 1 - xi[k] * xi[k];
        df[k] = -2 * xi[k];
      } else {
        f[k] = 1 + s[k] * xi[k];
        df[k] = s[k];
      }
    }
    const double prod = dim == 2 ? f[0] * f[1] : f[0] * f[1] * f[2];
    for (int j = 0; j < 3; ++j) dn[3 * a + j] = 0;
    if (m >= 0) {
      scale = dim == 2 ? 0.5 : 0.25;
      n[a] = scale * prod;
      for (int j = 0; j < dim; ++j) {
        double g = scale * df[j];
        for (int k = 0; k < dim; ++k)
          if (k != j) g *= f[k];
        dn[3 * a + j] = g;
      }
    } else {
      scale = dim == 2 ? 0.25 : 0.125;
      double sum = -(dim - 1);
      for (int k = 0; k < dim; ++k) sum += s[k] * xi[k];
      n[a] = scale * prod * sum;
      for (int j = 0; j < dim; ++j) {
        double g = scale * df[j] * sum;
        for (int k = 0; k < dim; ++k)
          if (k != j) g *= f[k];
        dn[3 * a + j] = g + scale * prod * s[j];
      }
    }
  }
}

/// Lagrange functions on the simplices in barycentric coordinates L_0 = 1 − Σξ, L_k = ξ_k:
/// order 1 L_a; order 2 L_a(2L_a − 1) at the corners and 4 L_a L_b on edge (a, b).
void simplex(CellType t, const Point& xi, double* n, double* dn) {
  const int dim = dimension(t);
  double l[4], dl[4][3] = {};
  l[0] = 1;
  for (int k = 0; k < dim; ++k) {
    l[0] -= xi[k];
    l[k + 1] = xi[k];
    dl[0][k] = -1;
    dl[k + 1][k] = 1;
  }
  const int nc = dim + 1;
  const bool quadratic = order(t) == 2;
  for (int a = 0; a < nc; ++a) {
    n[a] = quadratic ? l[a] * (2 * l[a] - 1) : l[a];
    for (int j = 0; j < 3; ++j) dn[3 * a + j] = (quadratic ? 4 * l[a] - 1 : 1.0) * dl[a][j];
  }
  if (!quadratic) return;
  for (const auto& e : edges(t)) {
    n[e.mid] = 4 * l[e.a] * l[e.b];
    for (int j = 0; j < 3; ++j) dn[3 * e.mid + j] = 4 * (l[e.a] * dl[e.b][j] + l[e.b] * dl[e.a][j]);
  }
}

}  // namespace

int order(CellType t) {
  return corner_type(t) == t ? 1 : 2;
}

int order(FacetType t) {
  return corner_type(t) == t ? 1 : 2;
}

CellType corner_type(CellType t) {
  switch (t) {
    case CellType::Tri6:
      return CellType::Tri3;
    case CellType::Quad8:
    case CellType::Quad9:
      return CellType::Quad4;
    case CellType::Tet10:
      return CellType::Tet4;
    case CellType::Hex20:
    case CellType::Hex27:
      return CellType::Hex8;
    default:
      return t;
  }
}

FacetType corner_type(FacetType t) {
  switch (t) {
    case F::Line3:
      return F::Line2;
    case F::Tri6:
      return F::Tri3;
    case F::Quad8:
    case F::Quad9:
      return F::Quad4;
    default:
      return t;
  }
}

int n_corners(CellType t) {
  return n_nodes(corner_type(t));
}

std::span<const CellEdge> edges(CellType t) {
  const bool first = order(t) == 1;
  switch (corner_type(t)) {
    case CellType::Tri3:
      return first ? std::span<const CellEdge>(kTriEdges1) : kTriEdges;
    case CellType::Quad4:
      return first ? std::span<const CellEdge>(kQuadEdges1) : kQuadEdges;
    case CellType::Tet4:
      return first ? std::span<const CellEdge>(kTetEdges1) : kTetEdges;
    default:
      return first ? std::span<const CellEdge>(kHexEdges1) : kHexEdges;
  }
}

std::span<const LocalFace> local_faces(CellType t) {
  if (order(t) == 1) return corner_faces(t);
  // Built once (thread-safe static initialisation), immutable afterwards.
  static const std::vector<LocalFace> faces[] = {{},
                                                 {},
                                                 {},
                                                 {},
                                                 derive_faces(CellType::Tri6),
                                                 derive_faces(CellType::Quad8),
                                                 derive_faces(CellType::Quad9),
                                                 derive_faces(CellType::Tet10),
                                                 derive_faces(CellType::Hex20),
                                                 derive_faces(CellType::Hex27)};
  return faces[static_cast<int>(t)];
}

Point reference_node(CellType t, int a) {
  TC_VERIFY(a >= 0 && a < n_nodes(t), "a node of the cell");
  const int nc = n_corners(t);
  if (a < nc) return corner(t, a);
  const auto e = edges(t);
  if (a < nc + static_cast<int>(e.size())) {
    const auto& edge = e[static_cast<std::size_t>(a - nc)];
    const Point p = corner(t, edge.a), q = corner(t, edge.b);
    return {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
  }
  if (t == CellType::Hex27 && a < 26) return kHexFaceCentres[a - 20];
  return {0, 0, 0};  // the centre of Quad9 and Hex27
}

Point reference_node(FacetType t, int a) {
  TC_VERIFY(a >= 0 && a < n_nodes(t), "a node of the facet");
  if (t == F::Line2 || t == F::Line3) return {a == 0 ? -1.0 : a == 1 ? 1.0 : 0.0, 0, 0};
  return reference_node(as_cell(t), a);
}

void shape_functions(CellType t, const Point& xi, double* n, double* dn) {
  if (is_simplex(t)) return simplex(t, xi, n, dn);
  if (t == CellType::Quad8 || t == CellType::Hex20) return serendipity(t, xi, n, dn);
  tensor_lagrange(
      dimension(t), order(t), n_nodes(t), [t](int a) { return reference_node(t, a); }, xi, n, dn);
}

void shape_functions(FacetType t, const Point& xi, double* n, double* dn) {
  if (t == F::Line2 || t == F::Line3)
    return tensor_lagrange(
        1, order(t), n_nodes(t), [t](int a) { return reference_node(t, a); }, xi, n, dn);
  shape_functions(as_cell(t), xi, n, dn);
}

}  // namespace tc::mesh
