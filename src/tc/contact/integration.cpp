#include "tc/contact/integration.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::contact {

namespace {

/// Gauss–Legendre nodes and weights on [−1, 1].
struct Rule1d {
  std::vector<double> x, w;
};

/// The roots of P_n by Newton from Tricomi's estimates, w = 2/((1 − x²)P_n'(x)²): converged
/// to round-off (|δx| < 1e-16) in a few steps for n ≤ 8.
Rule1d newton_legendre(int n) {
  Rule1d r{std::vector<double>(n), std::vector<double>(n)};
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    double x = -std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;  // P_0, P_1, then the three-term recurrence to P_n
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    r.x[i] = x;
    r.w[i] = 2 / ((1 - x * x) * dp * dp);
  }
  return r;
}

Rule1d legendre(int n) {
  switch (n) {
    case 1:
      return {{0.0}, {2.0}};
    case 2: {
      const double a = 1 / std::sqrt(3.0);
      return {{-a, a}, {1.0, 1.0}};
    }
    case 3: {
      const double a = std::sqrt(0.6);
      return {{-a, 0.0, a}, {5.0 / 9, 8.0 / 9, 5.0 / 9}};
    }
    case 4: {
      const double s = 2 * std::sqrt(1.2);
      const double a = std::sqrt((3 - s) / 7), b = std::sqrt((3 + s) / 7);
      const double wa = (18 + std::sqrt(30.0)) / 36, wb = (18 - std::sqrt(30.0)) / 36;
      return {{-b, -a, a, b}, {wb, wa, wa, wb}};
    }
    default:
      if (n < 1 || n > kMaxGaussPoints)
        throw Error("contact quadrature: 1 to " + std::to_string(kMaxGaussPoints) +
                    " Gauss points per direction, asked for " + std::to_string(n));
      return newton_legendre(n);
  }
}

std::vector<LinePoint> make_line(int n) {
  const Rule1d g = legendre(n);
  std::vector<LinePoint> out;
  for (int i = 0; i < n; ++i) out.push_back({0.5 * (1 + g.x[i]), 0.5 * g.w[i]});
  return out;
}

/// (r, s) = (u, v(1 − u)) maps the unit square onto the unit triangle with Jacobian 1 − u.
std::vector<TrianglePoint> make_triangle(int n) {
  const auto line = make_line(n);
  std::vector<TrianglePoint> out;
  for (const auto& u : line)
    for (const auto& v : line) out.push_back({u.s, v.s * (1 - u.s), 2 * u.w * v.w * (1 - u.s)});
  return out;
}

}  // namespace

std::span<const LinePoint> gauss_line(int n) {
  static const std::vector<LinePoint> rules[] = {make_line(1), make_line(2), make_line(3),
                                                 make_line(4), make_line(5), make_line(6),
                                                 make_line(7), make_line(8)};
  if (n < 1 || n > kMaxGaussPoints) (void)legendre(n);  // throws with the reason
  return rules[n - 1];
}

std::span<const TrianglePoint> gauss_triangle(int n) {
  static const std::vector<TrianglePoint> rules[] = {
      make_triangle(1), make_triangle(2), make_triangle(3), make_triangle(4),
      make_triangle(5), make_triangle(6), make_triangle(7), make_triangle(8)};
  if (n < 1 || n > kMaxGaussPoints) (void)legendre(n);
  return rules[n - 1];
}

namespace {

/// The degree of a facet's shape functions in the plane coordinates of an affine facet.
int shape_degree(mesh::FacetType t) {
  switch (t) {
    case mesh::FacetType::Line2:
    case mesh::FacetType::Tri3:
      return 1;
    case mesh::FacetType::Quad4:
    case mesh::FacetType::Line3:
    case mesh::FacetType::Tri6:
      return 2;
    case mesh::FacetType::Quad8:
      return 3;
    default:
      return 4;
  }
}

}  // namespace

