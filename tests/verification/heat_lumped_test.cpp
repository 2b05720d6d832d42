// [physics] heat_capacity = "lumped": a cold square plate whose left edge is suddenly held
// hot, one step of τ ≪ ρc_p h²/κ. With the consistent M_θ backward Euler undershoots ahead of
// the front (a temperature below the initial one: not physical); with the lumped M_θ on square
// Quad4 cells (K_θ with non-positive off-diagonal entries) the discrete maximum principle
// holds: every temperature stays between the cold and the hot value. Both conserve the same
// total heat capacity, so the heat taken in by the step is the same to O(τ) differences only.
#include <gtest/gtest.h>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

struct Last : physics::Observer {};

double min_temperature(bool lumped) {
  auto p = box_problem(2, {1, 1, 0}, {10, 10, 1}, steel(), physics::Scheme::quasistatic, 1e-2, 1);
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  p.physics.lumped_heat_capacity = lumped;
  p.bodies[0].initial_temperature = 300;
  auto hold_all = hold("xmin", {0, 1});  // anchors the (unloaded) plate
  hold_all.temperature = core::TimeTable(400.0);
  p.boundaries.push_back(hold_all);
  physics::Simulation sim(p);
  Last none;
  const auto status = sim.run(none);
  EXPECT_TRUE(status.completed) << status.message;
  EXPECT_LE(sim.history("max_temperature"), 400.0 + 1e-9);
  return sim.history("min_temperature");
}

TEST(LumpedHeatCapacity, KeepsTheTemperatureAboveItsInitialValueWhereConsistentUndershoots) {
  // τκ/(ρc_p h²) = 1e-2·50/(7850·450·0.01) ≈ 1.4e-5: a very sharp front for one step.
  const double consistent = min_temperature(false), lumped = min_temperature(true);
  std::printf("min temperature after one step: consistent %.6f K, lumped %.12f K\n", consistent,
              lumped);
  // Measured 6.1e-4 K below 300 K: far beyond round-off (1e-12 K), the undershoot the option
  // exists for (it grows to ~10 K in the ch. 7 examples, whose fronts are sharper still).
  EXPECT_LT(consistent, 300.0 - 1e-4);
  EXPECT_GE(lumped, 300.0 - 1e-9);  // round-off of the solve only
}

}  // namespace
}  // namespace tc::test
