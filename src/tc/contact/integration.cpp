#include "tc/contact/integration.hpp"

#include <cmath>
#include <vector>

#include "tc/core/error.hpp"

namespace tc::contact {

namespace {

/// Gauss–Legendre nodes and weights on [−1, 1].
struct Rule1d {
  std::vector<double> x, w;
};

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
      throw Error("contact quadrature: 1 to 4 Gauss points per direction, asked for " +
                  std::to_string(n));
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
                                                 make_line(4)};
  if (n < 1 || n > 4) (void)legendre(n);  // throws with the reason
  return rules[n - 1];
}

std::span<const TrianglePoint> gauss_triangle(int n) {
  static const std::vector<TrianglePoint> rules[] = {make_triangle(1), make_triangle(2),
                                                     make_triangle(3), make_triangle(4)};
  if (n < 1 || n > 4) (void)legendre(n);
  return rules[n - 1];
}

PlacedFacet place(const FacetPoints& f, const FacePlane& plane) {
  PlacedFacet p;
  p.facet = &f;
  for (int a = 0; a < f.n; ++a) p.q[a] = plane.project(f.x[a]);
  p.map = PlaneMap::of(f.type, p.q);
  return p;
}

}  // namespace tc::contact
