// The stages of the mortar pair taken one by one: polygon clipping, segment overlap, inverse
// facet maps, the AABB tree against a brute-force search, the exactness degree of the rules,
// and the tangent frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tc/contact/geometry.hpp"
#include "tc/contact/integration.hpp"
#include "tc/contact/search.hpp"
#include "tc/core/error.hpp"

namespace tc::contact {
namespace {

Polygon polygon(std::initializer_list<Vec2> v) {
  Polygon p;
  for (const auto& x : v) p.push(x);
  return p;
}

Polygon square(double cx, double cy, double half, double angle) {
  Polygon p;
  for (int k = 0; k < 4; ++k) {
    const double a = angle + M_PI / 4 + k * M_PI / 2, r = half * std::sqrt(2.0);
    p.push({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return p;
}

TEST(ContactClip, SquareAgainstItsRotationIsTheRegularOctagon) {
  // Two unit squares with the same centre, one turned by 45°: the intersection is a regular
  // octagon of area 2(√2 − 1).
  const Polygon c = clip(square(0, 0, 0.5, M_PI / 4), square(0, 0, 0.5, 0));
  EXPECT_EQ(c.n, 8);
  EXPECT_NEAR(signed_area(c), 2 * (std::sqrt(2.0) - 1), 1e-15);
}

TEST(ContactClip, InsideDisjointAndCoincident) {
  const Polygon unit = polygon({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const Polygon tri = polygon({{0.2, 0.2}, {0.7, 0.3}, {0.4, 0.8}});
  EXPECT_NEAR(signed_area(clip(tri, unit)), signed_area(tri), 1e-16);
  EXPECT_LT(clip(polygon({{2, 0}, {3, 0}, {3, 1}}), unit).n, 3);
  // Coincident edges (matching meshes): nothing is lost to round-off.
  EXPECT_NEAR(signed_area(clip(unit, unit)), 1.0, 1e-15);
  // A quad overhanging two sides: the overlap is [0.5, 1] × [0.25, 1].
  EXPECT_NEAR(signed_area(clip(polygon({{0.5, 0.25}, {1.5, 0.25}, {1.5, 1.5}, {0.5, 1.5}}), unit)),
              0.375, 1e-15);
}

TEST(ContactOverlap, SegmentsInEitherDirection) {
  const Interval a = overlap(1.0, 0.7, -0.2);  // a reversed master segment
  EXPECT_DOUBLE_EQ(a.lo, 0.0);
  EXPECT_DOUBLE_EQ(a.hi, 0.7);
  const Interval b = overlap(1.0, 1.2, 1.5);
  EXPECT_LE(b.hi, b.lo);
}

TEST(ContactInverseMap, RecoversTheReferenceCoordinatesOfAGeneralQuad) {
  const std::array<Vec2, 4> q{{{0.1, -0.05}, {1.2, 0.1}, {0.9, 1.3}, {-0.2, 0.8}}};
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Vec2 xi{2.0 * rng() / 4294967295.0 - 1, 2.0 * rng() / 4294967295.0 - 1};
    const ShapeValues s = facet_shape(mesh::FacetType::Quad4, xi);
    Vec2 p{0, 0};
    for (int a = 0; a < 4; ++a) p = {p[0] + s.phi[a] * q[a][0], p[1] + s.phi[a] * q[a][1]};
    const Vec2 back = inverse_map(mesh::FacetType::Quad4, q, p);
    EXPECT_NEAR(back[0], xi[0], 1e-13);
    EXPECT_NEAR(back[1], xi[1], 1e-13);
  }
  const std::array<Vec2, 4> t{{{0, 0}, {2, 0.5}, {0.3, 1}, {0, 0}}};
  const Vec2 r = inverse_map(mesh::FacetType::Tri3, t, {0.3 * 2 + 0.2 * 0.3, 0.3 * 0.5 + 0.2});
  EXPECT_NEAR(r[0], 0.3, 1e-15);
  EXPECT_NEAR(r[1], 0.2, 1e-15);
}

TEST(ContactSearch, TreeFindsWhatBruteForceFinds) {
  std::mt19937 rng(11);
  auto u = [&] { return rng() / 4294967295.0; };
  std::vector<Aabb> boxes(2000);
  for (auto& b : boxes) {
    const Vec3 c{u(), u(), 0.1 * u()};
    b.grow(c);
    b.grow(c + Vec3{0.02 * u(), 0.02 * u(), 0.01 * u()});
  }
  const AabbTree tree(boxes);
  for (int q = 0; q < 200; ++q) {
    Aabb box;
    const Vec3 c{u(), u(), 0.1 * u()};
    box.grow(c);
    box = box.inflated(0.03 * u());
    std::vector<int> hits, brute;
    tree.query(box, hits);
    for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
      if (boxes[i].overlaps(box)) brute.push_back(i);
    std::sort(hits.begin(), hits.end());
    EXPECT_EQ(hits, brute);
  }
  std::vector<int> none;
  AabbTree(std::vector<Aabb>{}).query(boxes[0], none);
  EXPECT_TRUE(none.empty());
}

/// ∫ over the unit triangle of r^i s^j = i! j! / (i + j + 2)!.
double monomial_integral(int i, int j) {
  return std::tgamma(i + 1) * std::tgamma(j + 1) / std::tgamma(i + j + 3);
}

TEST(ContactQuadrature, TriangleRulesAreExactToDegree2nMinus2AndNoFurther) {
  for (int n = 1; n <= kMaxGaussPoints; ++n) {
    double worst_beyond = 0;
    for (int deg = 0; deg <= 2 * n - 1; ++deg)
      for (int i = 0; i <= deg; ++i) {
        const int j = deg - i;
        double q = 0;
        for (const auto& p : gauss_triangle(n))
          q += 0.5 * p.w * std::pow(p.r, i) * std::pow(p.s, j);
        const double err = std::abs(q - monomial_integral(i, j)) / monomial_integral(i, j);
        if (deg <= 2 * n - 2)
          EXPECT_LT(err, 1e-14) << "n = " << n << ", r^" << i << " s^" << j;
        else
          worst_beyond = std::max(worst_beyond, err);
      }
    EXPECT_GT(worst_beyond, 1e-6) << "n = " << n << " is exact beyond 2n − 2: the bound is loose";
  }
}

TEST(ContactQuadrature, LineRulesAreExactToDegree2nMinus1) {
  for (int n = 1; n <= kMaxGaussPoints; ++n)
    for (int deg = 0; deg <= 2 * n; ++deg) {
      double q = 0;
      for (const auto& p : gauss_line(n)) q += p.w * std::pow(p.s, deg);
      const double err = std::abs(q - 1.0 / (deg + 1)) * (deg + 1);
      if (deg <= 2 * n - 1)
        EXPECT_LT(err, 1e-14) << n << " " << deg;
      else  // s^2n's (scaled) error (n!)⁴/((2n)!)² falls to 6e-9 at n = 8, 10⁴ above round-off
        EXPECT_GT(err, 1e-10) << n << " " << deg;
    }
  EXPECT_THROW((void)gauss_line(kMaxGaussPoints + 1), Error);
}

TEST(ContactFrames, TangentsAreOrthonormalWithTheNormal) {
  std::mt19937 rng(2);
  for (int i = 0; i < 100; ++i) {
    const Vec3 n = normalized(
        Vec3{rng() / 2147483648.0 - 1, rng() / 2147483648.0 - 1, rng() / 2147483648.0 - 1});
    Vec3 t0, t1;
    tangents_of(3, n, t0, t1);
    EXPECT_NEAR(dot(t0, n), 0, 1e-15);
    EXPECT_NEAR(dot(t1, n), 0, 1e-15);
    EXPECT_NEAR(dot(t0, t1), 0, 1e-15);
    EXPECT_NEAR(norm(t0), 1, 1e-15);
    EXPECT_NEAR(norm(t1), 1, 1e-15);
  }
  Vec3 t0, t1;
  tangents_of(2, {0, -1, 0}, t0, t1);
  EXPECT_EQ(t0, (Vec3{1, 0, 0}));
}

}  // namespace
}  // namespace tc::contact
