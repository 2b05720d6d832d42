#include "tc/contact/geometry.hpp"

#include <algorithm>

#include "tc/core/verify.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::contact {

using mesh::FacetType;

ShapeValues facet_shape(FacetType t, const Vec2& xi) {
  ShapeValues s;
  switch (t) {
    case FacetType::Line2:
      s.n = 2;
      s.phi = {1 - xi[0], xi[0], 0, 0};
      s.dphi[0] = {-1, 0};
      s.dphi[1] = {1, 0};
      break;
    case FacetType::Tri3:
      s.n = 3;
      s.phi = {1 - xi[0] - xi[1], xi[0], xi[1], 0};
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
    default:
      TC_VERIFY(false, "contact facets are of first order (MortarPair refuses the others)");
  }
  return s;
}

FacetPoints facet_points(const mesh::Facet& f, std::span<const Vec3> x) {
  FacetPoints p;
  TC_VERIFY(mesh::order(f.type) == 1,
            "contact facets are of first order (MortarPair refuses the others)");
  p.type = f.type;
  p.n = mesh::n_nodes(f.type);
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
      TC_VERIFY(false, "contact facets are of first order (MortarPair refuses the others)");
  }
  return {};
}

Vec3 vertex_normal(const FacetPoints& f, int a) {
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
    return p;  // e2 = 0: one plane coordinate
  }
  p.origin = {0, 0, 0};
  for (int a = 0; a < slave.n; ++a) p.origin = p.origin + (1.0 / slave.n) * slave.x[a];
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
  for (int a = 0; a < f.n; ++a) out.polygon.push(plane.project(f.x[a]));
  if (signed_area(out.polygon) < 0) {
    std::reverse(out.polygon.v.begin(), out.polygon.v.begin() + f.n);
    for (int a = 0; a < f.n; ++a) out.order[a] = f.n - 1 - a;
  }
  return out;
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

PlaneMap PlaneMap::of(FacetType t, const std::array<Vec2, 4>& q) {
  PlaneMap m;
  m.type = t;
  auto combo = [&](const double(&w)[4]) {
    Vec2 v{0, 0};
    for (int a = 0; a < 4; ++a) v = {v[0] + w[a] * q[a][0], v[1] + w[a] * q[a][1]};
    return v;
  };
  switch (t) {
    case FacetType::Line2:
      m.a = {q[0][0], 0};
      m.b = {q[1][0] - q[0][0], 0};
      break;
    case FacetType::Tri3:
      m.a = q[0];
      m.b = combo({-1, 1, 0, 0});
      m.c = combo({-1, 0, 1, 0});
      break;
    case FacetType::Quad4: {
      // φ_a = ¼(1 + s_aξ)(1 + t_aη) with (s, t) the corners of [−1, 1]² in VTK order.
      m.a = combo({0.25, 0.25, 0.25, 0.25});
      m.b = combo({-0.25, 0.25, 0.25, -0.25});
      m.c = combo({-0.25, -0.25, 0.25, 0.25});
      m.d = combo({0.25, -0.25, 0.25, -0.25});
      const double size = std::abs(m.b[0]) + std::abs(m.b[1]) + std::abs(m.c[0]) + std::abs(m.c[1]);
      m.affine = std::abs(m.d[0]) + std::abs(m.d[1]) <= 1e-15 * size;
      break;
    }
    default:
      TC_VERIFY(false, "contact facets are of first order (MortarPair refuses the others)");
  }
  return m;
}

Vec2 PlaneMap::inverse(const Vec2& p) const {
  if (type == FacetType::Line2) return {(p[0] - a[0]) / b[0], 0};
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

Vec2 inverse_map(FacetType t, const std::array<Vec2, 4>& q, const Vec2& p) {
  return PlaneMap::of(t, q).inverse(p);
}

double area_ratio(const FacetPoints& f, const FacePlane& plane, const Vec2& xi) {
  const ShapeValues s = facet_shape(f.type, xi);
  Vec3 dx{0, 0, 0}, dy{0, 0, 0};
  for (int a = 0; a < f.n; ++a) {
    dx = dx + s.dphi[a][0] * f.x[a];
    dy = dy + s.dphi[a][1] * f.x[a];
  }
  const Vec3 c = cross(dx, dy);
  return norm(c) / std::abs(dot(c, plane.normal));
}

}  // namespace tc::contact