int mortar_rule(int dim, mesh::FacetType s, mesh::FacetType m, bool thermal) {
  if (mesh::order(s) == 1 && mesh::order(m) == 1)
    return dim == 2 ? (thermal ? thermal_points_2d : mortar_points_2d)
                    : (thermal ? thermal_points : mortar_points);
  const int ps = shape_degree(s), pm = shape_degree(m);
  // D and M: φ_a^s φ_b^s (the slave's mass, which the dual basis inverts) and φ_a^s φ_c^m;
  // L_θγ: three functions of which one or more are the slave's.
  const int degree =
      thermal ? std::max({3 * ps, 2 * ps + pm, ps + 2 * pm}) : std::max(2 * ps, ps + pm);
  // A line rule is exact to 2n − 1, the collapsed triangle rule to 2n − 2.
  return dim == 2 ? (degree + 2) / 2 : (degree + 3) / 2;
}

ShareRange vertex_share_range(mesh::FacetType t) {
  // ∫φ̃_v = ∫φ_v + 2α∫φ_e > 0 and ∫φ̃_e = (1 − 2α)∫φ_e > 0 with (∫φ_v, ∫φ_e) = (0, ⅓) of the
  // area on a Tri6 and (−1/12, ⅓) on a Quad8.
  if (t == mesh::FacetType::Tri6) return {0.0, 0.5};
  if (t == mesh::FacetType::Quad8) return {0.125, 0.5};
  return {};
}

BasisTransformation basis_transformation(mesh::FacetType type, double alpha) {
  BasisTransformation b;
  b.n = mesh::n_nodes(type);
  b.alpha = type == mesh::FacetType::Tri6 || type == mesh::FacetType::Quad8 ? alpha : 0.0;
  for (int a = 0; a < b.n; ++a) b.t[a][a] = b.inv[a][a] = 1;
  if (b.identity()) return b;
  // Mid-edge node corners + i is on the edge from corner i to corner i + 1 (mesh::edges).
  const int corners = mesh::n_nodes(mesh::corner_type(type));
  const double a = b.alpha, keep = 1 - 2 * a;
  for (int i = 0; i < corners; ++i) {
    const int e = corners + i;
    b.t[e][e] = keep;
    b.inv[e][e] = 1 / keep;
    for (const int v : {i, (i + 1) % corners}) {
      b.t[v][e] = a;
      b.inv[v][e] = -a / keep;
    }
  }
  return b;
}

PlacedFacet place(const FacetPoints& f, const FacePlane& plane) {
  PlacedFacet p;
  p.facet = &f;
  for (int a = 0; a < f.n; ++a) p.q[a] = plane.project(f.x[a]);
  p.map = PlaneMap::of(f.type, p.q);
  return p;
}

void check_slave_bases(std::span<const mesh::Facet> facets, const std::string& name, double alpha) {
  // Quad9 faces (T = I) next to Tri6 or Quad8 faces would have no single transformed basis
  // along their common edges.
  bool plain = false, transformed = false;
  for (const auto& f : facets) {
    const ShareRange r = vertex_share_range(f.type);  // empty where T = I
    plain = plain || f.type == mesh::FacetType::Quad9;
    transformed = transformed || r.hi > 0;
    if (r.hi > 0 && !(alpha > r.lo && alpha < r.hi))
      throw Error("mortar pair: vertex_share must be in (" + std::to_string(r.lo) + ", " +
                  std::to_string(r.hi) + ") on " + mesh::name(f.type) +
                  " slave faces (positive weights), got " + std::to_string(alpha));
  }
  if (plain && transformed)
    throw MeshError("mortar pair: slave boundary '" + name +
                    "' mixes Quad9 faces with Tri6 or Quad8 faces; expected Quad9 faces alone, "
                    "or Tri6 and Quad8 faces (their multiplier bases differ along common edges)");
}

}  // namespace tc::contact
