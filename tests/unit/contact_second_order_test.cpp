// The geometry and basis of second-order contact facets (Line3, Tri6, Quad8, Quad9) one by one:
// shape functions (partition of unity, derivatives against differences), the inverse of the
// quadratic plane map, curved normals, the area ratio of a curved Line3, and the basis
// transformation T of Popp et al. (2012) (Σφ̃ = 1, T T⁻¹ = I, the transformed weights), and
// the dual basis on it for several shares α (MortarOptions::vertex_share).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "tc/contact/geometry.hpp"
#include "tc/contact/integration.hpp"

namespace tc::contact {
namespace {

using mesh::FacetType;

constexpr FacetType kQuadratic[] = {FacetType::Line3, FacetType::Tri6, FacetType::Quad8,
                                    FacetType::Quad9};

/// A point of the facet's reference cell (facet_shape's conventions).
Vec2 random_point(FacetType t, std::mt19937& rng) {
  auto u = [&] { return rng() / 4294967295.0; };
  if (t == FacetType::Line3) return {u(), 0};
  if (t == FacetType::Tri6) {
    const double a = u(), b = u() * (1 - a);
    return {a, b};
  }
  return {2 * u() - 1, 2 * u() - 1};
}

TEST(ContactSecondOrder, ShapeFunctionsAreAPartitionOfUnityWithTheirDerivatives) {
  std::mt19937 rng(5);
  for (const auto t : kQuadratic)
    for (int i = 0; i < 20; ++i) {
      const Vec2 xi = random_point(t, rng);
      const ShapeValues s = facet_shape(t, xi);
      ASSERT_EQ(s.n, mesh::n_nodes(t));
      double sum = 0, dsum[2] = {0, 0};
      for (int a = 0; a < s.n; ++a)
        sum += s.phi[a], dsum[0] += s.dphi[a][0], dsum[1] += s.dphi[a][1];
      EXPECT_NEAR(sum, 1.0, 1e-14) << mesh::name(t);
      EXPECT_NEAR(dsum[0], 0.0, 1e-13) << mesh::name(t);
      EXPECT_NEAR(dsum[1], 0.0, 1e-13) << mesh::name(t);
      // Central differences of a quadratic (serendipity: cubic) are exact up to h²/6 φ''' = 0
      // for quadratics and O(h²) ~ 1e-10 for the cubic terms of Quad8; round-off ~1e-16/h.
      const double h = 1e-5;
      for (int k = 0; k < (t == FacetType::Line3 ? 1 : 2); ++k) {
        Vec2 p = xi, m = xi;
        p[k] += h;
        m[k] -= h;
        const ShapeValues sp = facet_shape(t, p), sm = facet_shape(t, m);
        for (int a = 0; a < s.n; ++a)
          EXPECT_NEAR(s.dphi[a][k], (sp.phi[a] - sm.phi[a]) / (2 * h), 1e-9)
              << mesh::name(t) << " node " << a << " direction " << k;
      }
    }
}

TEST(ContactSecondOrder, InverseMapRecoversTheReferenceCoordinatesOfCurvedFacets) {
  std::mt19937 rng(9);
  // Planar images with mid-edge nodes moved off the chords: genuinely quadratic maps.
  const std::vector<std::pair<FacetType, std::vector<Vec2>>> facets = {
      {FacetType::Line3, {{0.1, 0}, {1.3, 0}, {0.8, 0}}},
      {FacetType::Tri6, {{0, 0}, {1, 0.1}, {0.1, 1}, {0.55, -0.05}, {0.6, 0.6}, {-0.05, 0.5}}},
      {FacetType::Quad8,
       {{-1, -1}, {1.1, -0.9}, {1, 1}, {-0.9, 1.1}, {0.05, -1.1}, {1.1, 0.1}, {0, 1.05}, {-1, 0}}},
      {FacetType::Quad9,
       {{-1, -1},
        {1.1, -0.9},
        {1, 1},
        {-0.9, 1.1},
        {0.05, -1.1},
        {1.1, 0.1},
        {0, 1.05},
        {-1, 0},
        {0.05, 0.02}}}};
  for (const auto& [t, q] : facets) {
    const PlaneMap map = PlaneMap::of(t, q);
    for (int i = 0; i < 50; ++i) {
      const Vec2 xi = random_point(t, rng);
      const ShapeValues s = facet_shape(t, xi);
      Vec2 p{0, 0};
      for (int a = 0; a < s.n; ++a) p = {p[0] + s.phi[a] * q[a][0], p[1] + s.phi[a] * q[a][1]};
      const Vec2 back = map.inverse(p);
      EXPECT_NEAR(back[0], xi[0], 1e-13) << mesh::name(t);
      if (t != FacetType::Line3) {
        EXPECT_NEAR(back[1], xi[1], 1e-13) << mesh::name(t);
      }
    }
  }
}

TEST(ContactSecondOrder, CurvedLine3HasTheArcsNormalsAndLineElement) {
  // x(ξ) on the parabola y = c x(1 − x) through (0, 0), (½, c/4), (1, 0): the map is
  // x = ξ, y = cξ(1 − ξ), so x_ξ = (1, c(1 − 2ξ)) and the ratio to the chord's element is
  // √(1 + c²(1 − 2ξ)²); the normal at ξ is (x_ξ turned clockwise)/|x_ξ|.
  const double c = 0.4;
  FacetPoints f;
  f.type = FacetType::Line3;
  f.n = 3;
  f.corners = 2;
  f.x[0] = {0, 0, 0};
  f.x[1] = {1, 0, 0};
  f.x[2] = {0.5, c / 4, 0};
  const FacePlane plane = face_plane(f, 2);
  EXPECT_NEAR(plane.normal[0], 0.0, 1e-15);
  EXPECT_NEAR(plane.normal[1], -1.0, 1e-15);
  EXPECT_TRUE(warped(f, plane, 2));
  for (const double xi : {0.0, 0.3, 0.5, 1.0}) {
    const double slope = c * (1 - 2 * xi);
    EXPECT_NEAR(area_ratio(f, plane, {xi, 0}), std::sqrt(1 + slope * slope), 1e-14);
  }
  const Vec3 n0 = vertex_normal(f, 0), n2 = vertex_normal(f, 2);
  EXPECT_NEAR(n0[0], c / std::sqrt(1 + c * c), 1e-15);
  EXPECT_NEAR(n0[1], -1 / std::sqrt(1 + c * c), 1e-15);
  EXPECT_NEAR(n2[0], 0.0, 1e-15);
  EXPECT_NEAR(n2[1], -1.0, 1e-15);
  f.x[2] = {0.5, 0, 0};
  EXPECT_FALSE(warped(f, face_plane(f, 2), 2));
}

TEST(ContactSecondOrder, TransformationKeepsThePartitionOfUnityAndMakesWeightsPositive) {
  // The weights ∫φ̃ = T∫φ per unit area on the reference cells, by the rules (exact for the
  // quadratic and serendipity functions): Tri6 (2/15, 1/5), Quad8 (1/20, 1/5) at (vertices,
  // mid-edge nodes); Line3 and Quad9 untransformed.
  struct Expected {
    FacetType t;
    double alpha, vertex, edge;
  };
  for (const auto& [t, alpha, vertex, edge] : {Expected{FacetType::Tri6, 0.2, 2.0 / 15, 1.0 / 5},
                                               {FacetType::Quad8, 0.2, 1.0 / 20, 1.0 / 5},
                                               {FacetType::Quad9, 0.0, 1.0 / 36, 1.0 / 9},
                                               {FacetType::Line3, 0.0, 1.0 / 6, 2.0 / 3}}) {
    const BasisTransformation tr = basis_transformation(t);
    EXPECT_EQ(tr.alpha, alpha) << mesh::name(t);
    const int n = tr.n;
    for (int b = 0; b < n; ++b) {
      double column = 0;
      for (int a = 0; a < n; ++a) {
        column += tr.t[a][b];
        double product = 0;  // (T T⁻¹)_ab
        for (int c = 0; c < n; ++c) product += tr.t[a][c] * tr.inv[c][b];
        EXPECT_NEAR(product, a == b ? 1.0 : 0.0, 1e-15) << mesh::name(t) << " " << a << b;
      }
      EXPECT_NEAR(column, 1.0, 1e-15) << "Σ_a T_ab = 1 is Σφ̃ = Σφ; " << mesh::name(t);
    }
    double w[kFacetNodes] = {}, area = 0;
    auto add = [&](const Vec2& xi, double weight) {
      const ShapeValues s = facet_shape(t, xi);
      area += weight;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) w[a] += weight * tr.t[a][b] * s.phi[b];
    };
    if (t == FacetType::Line3)
      for (const auto& p : gauss_line(3)) add({p.s, 0}, p.w);
    else if (t == FacetType::Tri6)
      for (const auto& p : gauss_triangle(3)) add({p.r, p.s}, 0.5 * p.w);
    else
      for (const auto& p : gauss_line(3))
        for (const auto& r : gauss_line(3)) add({2 * p.s - 1, 2 * r.s - 1}, 4 * p.w * r.w);
    const int corners = mesh::n_nodes(mesh::corner_type(t));
    for (int a = 0; a < n; ++a) {
      const double expected = a < corners                                ? vertex
                              : a < 2 * corners || t == FacetType::Line3 ? edge
                                                                         : 4.0 / 9;
      EXPECT_NEAR(w[a] / area, expected, 1e-14) << mesh::name(t) << " node " << a;
      EXPECT_GT(w[a], 0.0);
    }
  }
}

// The dual basis ψ = diag(d̃) M̃e⁻¹ φ̃ of one whole reference face for several α: biorthogonal
// (∫ψ_a φ̃_b = δ_ab d̃_a) and Σψ = 1 for every α of the positive range, checked with a rule
// one degree richer than needed (n = 5: degree 9 on a line, 8 on the triangle; ψφ̃ has degree
// 4 on a Tri6, 6 on a Quad8). Measured, for the choice of α (docs/choices.md): the spread of
// the weights max d̃/min d̃, the extremes of ψ over the face (on a 60 × 60 grid), and
// |D_ev|/D_ee = α of the physical D's mid-edge rows.
TEST(ContactSecondOrder, DualBasisOnTheTransformedBasisForEachShare) {
  struct Case {
    FacetType t;
    double alpha;
  };
  for (const auto& [t, alpha] :
       {Case{FacetType::Tri6, 1.0 / 12}, Case{FacetType::Tri6, 0.2}, Case{FacetType::Tri6, 0.25},
        Case{FacetType::Tri6, 0.4}, Case{FacetType::Quad8, 1.0 / 6}, Case{FacetType::Quad8, 0.2},
        Case{FacetType::Quad8, 0.25}, Case{FacetType::Quad8, 5.0 / 16},
        Case{FacetType::Quad8, 0.4}}) {
    const BasisTransformation tr = basis_transformation(t, alpha);
    ASSERT_EQ(tr.alpha, alpha);
    const int n = tr.n;
    const auto tilde = [&](const Vec2& xi) {
      const ShapeValues s = facet_shape(t, xi);
      Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) v(a) += tr.t[a][b] * s.phi[b];
      return v;
    };
    const auto each_point = [&](auto&& f) {  // the reference face, weights summing to its area
      if (t == FacetType::Tri6)
        for (const auto& p : gauss_triangle(5)) f(Vec2{p.r, p.s}, 0.5 * p.w);
      else
        for (const auto& p : gauss_line(5))
          for (const auto& r : gauss_line(5)) f(Vec2{2 * p.s - 1, 2 * r.s - 1}, 4 * p.w * r.w);
    };
    Eigen::MatrixXd me = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    double area = 0;
    each_point([&](const Vec2& xi, double w) {
      const Eigen::VectorXd v = tilde(xi);
      me += w * v * v.transpose();
      d += w * v;
      area += w;
    });
    const Eigen::MatrixXd a = d.asDiagonal() * me.inverse();
    Eigen::MatrixXd bi = Eigen::MatrixXd::Zero(n, n);  // ∫ψ_a φ̃_b
    each_point([&](const Vec2& xi, double w) {
      const Eigen::VectorXd v = tilde(xi);
      bi += w * (a * v) * v.transpose();
    });
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        EXPECT_NEAR(bi(i, j), i == j ? d(i) : 0.0, 1e-13 * area)
            << mesh::name(t) << " α " << alpha << " (" << i << ", " << j << ")";
    double lo = 1e300, hi = -1e300;
    const int grid = 60;
    for (int i = 0; i <= grid; ++i)
      for (int j = 0; j <= grid; ++j) {
        const Vec2 xi = t == FacetType::Tri6 ? Vec2{double(i) / grid, double(j) / grid}
                                             : Vec2{-1 + 2.0 * i / grid, -1 + 2.0 * j / grid};
        if (t == FacetType::Tri6 && i + j > grid) continue;
        const Eigen::VectorXd psi = a * tilde(xi);
        EXPECT_NEAR(psi.sum(), 1.0, 1e-12) << mesh::name(t) << " α " << alpha;
        lo = std::min(lo, psi.minCoeff());
        hi = std::max(hi, psi.maxCoeff());
      }
    const double spread = d.maxCoeff() / d.minCoeff();
    EXPECT_GT(d.minCoeff(), 0.0);
    std::printf(
        "[ measure  ] %s α = %.4f: weights/area vertex %.4f, mid-edge %.4f (spread %.2f); ψ in "
        "[%.2f, %.2f]; D's mid-edge row: −α/(1 − 2α) = %.3f of its weight at each vertex\n",
        mesh::name(t), alpha, d(0) / area, d(n - 1) / area, spread, lo, hi,
        -alpha / (1 - 2 * alpha));
  }
}

}  // namespace
}  // namespace tc::contact
