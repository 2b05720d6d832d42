#include "tc/contact/geometry.hpp"

#include <algorithm>

#include "tc/mesh/reference_cell.hpp"

namespace tc::contact {

using mesh::FacetType;

namespace {

/// Line3 on [0, 1]: corners at 0 and 1, the mid-edge node at ½.
void line3_shape(double x, ShapeValues& s) {
  s.n = 3;
  s.phi[0] = (1 - x) * (1 - 2 * x);
  s.phi[1] = x * (2 * x - 1);
  s.phi[2] = 4 * x * (1 - x);
  s.dphi[0] = {4 * x - 3, 0};
  s.dphi[1] = {4 * x - 1, 0};
  s.dphi[2] = {4 - 8 * x, 0};
}

/// Tri6, Quad8, Quad9: the mesh's reference functions, on the same cells as Tri3 and Quad4.
void surface_shape(FacetType t, const Vec2& xi, ShapeValues& s) {
  s.n = mesh::n_nodes(t);
  double n[kFacetNodes], dn[3 * kFacetNodes];
  mesh::shape_functions(t, {xi[0], xi[1], 0}, n, dn);
  for (int a = 0; a < s.n; ++a) {
    s.phi[a] = n[a];
    s.dphi[a] = {dn[3 * a], dn[3 * a + 1]};
  }
}

/// Reference coordinates of node a in the conventions of facet_shape.
Vec2 reference_point(FacetType t, int a) {
  if (t == FacetType::Line2 || t == FacetType::Line3) return {a == 0 ? 0.0 : a == 1 ? 1.0 : 0.5, 0};
  const mesh::Point p = mesh::reference_node(t, a);
  return {p[0], p[1]};
}

/// The reference centre: ½ on lines, (⅓, ⅓) on triangles, 0 on quadrilaterals.
Vec2 reference_centre(FacetType t) {
  switch (mesh::corner_type(t)) {
    case FacetType::Line2:
      return {0.5, 0};
    case FacetType::Tri3:
      return {1.0 / 3, 1.0 / 3};
    default:
      return {0, 0};
  }
}

/// x_ξ and x_η of the facet at ξ.
void tangent_vectors(const FacetPoints& f, const Vec2& xi, Vec3& dx, Vec3& dy) {
  const ShapeValues s = facet_shape(f.type, xi);
  dx = {0, 0, 0};
  dy = {0, 0, 0};
  for (int a = 0; a < f.n; ++a) {
    dx = dx + s.dphi[a][0] * f.x[a];
    dy = dy + s.dphi[a][1] * f.x[a];
  }
}

/// The unit normal of a second-order facet at ξ: x_ξ × x_η, or in 2D x_ξ turned clockwise.
Vec3 curved_normal(const FacetPoints& f, const Vec2& xi) {
  Vec3 dx, dy;
  tangent_vectors(f, xi, dx, dy);
  if (f.type == FacetType::Line3) return normalized(Vec3{dx[1], -dx[0], 0});
  return normalized(cross(dx, dy));
}

}  // namespace

ShapeValues facet_shape(FacetType t, const Vec2& xi) {
  ShapeValues s;
  switch (t) {
    case FacetType::Line2:
      s.n = 2;
      s.phi[0] = 1 - xi[0];
      s.phi[1] = xi[0];
      s.dphi[0] = {-1, 0};
      s.dphi[1] = {1, 0};
      break;
    case FacetType::Tri3:
      s.n = 3;
      s.phi[0] = 1 - xi[0] - xi[1];
      s.phi[1] = xi[0];
      s.phi[2] = xi[1];
      s.dphi[0] = {-1, -1};
      s.dphi[1] = {1, 0};
      s.dphi[2] = {0, 1};
      break;
    case FacetType::Quad4: {
      s.n = 4;
      static constexpr double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
      for (int a = 0; a < 4; ++a) {
        const double fx = 1 + sx[a] * xi[0], fy = 1 + sy[a] * xi[1];
        s.phi[a] = 0.25 * fx * fy;
        s.dphi[a] = {0.25 * sx[a] * fy, 0.25 * fx * sy[a]};
      }
      break;
    }
    case FacetType::Line3:
      line3_shape(xi[0], s);
      break;
    default:
      surface_shape(t, xi, s);
  }
  return s;
}

FacetPoints facet_points(const mesh::Facet& f, std::span<const Vec3> x) {
  FacetPoints p;
  p.type = f.type;
  p.n = mesh::n_nodes(f.type);
  p.corners = mesh::n_nodes(mesh::corner_type(f.type));
  for (int a = 0; a < p.n; ++a) p.x[a] = x[f.nodes[a]];
  return p;
}

Vec3 centre_normal(const FacetPoints& f) {
  switch (f.type) {
    case FacetType::Line2: {
      const Vec3 t = f.x[1] - f.x[0];
      return normalized(Vec3{t[1], -t[0], 0});
    }
    case FacetType::Tri3:
      return normalized(cross(f.x[1] - f.x[0], f.x[2] - f.x[0]));
    case FacetType::Quad4:
      return normalized(cross(f.x[2] - f.x[0], f.x[3] - f.x[1]));
    default:
      return curved_normal(f, reference_centre(f.type));
  }
}

Vec3 vertex_normal(const FacetPoints& f, int a) {
  if (mesh::order(f.type) == 2) return curved_normal(f, reference_point(f.type, a));
  if (f.type != FacetType::Quad4) return centre_normal(f);
  return normalized(cross(f.x[(a + 1) % 4] - f.x[a], f.x[(a + 3) % 4] - f.x[a]));
}

double facet_size(const FacetPoints& f) {
  Vec3 lo = f.x[0], hi = f.x[0];
  for (int a = 1; a < f.n; ++a)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], f.x[a][i]);
      hi[i] = std::max(hi[i], f.x[a][i]);
    }
  return norm(hi - lo);
}

