// Geometric checks of a mesh: signed cell measures, inverted or degenerate cells, and
// duplicated nodes.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/mesh/mesh.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::mesh {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Point& a, const Point& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

double cross2(const Vec& a, const Vec& b) {
  return a[0] * b[1] - a[1] * b[0];
}

double det3(const Vec& a, const Vec& b, const Vec& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// Quad4 and Hex8 nodes by their reference coordinates in {0,1}^d (Gmsh = VTK numbering:
// counter-clockwise bottom face, then the top face above it).
int corner_node(int a, int b, int c) {
  static constexpr int face[2][2] = {{0, 3}, {1, 2}};  // [a][b]
  return 4 * c + face[a][b];
}

/// Columns of the Jacobian of the bilinear/trilinear map from [0,1]^d at reference point xi.
std::array<Vec, 3> jacobian(const Mesh& m, int c, const Vec& xi) {
  const auto v = m.cell(c);
  const int dim = m.dim();
  std::array<Vec, 3> j{};
  const int n_c = dim == 3 ? 2 : 1;
  for (int cc = 0; cc < n_c; ++cc)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const int bits[3] = {a, b, cc};
        const Point& p = m.point(v[corner_node(a, b, cc)]);
        for (int k = 0; k < dim; ++k) {
          // dN/dxi_k of N = prod_l (bits_l ? xi_l : 1 − xi_l)
          double d = bits[k] ? 1.0 : -1.0;
          for (int l = 0; l < dim; ++l)
            if (l != k) d *= bits[l] ? xi[l] : 1.0 - xi[l];
          for (int i = 0; i < 3; ++i) j[k][i] += d * p[i];
        }
      }
  return j;
}

double jacobian_det(const Mesh& m, int c, const Vec& xi) {
  const auto j = jacobian(m, c, xi);
  return m.dim() == 2 ? cross2(j[0], j[1]) : det3(j[0], j[1], j[2]);
}

// ---- Second-order cells: the isoparametric map of all their nodes --------------------------

/// det ∂x/∂ξ of a cell at reference point xi, from the shape functions of its type.
double isoparametric_det(const Mesh& m, int c, const Vec& xi) {
  const auto v = m.cell(c);
  double n[kMaxCellNodes], dn[3 * kMaxCellNodes];
  shape_functions(m.cell_type(c), xi, n, dn);
  std::array<Vec, 3> j{};  // j[k] = ∂x/∂ξ_k
  for (std::size_t a = 0; a < v.size(); ++a)
    for (int k = 0; k < m.dim(); ++k)
      for (int i = 0; i < 3; ++i) j[k][i] += dn[3 * a + k] * m.point(v[a])[i];
  return m.dim() == 2 ? cross2(j[0], j[1]) : det3(j[0], j[1], j[2]);
}

struct WeightedPoint {
  Vec xi;
  double w;
};

/// 4-point Gauss per direction on [−1, 1]^d, collapsed onto the simplex (Duffy) for Tri/Tet:
/// exact to degree 7 per direction, more than det J of any second-order cell needs (Hex27:
/// degree 5 per direction; Tet10: total degree 3).
std::vector<WeightedPoint> gauss4(CellType t) {
  constexpr double x[4] = {-0.86113631159405257522, -0.33998104358485626480, 0.33998104358485626480,
                           0.86113631159405257522};
  constexpr double w[4] = {0.34785484513745385737, 0.65214515486254614263, 0.65214515486254614263,
                           0.34785484513745385737};
  const int d = dimension(t);
  const bool simplex = corner_type(t) == CellType::Tri3 || corner_type(t) == CellType::Tet4;
  std::vector<WeightedPoint> out;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < (d == 3 ? 4 : 1); ++k) {
        if (!simplex) {
          out.push_back({{x[i], x[j], d == 3 ? x[k] : 0.0}, w[i] * w[j] * (d == 3 ? w[k] : 1.0)});
          continue;
        }
        // [0, 1]^d → simplex: (s, r, q) ↦ (s, r(1 − s), q(1 − s)(1 − r)).
        const double s = 0.5 * (1 + x[i]), r = 0.5 * (1 + x[j]), q = 0.5 * (1 + x[k]);
        const double ws = 0.5 * w[i], wr = 0.5 * w[j], wq = 0.5 * w[k];
        if (d == 2)
          out.push_back({{s, r * (1 - s), 0}, ws * wr * (1 - s)});
        else
          out.push_back({{s, r * (1 - s), q * (1 - s) * (1 - r)},
                         ws * wr * wq * (1 - s) * (1 - s) * (1 - r)});
      }
  return out;
}

