#pragma once
// Geometry stage of the mortar pair (the "geom" stage of LLNL Tribol): small vector algebra,
// the shape functions of contact facets, averaged nodal normals and tangents on the slave side,
// the auxiliary plane of a slave face onto which master faces are projected (Puso & Laursen
// 2004; Popp et al. 2010), 2D segment overlap and 3D polygon clipping (Sutherland–Hodgman),
// and the inverse of a projected facet map, for first- and second-order facets (Line3, Tri6,
// Quad8, Quad9: clipped on their corners' polygon when their edges are straight, on their
// sub-facets when curved; mapped by their quadratic shape functions).
// Pure functions, no PETSc, no allocation per call.
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "tc/mesh/mesh.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::contact {

using Vec3 = std::array<double, 3>;
using Vec2 = std::array<double, 2>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator*(double s, const Vec3& a) {
  return {s * a[0], s * a[1], s * a[2]};
}
inline double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
inline Vec3 normalized(const Vec3& a) {
  return (1.0 / norm(a)) * a;
}

/// The most nodes of a contact facet (Quad9).
inline constexpr int kFacetNodes = mesh::kMaxFacetNodes;

/// Values (and reference derivatives) of the shape functions of a facet. Reference cells:
/// Line2 ξ ∈ [0, 1], φ = (1 − ξ, ξ); Tri3 the unit triangle, φ = (1 − ξ − η, ξ, η); Quad4
/// [−1, 1]² in VTK order, φ_a = ¼(1 ± ξ)(1 ± η). Second order on the same cells: Line3
/// ((1 − ξ)(1 − 2ξ), ξ(2ξ − 1), 4ξ(1 − ξ)), Tri6, Quad8, Quad9 those of mesh::shape_functions.
/// Entries beyond n are 0.
struct ShapeValues {
  int n = 0;
  std::array<double, kFacetNodes> phi{};
  std::array<Vec2, kFacetNodes> dphi{};  // ∂φ_a/∂(ξ, η)
};
[[nodiscard]] ShapeValues facet_shape(mesh::FacetType t, const Vec2& xi);

/// A facet's nodes in the current configuration: n nodes, the first `corners` its vertices.
struct FacetPoints {
  mesh::FacetType type = mesh::FacetType::Line2;
  int n = 0, corners = 0;
  std::array<Vec3, kFacetNodes> x{};
};
[[nodiscard]] FacetPoints facet_points(const mesh::Facet& f, std::span<const Vec3> x);

/// Outward unit normal of a facet at its centre: Line2 (t_y, −t_x) with t = x1 − x0 (mesh.hpp),
/// Tri3 and Quad4 by the right-hand rule (for Quad4 the cross product of the diagonals, which
/// is the normal of the bilinear surface at ξ = η = 0); second order that of the curved
/// surface, x_ξ × x_η (Line3: x_ξ turned) at the reference centre.
[[nodiscard]] Vec3 centre_normal(const FacetPoints& f);
/// Unit normal of the facet at its node a (for a warped Quad4, that of the corner; second
/// order: of the curved surface at the node).
[[nodiscard]] Vec3 vertex_normal(const FacetPoints& f, int a);
/// Diameter of the facet's bounding box.
[[nodiscard]] double facet_size(const FacetPoints& f);

/// Averaged nodal normals (Popp, Gitterle, Gee, Wall 2010): at each node the normalised sum
/// of the unit vertex normals of the facets around it. Indexed by mesh node; zero for nodes
/// on none of the facets.
[[nodiscard]] std::vector<Vec3> averaged_normals(std::span<const mesh::Facet> facets,
                                                 std::span<const Vec3> x);

/// Orthonormal tangents of a unit normal n. 2D: τ = (−n_y, n_x). 3D: τ₁ is the coordinate
/// axis least aligned with n, made orthogonal to n; τ₂ = τ₁ × n. (For n = −e_z this gives
/// τ₁ = e_x, τ₂ = e_y, the frame of tests/support/contact_rows.hpp.)
void tangents_of(int dim, const Vec3& n, Vec3& t0, Vec3& t1);

/// The auxiliary plane of one slave face: through the centroid of its vertices, normal the face's
/// centre normal n₀, with in-plane axes e₁, e₂ such that (e₁, e₂, n₀) is right-handed, so the slave
/// face is counter-clockwise in plane coordinates. In 2D the "plane" is the slave line,
/// origin at vertex 0 and e₁ = the unit tangent (one coordinate; the second is 0).
struct FacePlane {
  Vec3 origin{}, normal{}, e1{}, e2{};
  [[nodiscard]] Vec2 project(const Vec3& x) const {
    const Vec3 d = x - origin;
    return {dot(d, e1), dot(d, e2)};
  }
};
[[nodiscard]] FacePlane face_plane(const FacetPoints& slave, int dim);

/// A convex (or star-shaped) polygon in plane coordinates; at most 16 vertices, enough for a
/// quadrilateral clipped by a quadrilateral (≤ 8).
struct Polygon {
  int n = 0;
  std::array<Vec2, 16> v{};
  void push(const Vec2& p) { v[n++] = p; }
};
[[nodiscard]] double signed_area(const Polygon& p);