std::vector<Vec3> averaged_normals(std::span<const mesh::Facet> facets, std::span<const Vec3> x) {
  std::vector<Vec3> n(x.size(), Vec3{0, 0, 0});
  for (const auto& f : facets) {
    const FacetPoints p = facet_points(f, x);
    for (int a = 0; a < p.n; ++a) n[f.nodes[a]] = n[f.nodes[a]] + vertex_normal(p, a);
  }
  for (auto& v : n)
    if (dot(v, v) > 0) v = normalized(v);
  return n;
}

void tangents_of(int dim, const Vec3& n, Vec3& t0, Vec3& t1) {
  if (dim == 2) {
    t0 = {-n[1], n[0], 0};
    t1 = {0, 0, 0};
    return;
  }
  int axis = 0;  // the coordinate axis least aligned with n (the first one on ties)
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) < std::abs(n[axis])) axis = i;
  Vec3 e{0, 0, 0};
  e[axis] = 1;
  t0 = normalized(e - dot(e, n) * n);
  t1 = cross(t0, n);
}

FacePlane face_plane(const FacetPoints& slave, int dim) {
  FacePlane p;
  p.normal = centre_normal(slave);
  if (dim == 2) {
    p.origin = slave.x[0];
    p.e1 = normalized(slave.x[1] - slave.x[0]);
    // A curved Line3 is projected onto its chord: the chord's normal, not the arc's.
    if (slave.type == FacetType::Line3) p.normal = {p.e1[1], -p.e1[0], 0};
    return p;  // e2 = 0: one plane coordinate
  }
  p.origin = {0, 0, 0};
  for (int a = 0; a < slave.corners; ++a) p.origin = p.origin + (1.0 / slave.corners) * slave.x[a];
  const Vec3 edge = slave.x[1] - slave.x[0];
  p.e1 = normalized(edge - dot(edge, p.normal) * p.normal);
  p.e2 = cross(p.normal, p.e1);
  return p;
}

double signed_area(const Polygon& p) {
  double a = 0;
  for (int i = 0; i < p.n; ++i) {
    const Vec2& u = p.v[i];
    const Vec2& w = p.v[(i + 1) % p.n];
    a += u[0] * w[1] - u[1] * w[0];
  }
  return 0.5 * a;
}

ProjectedFacet project(const FacetPoints& f, const FacePlane& plane) {
  ProjectedFacet out;
  const int n = f.corners;
  for (int a = 0; a < n; ++a) out.polygon.push(plane.project(f.x[a]));
  if (signed_area(out.polygon) < 0) {
    std::reverse(out.polygon.v.begin(), out.polygon.v.begin() + n);
    for (int a = 0; a < n; ++a) out.order[a] = n - 1 - a;
  }
  return out;
}

bool curved_edges(const FacetPoints& f) {
  if (mesh::order(f.type) != 2 || f.type == FacetType::Line3) return false;
  const double tol = 1e-12 * facet_size(f);
  for (int i = 0; i < f.corners; ++i) {
    // Mid-edge node corners + i is on the edge from corner i to corner i + 1 (mesh::edges).
    const Vec3& a = f.x[i];
    const Vec3 chord = f.x[(i + 1) % f.corners] - a;
    const Vec3 off = cross(chord, f.x[f.corners + i] - a);
    if (norm(off) > tol * norm(chord)) return true;
  }
  return false;
}