const std::vector<WeightedPoint>& gauss4_table(CellType t) {
  static const std::vector<WeightedPoint> tables[] = {{},
                                                      {},
                                                      {},
                                                      {},
                                                      gauss4(CellType::Tri6),
                                                      gauss4(CellType::Quad8),
                                                      gauss4(CellType::Quad9),
                                                      gauss4(CellType::Tet10),
                                                      gauss4(CellType::Hex20),
                                                      gauss4(CellType::Hex27)};
  return tables[static_cast<int>(t)];
}

/// What is wrong with a second-order cell ("" when nothing): its Jacobian must be positive at
/// every node (where a curved edge folds first) and every point of the 4^d rule, which holds
/// the kernels' points within its span (fem's rules lie inside the same reference cell).
std::string curved_cell_problem(const Mesh& m, int c, double tol) {
  const CellType t = m.cell_type(c);
  std::ostringstream msg;
  msg.precision(3);
  for (int a = 0; a < n_nodes(t); ++a) {
    const double det = isoparametric_det(m, c, reference_node(t, a));
    if (!(det > tol)) {
      msg << "Jacobian " << det << " at node " << a
          << (det < 0 ? " (a curved edge folds, or the cell is inverted)" : " (degenerate)");
      return msg.str();
    }
  }
  for (const auto& p : gauss4_table(t)) {
    const double det = isoparametric_det(m, c, p.xi);
    if (!(det > tol)) {
      msg << "Jacobian " << det << " at the quadrature point (" << p.xi[0] << ", " << p.xi[1]
          << ", " << p.xi[2] << ")"
          << (det < 0 ? " (a curved edge folds, or the cell is inverted)" : " (degenerate)");
      return msg.str();
    }
  }
  return "";
}

/// Largest distance between two nodes of cell c, the length scale of "zero measure".
double cell_size(const Mesh& m, int c) {
  const auto v = m.cell(c);
  double h2 = 0;
  for (std::size_t a = 0; a < v.size(); ++a)
    for (std::size_t b = a + 1; b < v.size(); ++b) {
      const Vec d = sub(m.point(v[a]), m.point(v[b]));
      h2 = std::max(h2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
  return std::sqrt(h2);
}

/// What is wrong with cell c, or "" when nothing is. A cell is bad when its measure or its
/// Jacobian at a corner is not above 1e-12 h^d: rounding errors are ~1e-16 h^d, and any cell
/// a solver can use is many orders of magnitude above that bound.
std::string cell_problem(const Mesh& m, int c) {
  const CellType t = m.cell_type(c);
  const double scale = std::pow(cell_size(m, c), m.dim());
  const double tol = 1e-12 * scale;
  const double measure = cell_measure(m, c);
  std::ostringstream msg;
  msg.precision(3);
  if (!(measure > tol)) {  // also catches NaN
    msg << (m.dim() == 2 ? "area " : "volume ") << measure
        << (measure < 0 ? " (inverted)" : " (degenerate)");
    return msg.str();
  }
  if (order(t) == 2) return curved_cell_problem(m, c, tol);
  // A simplex has a constant Jacobian; a Quad4/Hex8 can be non-convex (Jacobian of the wrong
  // sign at a corner) while its measure is positive.
  if (t == CellType::Tri3 || t == CellType::Tet4) return "";
  const int n_c = m.dim() == 3 ? 2 : 1;
  for (int cc = 0; cc < n_c; ++cc)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double det = jacobian_det(m, c, {double(a), double(b), double(cc)});
        if (!(det > tol)) {
          msg << "Jacobian " << det << " at corner " << corner_node(a, b, cc)
              << (det < 0 ? " (non-convex or inverted)" : " (degenerate)");
          return msg.str();
        }
      }
  return "";
}

}  // namespace