/// The facet's vertices (corners) projected onto the plane, counter-clockwise (reversed when
/// the facet faces the other way, as master faces do); `reversed` records it so that vertex a
/// of the polygon is facet vertex order[a]. A second-order facet is clipped on this polygon of
/// its corners: exact for straight edges, a chord of each curved one.
struct ProjectedFacet {
  Polygon polygon;
  std::array<int, 4> order{0, 1, 2, 3};
};
[[nodiscard]] ProjectedFacet project(const FacetPoints& f, const FacePlane& plane);

/// Whether a second-order 3D facet has a mid-edge node off the chord of its edge's corners
/// (beyond 1e-12 of the facet's size): its corners' polygon is then not the projection of its
/// boundary. False for first-order facets, Line3 and straight-edged second-order facets.
[[nodiscard]] bool curved_edges(const FacetPoints& f);

/// A curved facet's sub-facets: its reference cell cut into `divisions` parts per edge
/// (divisions² triangles of a Tri6, divisions² quadrilaterals of a Quad8 or Quad9), each given
/// by the points of the curved facet at its corners, x(ξ) = Σ x_a φ_a(ξ): for divisions = 2 the
/// facet's nodes (and the centre x(0, 0) of a Quad8). The sub-facets' polygon follows each
/// curved edge by `divisions` chords, whose sagitta is 1/divisions² of the edge's.
inline constexpr int kMaxDivisions = 4;
struct SubFacets {
  int n = 0, corners = 0;  // sub-facets, and 3 (triangles) or 4 (quadrilaterals)
  std::array<std::array<Vec3, 4>, kMaxDivisions * kMaxDivisions> x{};
};
[[nodiscard]] SubFacets sub_facets(const FacetPoints& f, int divisions);
/// Sub-facet i projected onto the plane, counter-clockwise (as project()).
[[nodiscard]] Polygon project(const SubFacets& s, int i, const FacePlane& plane);

/// Whether the bounding boxes of two polygons overlap (touching counts).
[[nodiscard]] bool boxes_meet(const Polygon& a, const Polygon& b);

/// Sutherland–Hodgman: the part of `subject` inside the convex, counter-clockwise `clip`.
/// Points on a clip edge (within a round-off band) count as inside, so matching meshes do not
/// lose slivers of area.
[[nodiscard]] Polygon clip(const Polygon& subject, const Polygon& clip);

/// 2D: the overlap [lo, hi] of the slave segment [0, L] with the projected master segment
/// [min(a, b), max(a, b)]; empty when hi ≤ lo.
struct Interval {
  double lo = 0, hi = 0;
};
[[nodiscard]] Interval overlap(double length, double a, double b);

/// A facet's map from reference coordinates to the plane, ξ ↦ a + bξ + cη + dξη, from its
/// projected vertices q (facet order): Line2 (first coordinate only) and Tri3 have d = 0,
/// Quad4 is bilinear (d = 0 for parallelograms). A second-order facet keeps that map of its
/// corners as the start and its nodes q for the quadratic map ξ ↦ Σ_a q_a φ_a(ξ). Built once
/// per facet and plane.
struct PlaneMap {
  mesh::FacetType type = mesh::FacetType::Line2;
  Vec2 a{}, b{}, c{}, d{};
  bool affine = true;
  int n = 0;                          // nodes of a second-order facet, 0 for first order
  std::array<Vec2, kFacetNodes> q{};  // a second-order facet's projected nodes
  [[nodiscard]] static PlaneMap of(mesh::FacetType t, std::span<const Vec2> q);
  /// The reference coordinates of the facet point whose projection is p: exact when affine,
  /// else Newton from the affine part's solution (2–3 steps to round-off; second order: on
  /// the quadratic map from the corners' solution, one step when the mid-edge nodes sit at
  /// the midpoints of straight edges).
  [[nodiscard]] Vec2 inverse(const Vec2& p) const;

 private:
  [[nodiscard]] Vec2 corner_inverse(const Vec2& p) const;
  [[nodiscard]] Vec2 quadratic_inverse(const Vec2& p) const;
};

/// PlaneMap::of(t, q).inverse(p).
[[nodiscard]] Vec2 inverse_map(mesh::FacetType t, std::span<const Vec2> q, const Vec2& p);

/// Ratio of the facet's surface element |x_ξ × x_η| to that of its projection onto the plane,
/// at ξ: 1 for a planar face parallel to the plane; for a warped Quad4 it maps the plane's
/// area onto the true surface (so that ∫ dS over the slave surface is its area). In 2D (a
/// curved Line3) the ratio of the arc's line element |x_ξ| to that of its projection |x_ξ·e₁|.
[[nodiscard]] double area_ratio(const FacetPoints& f, const FacePlane& plane, const Vec2& xi);

/// Whether a slave facet's surface element differs from its plane's: a node off the plane
/// (3D) or off the chord (2D Line3), beyond 1e-12 of the facet's size.
[[nodiscard]] bool warped(const FacetPoints& f, const FacePlane& plane, int dim);

}  // namespace tc::contact
