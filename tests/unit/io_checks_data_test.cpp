// The dynamic scheme's check of prescribed displacements (io/checks/data_checks.hpp): the
// trapezoidal velocity update u̇^{k+1} = 2Δu/τ − u̇^k leaves a jump Δv in the data as a step-to-step
// alternation ±Δv for ever, and follows a parabola sampled at the steps exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tc/io/checks/data_checks.hpp"

namespace {

using tc::core::TimeTable;
using tc::io::trapezoidal_ringing;

TEST(TrapezoidalRinging, AnInstantStartAlternatesByTheJumpTwoStepsLater) {
  // Held until t = 4 ms, then 1 m/s: u̇ = 0, 0, 0, 0, 2, 0, 2, … against a mean speed of 1.
  const TimeTable d({0.0, 0.004, 0.204}, {0.0, 0.0, 0.2});
  const auto r = trapezoidal_ringing(d, 0.0, 0.001, 204);
  EXPECT_NEAR(r.alternation, 1.0, 1e-9);  // |Δv|, exactly (the data are linear after it)
  EXPECT_NEAR(r.at_time, 0.006, 1e-12);   // the jump at 4 ms, two steps on
  EXPECT_NEAR(r.max_speed, 1.0, 1e-9);
  // A run of 10⁸ steps (the case format's most) is looked at up to two steps past the table's
  // last point, where nothing changes any more: the same answer, at once.
  const auto long_run = trapezoidal_ringing(d, 0.0, 0.001, 100000000);
  EXPECT_EQ(long_run.alternation, r.alternation);
  EXPECT_EQ(long_run.at_time, r.at_time);
}

TEST(TrapezoidalRinging, AParabolaSampledAtTheStepsIsFollowedExactly) {
  // 0 → 1 m/s over 4 ms: d = (t − 4 ms)²/(2 × 4 ms) at every step of 1 ms, then linear. The
  // rule gives u̇^k = a(t_k − 4 ms) exactly, so what it leaves is at most half a step's change
  // of speed at the ramp's ends, which the measure subtracts: nothing (round-off only).
  std::vector<double> t{0.0, 0.004}, v{0.0, 0.0};
  for (int k = 1; k <= 4; ++k) {
    const double s = 0.001 * k;
    t.push_back(0.004 + s);
    v.push_back(s * s / 0.008);
  }
  t.push_back(0.206);
  v.push_back(0.002 + 0.198);
  const auto r = trapezoidal_ringing(TimeTable(t, v), 0.0, 0.001, 206);
  EXPECT_LT(r.alternation, 1e-9);
  EXPECT_NEAR(r.max_speed, 1.0, 1e-9);
}

TEST(TrapezoidalRinging, AnInitialVelocityThatTheDataDoNotContinueRingsToo) {
  // The body starts at 1 m/s (its initial_velocity) while the data hold it: Δv = −1.
  const TimeTable d({0.0, 1.0}, {0.0, 0.0});
  EXPECT_NEAR(trapezoidal_ringing(d, 1.0, 0.01, 100).alternation, 1.0, 1e-9);
}

tc::physics::Problem one_boundary(TimeTable x, tc::physics::Scheme scheme) {
  tc::physics::Problem p;
  p.dimension = 3;
  p.time.scheme = scheme;
  p.time.step = 0.001;
  p.time.end = 0.204;
  p.bodies.resize(1);
  p.bodies[0].name = "pin";
  tc::physics::BoundaryCondition b;
  b.where = "collet";
  b.displacement[0] = std::move(x);
  b.displacement[1] = TimeTable(0.0);
  p.boundaries.push_back(b);
  return p;
}

TEST(CheckTimeData, WarnsOfAnInstantStartInADynamicRunOnly) {
  const TimeTable jump({0.0, 0.004, 0.204}, {0.0, 0.0, 0.2});
  const auto w = tc::io::check_time_data(one_boundary(jump, tc::physics::Scheme::dynamic));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("body 'pin' where 'collet'"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("along x"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("at t = 0.004 s"), std::string::npos) << w[0];
  // Quasistatic runs have no velocity to ring.
  EXPECT_TRUE(
      tc::io::check_time_data(one_boundary(jump, tc::physics::Scheme::quasistatic)).empty());
}

}  // namespace
