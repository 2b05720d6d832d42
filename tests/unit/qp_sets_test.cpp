// The convex sets of the dual QP: projections, activity, chopped gradients, feasible steps.
#include <gtest/gtest.h>

#include <cfenv>

#include "tc/qp/sets.hpp"

namespace tc::qp {
namespace {

TEST(Interval, ProjectsAndChops) {
  const Interval lower{0.0, infinity};
  EXPECT_EQ(lower.project(-2.0), 0.0);
  EXPECT_EQ(lower.project(3.0), 3.0);
  EXPECT_TRUE(lower.active(0.0));
  EXPECT_FALSE(lower.active(1e-300));         // activity is exact at a zero bound
  EXPECT_EQ(lower.chopped(0.0, -2.0), -2.0);  // −g points into the set: may move
  EXPECT_EQ(lower.chopped(0.0, 2.0), 0.0);    // −g points out: blocked

  const Interval box{-1.0, 1.0};
  EXPECT_EQ(box.chopped(1.0, 2.0), 2.0);
  EXPECT_EQ(box.chopped(1.0, -2.0), 0.0);
  const Interval fixed{0.5, 0.5};  // both bounds active: nothing moves
  EXPECT_EQ(fixed.chopped(0.5, -3.0), 0.0);
  EXPECT_EQ(fixed.chopped(0.5, 3.0), 0.0);
}

TEST(Interval, MaxStep) {
  const Interval box{-1.0, 2.0};
  EXPECT_DOUBLE_EQ(box.max_step(0.5, 0.5), 3.0);   // 0.5 − 3·0.5 = −1
  EXPECT_DOUBLE_EQ(box.max_step(0.5, -0.5), 3.0);  // 0.5 + 3·0.5 = 2
  EXPECT_EQ(box.max_step(0.5, 0.0), infinity);
}

TEST(Disc, ProjectionAndActivity) {
  const Disc d{2.0};
  const auto p = d.project({3.0, 4.0});
  EXPECT_NEAR(p[0], 1.2, 1e-15);
  EXPECT_NEAR(p[1], 1.6, 1e-15);
  EXPECT_TRUE(d.active(p));
  EXPECT_FALSE(d.active({1.0, 1.0}));
  const Disc centre{0.0};
  EXPECT_EQ(centre.project({3.0, 4.0})[0], 0.0);
  EXPECT_TRUE(centre.active({0.0, 0.0}));
}

TEST(Disc, ChoppedGradientKeepsTheTangentOnly) {
  const Disc d{1.0};
  // At (1, 0) with g = (−2, 3): −g = (2, −3) points out; the tangential part (0, 3) stays.
  const auto c = d.chopped({1.0, 0.0}, {-2.0, 3.0});
  EXPECT_DOUBLE_EQ(c[0], 0.0);
  EXPECT_DOUBLE_EQ(c[1], 3.0);
  // g = (2, 3): −g points inside, all of it may move.
  const auto all = d.chopped({1.0, 0.0}, {2.0, 3.0});
  EXPECT_DOUBLE_EQ(all[0], 2.0);
  EXPECT_DOUBLE_EQ(all[1], 3.0);
}

TEST(Disc, MaxStepIsTheRootOfTheQuadratic) {
  const Disc d{5.0};
  // From (0, 0) along −p = (3, 4)/… : ‖α p‖ = 5 ⇒ α = 1 for p = (−3, −4).
  EXPECT_NEAR(d.max_step({0.0, 0.0}, {-3.0, -4.0}), 1.0, 1e-15);
  // From (3, 0) along −p = (1, 0): reaches (5, 0) at α = 2.
  EXPECT_NEAR(d.max_step({3.0, 0.0}, {-1.0, 0.0}), 2.0, 1e-15);
  // On the circle a tangential direction leaves at once; an inward one crosses the disc.
  EXPECT_EQ(d.max_step({5.0, 0.0}, {0.0, 1.0}), 0.0);
  EXPECT_NEAR(d.max_step({5.0, 0.0}, {1.0, 0.0}), 10.0, 1e-14);
}

TEST(FeasibleSet, AdvanceLandsExactlyOnTheBoundary) {
  core::Vector x = core::Vector::from(std::vector<double>{0.3, 0.7, 0.1, 0.2});
  FeasibleSet set(x);
  set.set_interval(0, {0.0, infinity});
  set.set_interval(1, {0.0, infinity});
  set.add_disc({2, 3, {1.0}});
  const auto p = core::Vector::from(std::vector<double>{0.1, 0.1, -0.1, -0.1});
  const double a = set.max_step(x, p);
  EXPECT_NEAR(a, 3.0, 1e-14);  // component 0: 0.3 − 3·0.1 = 0 binds first
  set.advance(x, p, a);
  const auto v = x.to_std();
  EXPECT_EQ(v[0], 0.0);  // exactly: active without a tolerance
  EXPECT_NEAR(v[1], 0.4, 1e-15);
  EXPECT_EQ(set.count_active(x), 1);  // the disc stays inside: ‖(0.4, 0.5)‖ < 1
  EXPECT_LE(set.violation(x), 0.0);
}

TEST(FeasibleSet, SplitGradientOfAMixedProduct) {
  // [free, λ_n at 0, disc on its circle]: g^P = φ + β component by component.
  core::Vector x = core::Vector::from(std::vector<double>{0.5, 0.0, 0.6, 0.8});
  FeasibleSet set(x);
  set.set_interval(1, {0.0, infinity});
  set.add_disc({2, 3, {1.0}});
  const auto g = core::Vector::from(std::vector<double>{2.0, 1.0, -0.6, 0.0});
  core::Vector phi = x.duplicate(), beta = x.duplicate(), gp = x.duplicate();
  set.split_gradient(x, g, phi, beta, gp);
  const auto f = phi.to_std(), b = beta.to_std(), p = gp.to_std();
  EXPECT_EQ(f[0], 2.0);  // free component: φ = g
  EXPECT_EQ(b[1], 0.0);  // λ_n = 0 with g > 0: at the KKT point
  // Disc at n = (0.6, 0.8), g = (−0.6, 0): g·n = −0.36 < 0 ⇒ β = g + 0.36 n = (−0.384, 0.288).
  EXPECT_NEAR(b[2], -0.384, 1e-15);
  EXPECT_NEAR(b[3], 0.288, 1e-15);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p[i], f[i] + b[i]);
}

TEST(FeasibleSet, SplitGradientRaisesNoInvalidOperationAtInfiniteBounds) {
  // The activity tolerance of an infinite bound was ∞ − ∞: a NaN that compared false, but
  // FE_INVALID aborted runs under PETSc's -fp_trap (issue 20, #16). Every kind of component,
  // with the flag watched: free, [0, ∞), (−∞, 1] at its bound, a disc.
  core::Vector x = core::Vector::from(std::vector<double>{0.5, 0.0, 1.0, 0.6, 0.8});
  FeasibleSet set(x);
  set.set_interval(1, {0.0, infinity});
  set.set_interval(2, {-infinity, 1.0});
  set.add_disc({3, 4, {1.0}});
  const auto g = core::Vector::from(std::vector<double>{2.0, 1.0, 1.0, -0.6, 0.0});
  core::Vector phi = x.duplicate(), beta = x.duplicate(), gp = x.duplicate();
  std::feclearexcept(FE_ALL_EXCEPT);
  set.split_gradient(x, g, phi, beta, gp);
  EXPECT_FALSE(std::fetestexcept(FE_INVALID));
  const auto f = phi.to_std(), b = beta.to_std();
  EXPECT_EQ(f[0], 2.0);  // free: never active
  EXPECT_EQ(b[1], 0.0);  // at 0 with g > 0: blocked
  EXPECT_EQ(f[2], 0.0);  // at its upper bound 1: active, the bound found despite −∞ below
  EXPECT_EQ(b[2], 1.0);  // −g points into the set: may move
}

TEST(FeasibleSet, ScaledSetIsTheImageUnderTheChangeOfVariables) {
  // [λ_n ≥ 0, box [−1, 2], disc r = 3] in x̂ = S⁻¹x with s = (2, 4, 0.5, 0.5).
  core::Vector layout(4);
  FeasibleSet set(layout);
  set.set_interval(0, {0.0, infinity});
  set.set_interval(1, {-1.0, 2.0});
  set.add_disc({2, 3, {3.0}});
  const auto s = core::Vector::from(std::vector<double>{2.0, 4.0, 0.5, 0.5});
  const FeasibleSet hat = set.scaled(s);
  // The corners of the image: 0 and ∞ stay, −1/4 and 2/4, radius 3/0.5 = 6.
  auto x = core::Vector::from(std::vector<double>{-1.0, 1.0, 8.0, 0.0});
  hat.project(x);
  const auto v = x.to_std();
  EXPECT_EQ(v[0], 0.0);
  EXPECT_EQ(v[1], 0.5);
  EXPECT_DOUBLE_EQ(v[2], 6.0);
  EXPECT_EQ(v[3], 0.0);
  EXPECT_EQ(hat.violation(core::Vector::from(std::vector<double>{1e9, -0.25, 0.0, 6.0})), 0.0);
  // The two components of a disc must share one factor, or a disc would become an ellipse.
  const auto bad = core::Vector::from(std::vector<double>{1.0, 1.0, 1.0, 2.0});
  EXPECT_THROW((void)set.scaled(bad), std::invalid_argument);
}

TEST(FeasibleSet, JacobiScalingSharesOneFactorPerDisc) {
  core::Vector layout(4);
  FeasibleSet set(layout);
  set.add_disc({2, 3, {1.0}});
  const auto diag = core::Vector::from(std::vector<double>{4.0, 1.0, 16.0, 1.0});
  const auto s = set.jacobi_scaling(diag).to_std();
  EXPECT_DOUBLE_EQ(s[0], 0.5);  // 4^(−1/2)
  EXPECT_DOUBLE_EQ(s[1], 1.0);
  EXPECT_DOUBLE_EQ(s[2], 0.5);  // (16·1)^(−1/4): the geometric mean of 1/4 and 1
  EXPECT_DOUBLE_EQ(s[3], 0.5);
}

}  // namespace
}  // namespace tc::qp
