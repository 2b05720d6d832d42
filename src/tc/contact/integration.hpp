#pragma once
// Integration stage of the mortar pair (Tribol's "integ"): quadrature on the mortar segments,
// the cells where one master face covers one slave face, in the slave face's auxiliary plane.
// A 3D segment (a convex clip polygon) is split into a fan of triangles; a 2D segment is an
// interval of the slave line.
//
// Exactness. On affine facets (Line2, Tri3, parallelogram Quad4) the shape functions are
// polynomials of the plane coordinates: degree 1 (Line2, Tri3) or 2 (bilinear). The mortar
// matrices D and M integrate products of two of them (the dual ψ are combinations of the φ of
// the same face), degree ≤ 2 in 2D and ≤ 4 in 3D; L_θγ integrates three (γ = Σγ_kφ_k), degree
// ≤ 3 and ≤ 6. Gauss–Legendre with n points is exact to degree 2n − 1 on a line, and the
// n × n collapsed (Duffy) Gauss product to degree 2n − 2 on a triangle (the collapse adds the
// factor 1 − u). Hence n = 2 (line) and n = 3 (9 points per triangle) for D and M, and n = 3
// and n = 4 (16 points) for the thermal terms. On general quadrilaterals the inverse bilinear
// map is not polynomial and the rules are only accurate, not exact.
#include <span>

#include "tc/contact/geometry.hpp"

namespace tc::contact {

struct LinePoint {
  double s = 0, w = 0;  // on [0, 1]; weights sum to 1
};
struct TrianglePoint {
  double r = 0, s = 0, w = 0;  // on the unit triangle; weights sum to 1 (multiply by the area)
};
/// n-point Gauss–Legendre on [0, 1] (n = 1..4), exact to degree 2n − 1.
[[nodiscard]] std::span<const LinePoint> gauss_line(int n);
/// n × n collapsed Gauss product on a triangle (n = 1..4), exact to total degree 2n − 2.
[[nodiscard]] std::span<const TrianglePoint> gauss_triangle(int n);

/// Points per direction for the mortar matrices and for the thermal terms (see above).
inline constexpr int mortar_points = 3, thermal_points = 4;
inline constexpr int mortar_points_2d = 2, thermal_points_2d = 3;

/// The part of slave face `slave` covered by master face `master`, in the slave face's plane:
/// in 3D the clip polygon, in 2D the interval [cell.v[0][0], cell.v[1][0]].
struct MortarSegment {
  int slave = -1, master = -1;
  Polygon cell;
};

/// A facet with its vertices projected onto a slave face's plane (facet order).
struct PlacedFacet {
  const FacetPoints* facet = nullptr;
  std::array<Vec2, 4> q{};
  PlaneMap map;
};
[[nodiscard]] PlacedFacet place(const FacetPoints& f, const FacePlane& plane);

/// A quadrature point of a segment: slave and master shape functions at the points of the two
/// faces that project onto it, and the weight of dS on the slave surface.
struct MortarPoint {
  ShapeValues slave, master;
  double weight = 0;
};

/// Calls f(MortarPoint) at each quadrature point of `cell` (n points per direction). `warped`:
/// the slave face is a non-planar Quad4, whose surface element differs from the plane's.
template <class F>
void for_each_point(int dim, const FacePlane& plane, const PlacedFacet& slave, bool warped,
                    const PlacedFacet& master, const Polygon& cell, int n, F&& f) {
  auto at = [&](const Vec2& p, double w) {
    MortarPoint q;
    const Vec2 xs = slave.map.inverse(p);
    q.slave = facet_shape(slave.facet->type, xs);
    q.master = facet_shape(master.facet->type, master.map.inverse(p));
    q.weight = warped ? w * area_ratio(*slave.facet, plane, xs) : w;
    f(q);
  };
  if (dim == 2) {
    const double lo = cell.v[0][0], len = cell.v[1][0] - lo;
    for (const auto& g : gauss_line(n)) at({lo + g.s * len, 0}, g.w * len);
    return;
  }
  const Vec2& a = cell.v[0];
  for (int i = 1; i + 1 < cell.n; ++i) {
    const Vec2& b = cell.v[i];
    const Vec2& c = cell.v[i + 1];
    const double area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    if (!(area > 0)) continue;  // a degenerate fan triangle (collinear clip vertices)
    for (const auto& g : gauss_triangle(n)) {
      const Vec2 p{a[0] + g.r * (b[0] - a[0]) + g.s * (c[0] - a[0]),
                   a[1] + g.r * (b[1] - a[1]) + g.s * (c[1] - a[1])};
      at(p, g.w * area);
    }
  }
}

}  // namespace tc::contact
