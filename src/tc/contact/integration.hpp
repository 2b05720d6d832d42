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
//
// Second order (mortar_rule): on affine facets with straight edges Line3 and Tri6 functions
// have degree 2, Quad8 3 (ξ²η), Quad9 4 (ξ²η²), and a product of k functions of degrees p_i
// has degree Σp_i; the rule takes the fewest points exact for it (D, M with the slave's mass:
// max(2p_s, p_s + p_m); L_θγ: max(3p_s, 2p_s + p_m, p_s + 2p_m)), e.g. Quad9 against Quad9
// n = 5 for D and M, n = 7 for L_θγ.
#include <span>
#include <string>

#include "tc/contact/geometry.hpp"

namespace tc::contact {

struct LinePoint {
  double s = 0, w = 0;  // on [0, 1]; weights sum to 1
};
struct TrianglePoint {
  double r = 0, s = 0, w = 0;  // on the unit triangle; weights sum to 1 (multiply by the area)
};
/// The most points per direction of the rules below.
inline constexpr int kMaxGaussPoints = 8;
/// n-point Gauss–Legendre on [0, 1] (n = 1..8), exact to degree 2n − 1.
[[nodiscard]] std::span<const LinePoint> gauss_line(int n);
/// n × n collapsed Gauss product on a triangle (n = 1..8), exact to total degree 2n − 2.
[[nodiscard]] std::span<const TrianglePoint> gauss_triangle(int n);

/// Points per direction for the mortar matrices and for the thermal terms of first-order
/// facets (see above).
inline constexpr int mortar_points = 3, thermal_points = 4;
inline constexpr int mortar_points_2d = 2, thermal_points_2d = 3;

/// Points per direction for a segment of a slave facet of type s against a master facet of
/// type m: the constants above when both are of first order, else the fewest exact for the
/// products on affine facets (see above); `thermal`: the triple products of L_θγ.
[[nodiscard]] int mortar_rule(int dim, mesh::FacetType s, mesh::FacetType m, bool thermal);

/// The part of slave face `slave` covered by master face `master`, in the slave face's plane:
/// in 3D the clip polygon, in 2D the interval [cell.v[0][0], cell.v[1][0]].
struct MortarSegment {
  int slave = -1, master = -1;
  Polygon cell;
};

/// The basis transformation of a second-order slave facet (Popp, Wohlmuth, Gee & Wall, SIAM J.
/// Sci. Comput. 2012, §4.4.1): φ̃ = T φ with φ̃_v = φ_v + α Σ_{e ∋ v} φ_e at each vertex v
/// (its two mid-edge neighbours e) and φ̃_e = (1 − 2α) φ_e, so Σ φ̃ = Σ φ = 1. Tri6 and Quad8
/// have ∫φ_v = 0 and −⅓ of ∫φ_e: no dual basis biorthogonal to φ exists with positive
/// weights, while with α = ⅕ (4C's choice) ∫φ̃_v = (2/15, 1/20) × area and ∫φ̃_e = (1/5, 1/5)
/// × area. Identity (α = 0) for the first-order facets, Line3 (weights 1/6, 1/6, 2/3) and
/// Quad9 (1/36, 1/9, 4/9 × 4). Local to one facet, and globally one change of basis on the
/// slave surface, since a mid-edge node has the same two vertices in both faces it is on.
/// Other α (MortarOptions::vertex_share): the weights are 2α/3 and (1 − 2α)/3 of a Tri6's area,
/// 2α/3 − 1/12 and (1 − 2α)/3 of a Quad8's, positive for 0 < α < ½ and ⅛ < α < ½ (equal at
/// α = ¼ and 5/16: docs/choices.md, "α by measurement").
inline constexpr double kVertexShare = 0.2;
/// The open interval of α that gives positive weights to every node of a facet of type t
/// ({0, 0} where T = I).
struct ShareRange {
  double lo = 0, hi = 0;
};
[[nodiscard]] ShareRange vertex_share_range(mesh::FacetType t);
struct BasisTransformation {
  int n = 0;         // nodes of the facet
  double alpha = 0;  // 0: T = I
  double t[kFacetNodes][kFacetNodes]{};
  double inv[kFacetNodes][kFacetNodes]{};  // T⁻¹: φ_v = φ̃_v − α/(1 − 2α) Σ φ̃_e, φ_e = φ̃_e/(1 − 2α)
  [[nodiscard]] bool identity() const { return alpha == 0; }
};
/// T with the share α on Tri6 and Quad8 (the identity on every other facet type).
[[nodiscard]] BasisTransformation basis_transformation(mesh::FacetType t,
                                                       double alpha = kVertexShare);

/// A facet with its vertices projected onto a slave face's plane (facet order).
struct PlacedFacet {
  const FacetPoints* facet = nullptr;
  std::array<Vec2, kFacetNodes> q{};
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
/// the slave face is a non-planar Quad4 or a curved second-order facet, whose surface element
/// differs from the plane's (geometry.hpp's warped).
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

/// The slave surface's faces admit the transformed basis at α: every weight positive (MortarPair
/// throws Error otherwise), and no Quad9 face next to a Tri6 or Quad8 one (MeshError).
void check_slave_bases(std::span<const mesh::Facet> facets, const std::string& name, double alpha);

}  // namespace tc::contact