double cell_measure(const Mesh& m, int c) {
  const auto v = m.cell(c);
  const auto p = [&](int a) -> const Point& { return m.point(v[a]); };
  switch (m.cell_type(c)) {
    case CellType::Tri3:
      return 0.5 * cross2(sub(p(1), p(0)), sub(p(2), p(0)));
    case CellType::Quad4:
      // The area of a bilinear quad is exactly that of its polygon (half the cross product
      // of the diagonals).
      return 0.5 * cross2(sub(p(2), p(0)), sub(p(3), p(1)));
    case CellType::Tet4:
      return det3(sub(p(1), p(0)), sub(p(2), p(0)), sub(p(3), p(0))) / 6.0;
    case CellType::Hex8: {
      // det J of a trilinear map is of degree ≤ 2 in each reference coordinate, so the
      // 2×2×2 Gauss rule (exact to degree 3 per direction) gives the exact volume.
      const double g = 0.5 / std::sqrt(3.0);
      double vol = 0;
      for (const double z : {0.5 - g, 0.5 + g})
        for (const double y : {0.5 - g, 0.5 + g})
          for (const double x : {0.5 - g, 0.5 + g}) vol += 0.125 * jacobian_det(m, c, {x, y, z});
      return vol;
    }
    default: {
      double measure = 0;
      for (const auto& q : gauss4_table(m.cell_type(c)))
        measure += q.w * isoparametric_det(m, c, q.xi);
      return measure;
    }
  }
  return 0;
}

void check_cells(const Mesh& m, const std::string& source) {
  constexpr int max_listed = 10;
  // Coordinates first: a node at 1e300 made its cells' measures overflow, reported as a
  // "degenerate" cell of ordinary area (issue 42 M1).
  for (int a = 0; a < m.n_nodes(); ++a) {
    const Point& x = m.point(a);
    const auto beyond = [](double v) { return !(std::abs(v) <= kMaxCoordinate); };  // NaN too
    if (beyond(x[0]) || beyond(x[1]) || beyond(x[2])) {
      std::ostringstream msg;
      msg.precision(6);
      const bool finite = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
      msg << source << ": node " << a << " (0-based) at (" << x[0] << ", " << x[1] << ", " << x[2]
          << ") has a coordinate " << (finite ? "beyond" : "that is not finite, expected within")
          << " ±" << kMaxCoordinate
          << " m: cell measures multiply coordinates, which would overflow or lose every digit "
             "of the cells (expected a mesh in metres)";
      throw MeshError(msg.str());
    }
  }
  std::ostringstream list;
  int n_bad = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const std::string problem = cell_problem(m, c);
    if (problem.empty()) continue;
    if (++n_bad <= max_listed)
      list << "\n  cell " << c << " (" << name(m.cell_type(c)) << "): " << problem;
  }
  if (n_bad == 0) return;
  std::ostringstream msg;
  msg << source << ": " << n_bad << " inverted or degenerate cells (0-based cell indices"
      << (n_bad > max_listed ? ", first 10 listed" : "") << "):" << list.str();
  throw MeshError(msg.str());
}

