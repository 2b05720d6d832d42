// physics::StaggeredLoop: the staggered fixed point (6.3) written once, on a scalar two-field
// map with a closed-form fixed point, its order, its stopping rules, its failure.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "tc/physics/body/step/staggered_loop.hpp"

namespace tc::physics {
namespace {

// θ = a u + b (the heat half), u = c θ + d (the mechanical half): a contraction when |ac| < 1,
// with fixed point θ* = (a d + b)/(1 − a c), u* = c θ* + d.
struct LinearPair {
  LinearPair(double a_, double b_, double c_, double d_) : a(a_), b(b_), c(c_), d(d_) {}
  double a, b, c, d;
  double u = 0, theta = 0, u_prev = 0, theta_prev = 0;
  std::string log;  // the halves in the order they ran

  StaggeredSweep sweep() {
    return {.begin = [this](SweepState&) { u_prev = u, theta_prev = theta; },
            .heat =
                [this](SweepState& s) {
                  theta = a * u + b;
                  s.theta = {std::abs(theta - theta_prev), std::abs(theta)};
                  log += 'h';
                },
            .mechanics =
                [this](SweepState&) {
                  u = c * theta + d;
                  log += 'm';
                },
            .end =
                [this](SweepState& s) {
                  s.primal = {std::abs(u - u_prev), std::abs(u)};
                }};
  }
};

TEST(StaggeredLoop, ConvergesToTheClosedFormFixedPointInThePredictedSweeps) {
  LinearPair p(0.5, 1.0, 0.4, 2.0);
  const double tol = 1e-10;
  StaggeredLoop loop(SweepOrder::heat_first, 100);
  loop.stop_when(std::make_unique<ChangesWithin>(tol));
  const auto r = loop.run(p.sweep());
  ASSERT_TRUE(r.converged);
  const double theta_star = (p.a * p.d + p.b) / (1 - p.a * p.c), u_star = p.c * theta_star + p.d;
  // Stopped when |Δu| ≤ tol|u|: the error left is |Δu| ac/(1 − ac) ≤ tol|u|·0.25.
  EXPECT_NEAR(p.u, u_star, tol * std::abs(u_star));
  EXPECT_NEAR(p.theta, theta_star, tol * std::abs(theta_star));
  // The sweeps from the closed form of the errors: u_p − u* = (ac)^p (u_0 − u*), θ_p − θ* =
  // a(u_{p−1} − u*); the first p with both changes within tol.
  const double q = p.a * p.c, e0 = 0 - u_star;
  int expected = 0;
  for (int k = 1; k < 100 && expected == 0; ++k) {
    const double up = u_star + std::pow(q, k) * e0, du = std::pow(q, k - 1) * (q - 1) * e0;
    const double tp = theta_star + p.a * std::pow(q, k - 1) * e0;
    const double dt = k == 1 ? std::abs(tp) : std::abs(p.a * std::pow(q, k - 2) * (q - 1) * e0);
    if (std::abs(du) <= tol * std::abs(up) && dt <= tol * std::abs(tp)) expected = k;
  }
  EXPECT_EQ(r.iterations, expected);
  EXPECT_EQ(p.log.size(), 2u * static_cast<size_t>(expected));
}

TEST(StaggeredLoop, TakesTheHalvesInItsOrder) {
  LinearPair p(0.5, 1.0, 0.4, 2.0);
  StaggeredLoop loop(SweepOrder::mechanics_first, 2);
  ASSERT_FALSE(loop.run(p.sweep()).converged);  // no rule: every sweep taken
  EXPECT_EQ(p.log, "mhmh");
}

TEST(StaggeredLoop, OnePassStopsAfterTheFirstSweep) {
  LinearPair p(0.0, 3.0, 0.4, 2.0);  // θ does not depend on u: one-way
  StaggeredLoop loop(SweepOrder::heat_first, 10);
  loop.stop_when(std::make_unique<OnePass>());
  const auto r = loop.run(p.sweep());
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(p.log, "hm");
  EXPECT_DOUBLE_EQ(p.u, 0.4 * 3.0 + 2.0);  // exact after one pass in the order of dependence
}

TEST(StaggeredLoop, ReportsTheLastChangeWhenItDoesNotConverge) {
  LinearPair p(2.0, 1.0, 2.0, 1.0);  // ac = 4: diverges
  StaggeredLoop loop(SweepOrder::heat_first, 5);
  loop.stop_when(std::make_unique<ChangesWithin>(1e-8));
  const auto r = loop.run(p.sweep());
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 5);
  // |Δu|/|u| → (ac − 1)/ac = 3/4 as the iterates grow like (ac)^p.
  EXPECT_NEAR(r.change, 0.75, 0.01);
}

TEST(StaggeredLoop, FinalHeatStopsBeforeTheMechanicsItWouldRepeat) {
  // λ (here u) is final once the inner fixed point is met: with the heat first, the second
  // sweep's heat step had the final u and is the last needed.
  LinearPair p(0.5, 1.0, 0.0, 2.0);
  StaggeredLoop loop(SweepOrder::heat_first, 10);
  loop.stop_when(std::make_unique<FinalHeat>(SweepOrder::heat_first, 1e-8, false));
  auto sweep = p.sweep();
  sweep.begin = [&](SweepState& s) {
    p.u_prev = p.u, p.theta_prev = p.theta;
    s.inner_converged = p.log.find('m') != std::string::npos;  // met once mechanics ran
  };
  const auto r = loop.run(sweep);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_EQ(p.log, "hmh");
  // Mechanics first, the same rule asks after the sweep, with the friction residual met.
  const FinalHeat after(SweepOrder::mechanics_first, 1e-8, true);
  SweepState s;
  s.theta = {1e-9, 1.0};
  EXPECT_FALSE(after.after_heat(s));
  EXPECT_TRUE(after.after_sweep(s));
  s.theta = {1e-7, 1.0};  // θ iterates itself and is not yet within tol
  EXPECT_FALSE(after.after_sweep(s));
}

TEST(StaggeredLoop, TheContractionEstimateStopsOnlyOnAClearContraction) {
  // ρ = 0.01: λ left ρ/(1 − ρ)·1e-5 ≈ 1e-7, θ left 1e-6/1e-3·1e-5/(1 − ρ) ≈ 1e-8, both ≤ 1e-4.
  EXPECT_TRUE(fixed_point_reached(1e-5, 1e-6, 1e-3, 1e-4));
  EXPECT_FALSE(fixed_point_reached(6e-4, 1e-6, 1e-3, 1e-4));  // ρ = 0.6 > 1/2: confirm first
  EXPECT_FALSE(fixed_point_reached(1e-5, 1e-1, 1e-3, 1e-4));  // θ would still move 1e-3
  SweepState s;
  s.primal = {1e-5, 1.0};
  s.theta = {1e-6, 1.0};
  const ContractionEstimate rule(1e-4);
  EXPECT_FALSE(rule.after_sweep(s));  // no previous sweep yet
  s.previous_primal = 1e-3;
  EXPECT_TRUE(rule.after_sweep(s));
  s.inner_converged = false;  // the friction fixed point not met: never
  EXPECT_FALSE(rule.after_sweep(s));
}

}  // namespace
}  // namespace tc::physics