SubFacets sub_facets(const FacetPoints& f, int divisions) {
  SubFacets s;
  const int d = std::clamp(divisions, 1, kMaxDivisions);
  const bool tri = mesh::corner_type(f.type) == FacetType::Tri3;
  s.corners = tri ? 3 : 4;
  auto at = [&](int i, int j) {
    // Reference point (i, j)/d of the triangle, −1 + 2(i, j)/d of the square.
    const Vec2 xi = tri ? Vec2{static_cast<double>(i) / d, static_cast<double>(j) / d}
                        : Vec2{-1 + 2.0 * i / d, -1 + 2.0 * j / d};
    const ShapeValues v = facet_shape(f.type, xi);
    Vec3 x{0, 0, 0};
    for (int a = 0; a < f.n; ++a) x = x + v.phi[a] * f.x[a];
    return x;
  };
  for (int j = 0; j < d; ++j)
    for (int i = 0; i < d; ++i) {
      if (!tri) {
        s.x[s.n++] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
        continue;
      }
      if (i + j < d) s.x[s.n++] = {at(i, j), at(i + 1, j), at(i, j + 1), Vec3{}};
      if (i + j < d - 1) s.x[s.n++] = {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), Vec3{}};
    }
  return s;
}

Polygon project(const SubFacets& s, int i, const FacePlane& plane) {
  Polygon p;
  for (int a = 0; a < s.corners; ++a) p.push(plane.project(s.x[i][a]));
  if (signed_area(p) < 0) std::reverse(p.v.begin(), p.v.begin() + p.n);
  return p;
}

bool boxes_meet(const Polygon& a, const Polygon& b) {
  for (int k = 0; k < 2; ++k) {
    double alo = a.v[0][k], ahi = alo, blo = b.v[0][k], bhi = blo;
    for (int i = 1; i < a.n; ++i) alo = std::min(alo, a.v[i][k]), ahi = std::max(ahi, a.v[i][k]);
    for (int i = 1; i < b.n; ++i) blo = std::min(blo, b.v[i][k]), bhi = std::max(bhi, b.v[i][k]);
    if (ahi < blo || bhi < alo) return false;
  }
  return true;
}