void check_no_fold(const Mesh& m, const std::string& source) {
  if (m.dim() != 2) return;
  // Each directed edge (a → b) of a counter-clockwise cell has the cell on its left. In a mesh
  // that does not overlap itself an interior edge is walked once each way; walked twice the
  // same way, two cells lie on the same side of it: the mesh folds there.
  constexpr int max_listed = 10;
  std::unordered_map<long long, int> left_of;  // directed edge → its cell
  left_of.reserve(static_cast<size_t>(4 * m.n_cells()));
  const auto key = [&](int a, int b) {
    return static_cast<long long>(a) * static_cast<long long>(m.n_nodes()) + b;
  };
  std::ostringstream list;
  int n_bad = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto v = m.cell(c);
    // The corners' cycle: a second-order cell's edges join its corners too.
    const auto nc = static_cast<std::size_t>(n_corners(m.cell_type(c)));
    for (std::size_t i = 0; i < nc; ++i) {
      const int a = v[i], b = v[(i + 1) % nc];
      const auto [it, fresh] = left_of.emplace(key(a, b), c);
      if (fresh) continue;
      if (++n_bad <= max_listed)
        list << "\n  cells " << it->second << " and " << c << " both lie left of edge " << a
             << " -> " << b;
    }
  }
  if (n_bad == 0) return;
  std::ostringstream msg;
  msg << source << ": the mesh folds over itself at " << n_bad
      << " edge(s): cells listed clockwise and counter-clockwise in one mesh overlap where they "
         "meet (0-based cell and node indices"
      << (n_bad > max_listed ? ", first 10 listed" : "") << "):" << list.str()
      << "\n  expected every cell of a 2D mesh in one orientation (all counter-clockwise, or "
         "all clockwise: then they are turned as a whole) and no cell overlapping another";
  throw MeshError(msg.str());
}

std::vector<std::pair<int, int>> find_duplicate_nodes(const Mesh& m) {
  const auto& pts = m.points();
  std::vector<std::pair<int, int>> out;
  if (pts.size() < 2) return out;
  Point lo = pts[0], hi = pts[0];
  for (const auto& p : pts)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  const Vec d = sub(hi, lo);
  const double tol = 1e-12 * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  // A bounding box beyond double's range (or a NaN) has no tolerance to bin by; the binning
  // below would convert NaN/Inf to integers. Such a mesh fails check_cells anyway.
  if (!std::isfinite(tol)) return out;
  // Bin the points on a grid of spacing h ≫ tol and sort by bin: two points within tol are in
  // the same bin or in adjacent ones, and a point's neighbour bins are found by binary search.
  // h = 1000 tol keeps most points away from bin faces, so usually one bin is searched.
  const double h = tol > 0 ? 1e3 * tol : 1.0;
  using Bin = std::array<long long, 3>;
  const auto bin_of = [&](const Point& p, double shift) {
    Bin b{};
    for (int k = 0; k < 3; ++k)
      b[k] = static_cast<long long>(std::floor((p[k] - lo[k] + shift) / h));
    return b;
  };
  std::vector<std::pair<Bin, int>> sorted;
  sorted.reserve(pts.size());
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) sorted.emplace_back(bin_of(pts[i], 0), i);
  std::sort(sorted.begin(), sorted.end());

  const auto close = [&](const Point& a, const Point& b) {
    for (int k = 0; k < 3; ++k)
      if (std::abs(a[k] - b[k]) > tol) return false;
    return true;
  };
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    const Bin first = bin_of(pts[i], -tol), last = bin_of(pts[i], tol);
    Bin b{};
    for (b[0] = first[0]; b[0] <= last[0]; ++b[0])
      for (b[1] = first[1]; b[1] <= last[1]; ++b[1])
        for (b[2] = first[2]; b[2] <= last[2]; ++b[2]) {
          const auto lower = std::lower_bound(sorted.begin(), sorted.end(), std::pair{b, -1});
          for (auto it = lower; it != sorted.end() && it->first == b; ++it)
            if (it->second > i && close(pts[i], pts[it->second])) out.emplace_back(i, it->second);
        }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace tc::mesh