namespace {

/// Twice the signed area of (a, b, p): positive when p is left of a → b.
double side(const Vec2& a, const Vec2& b, const Vec2& p) {
  return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

Vec2 lerp(const Vec2& a, const Vec2& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
}

}  // namespace

Polygon clip(const Polygon& subject, const Polygon& clip_polygon) {
  Polygon out = subject;
  for (int e = 0; e < clip_polygon.n && out.n > 0; ++e) {
    const Vec2& a = clip_polygon.v[e];
    const Vec2& b = clip_polygon.v[(e + 1) % clip_polygon.n];
    // side() has units of length²: a band of 1e-13 |ab|² around the edge absorbs the round-off
    // of projecting coincident vertices of matching meshes.
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const double tol = 1e-13 * (dx * dx + dy * dy);
    const Polygon in = out;
    out.n = 0;
    for (int i = 0; i < in.n; ++i) {
      const Vec2& cur = in.v[i];
      const Vec2& prev = in.v[(i + in.n - 1) % in.n];
      const double dc = side(a, b, cur), dp = side(a, b, prev);
      const bool cur_in = dc >= -tol, prev_in = dp >= -tol;
      if (cur_in != prev_in) out.push(lerp(prev, cur, std::clamp(dp / (dp - dc), 0.0, 1.0)));
      if (cur_in) out.push(cur);
    }
  }
  return out;
}

Interval overlap(double length, double a, double b) {
  return {std::max(0.0, std::min(a, b)), std::min(length, std::max(a, b))};
}

PlaneMap PlaneMap::of(FacetType t, std::span<const Vec2> q) {
  PlaneMap m;
  m.type = t;
  auto combo = [&](const double(&w)[4]) {
    Vec2 v{0, 0};
    const int n = std::min(4, static_cast<int>(q.size()));
    for (int a = 0; a < n; ++a) v = {v[0] + w[a] * q[a][0], v[1] + w[a] * q[a][1]};
    return v;
  };
  switch (mesh::corner_type(t)) {
    case FacetType::Line2:
      m.a = {q[0][0], 0};
      m.b = {q[1][0] - q[0][0], 0};
      break;
    case FacetType::Tri3:
      m.a = q[0];
      m.b = combo({-1, 1, 0, 0});
      m.c = combo({-1, 0, 1, 0});
      break;
    default: {
      // φ_a = ¼(1 + s_aξ)(1 + t_aη) with (s, t) the corners of [−1, 1]² in VTK order.
      m.a = combo({0.25, 0.25, 0.25, 0.25});
      m.b = combo({-0.25, 0.25, 0.25, -0.25});
      m.c = combo({-0.25, -0.25, 0.25, 0.25});
      m.d = combo({0.25, -0.25, 0.25, -0.25});
      const double size = std::abs(m.b[0]) + std::abs(m.b[1]) + std::abs(m.c[0]) + std::abs(m.c[1]);
      m.affine = std::abs(m.d[0]) + std::abs(m.d[1]) <= 1e-15 * size;
      break;
    }
  }
  if (mesh::order(t) == 2) {
    m.n = mesh::n_nodes(t);
    for (int a = 0; a < m.n; ++a) m.q[a] = q[a];
  }
  return m;
}

Vec2 PlaneMap::inverse(const Vec2& p) const {
  return n == 0 ? corner_inverse(p) : quadratic_inverse(p);
}

Vec2 PlaneMap::corner_inverse(const Vec2& p) const {
  if (mesh::corner_type(type) == FacetType::Line2) return {(p[0] - a[0]) / b[0], 0};
  // The affine part: [b c] ξ = p − a.
  const double rx = p[0] - a[0], ry = p[1] - a[1];
  const double det = b[0] * c[1] - c[0] * b[1];
  Vec2 xi{(c[1] * rx - c[0] * ry) / det, (b[0] * ry - b[1] * rx) / det};
  if (affine) return xi;
  for (int it = 0; it < 30; ++it) {
    const double fx = rx - b[0] * xi[0] - c[0] * xi[1] - d[0] * xi[0] * xi[1];
    const double fy = ry - b[1] * xi[0] - c[1] * xi[1] - d[1] * xi[0] * xi[1];
    const double j00 = b[0] + d[0] * xi[1], j01 = c[0] + d[0] * xi[0];
    const double j10 = b[1] + d[1] * xi[1], j11 = c[1] + d[1] * xi[0];
    const double dj = j00 * j11 - j01 * j10;
    const double d0 = (j11 * fx - j01 * fy) / dj, d1 = (j00 * fy - j10 * fx) / dj;
    xi = {xi[0] + d0, xi[1] + d1};
    if (std::abs(d0) + std::abs(d1) < 1e-14) break;  // |ξ| ≤ ~1: round-off level
  }
  return xi;
}

Vec2 PlaneMap::quadratic_inverse(const Vec2& p) const {
  const bool line = type == FacetType::Line3;
  Vec2 xi = corner_inverse(p);
  for (int it = 0; it < 30; ++it) {
    const ShapeValues s = facet_shape(type, xi);
    double fx = p[0], fy = p[1], j00 = 0, j01 = 0, j10 = 0, j11 = 0;
    for (int k = 0; k < n; ++k) {
      fx -= s.phi[k] * q[k][0];
      fy -= s.phi[k] * q[k][1];
      j00 += s.dphi[k][0] * q[k][0];
      j01 += s.dphi[k][1] * q[k][0];
      j10 += s.dphi[k][0] * q[k][1];
      j11 += s.dphi[k][1] * q[k][1];
    }
    double d0 = 0, d1 = 0;
    if (line) {
      d0 = fx / j00;
    } else {
      const double dj = j00 * j11 - j01 * j10;
      d0 = (j11 * fx - j01 * fy) / dj;
      d1 = (j00 * fy - j10 * fx) / dj;
    }
    xi = {xi[0] + d0, xi[1] + d1};
    if (std::abs(d0) + std::abs(d1) < 1e-14) break;  // |ξ| ≤ ~1: round-off level
  }
  return xi;
}

Vec2 inverse_map(FacetType t, std::span<const Vec2> q, const Vec2& p) {
  return PlaneMap::of(t, q).inverse(p);
}

double area_ratio(const FacetPoints& f, const FacePlane& plane, const Vec2& xi) {
  Vec3 dx, dy;
  tangent_vectors(f, xi, dx, dy);
  if (f.type == FacetType::Line2 || f.type == FacetType::Line3)
    return norm(dx) / std::abs(dot(dx, plane.e1));
  const Vec3 c = cross(dx, dy);
  return norm(c) / std::abs(dot(c, plane.normal));
}

bool warped(const FacetPoints& f, const FacePlane& plane, int dim) {
  const double size = facet_size(f);
  if (dim == 2) {
    // Line3: the mid-edge node off the chord; a Line2 is its chord.
    for (int a = 2; a < f.n; ++a)
      if (std::abs(dot(f.x[a] - plane.origin, plane.normal)) > 1e-12 * size) return true;
    return false;
  }
  for (int a = 0; a < f.n; ++a)
    if (std::abs(dot(f.x[a] - plane.origin, plane.normal)) > 1e-12 * size) return true;
  return false;
}

}  // namespace tc::contact
