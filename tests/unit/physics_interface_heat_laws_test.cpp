// physics::InterfaceLaws: 𝔉(θ), β_C(θ), δ_C(θ) of (2.13) from numbers and tables in the
// interface temperature, against hand-computed values.
#include <gtest/gtest.h>

#include "tc/physics/interface_heat/interface_laws.hpp"

namespace tc::physics {
namespace {

ContactSettings laws(core::TemperatureTable f, core::TemperatureTable gs,
                     core::TemperatureTable gm) {
  ContactSettings c;
  c.friction = std::move(f);
  c.conductance_slave = std::move(gs);
  c.conductance_master = std::move(gm);
  return c;
}

TEST(InterfaceLaws, ConstantsGiveTheConstantBetaAndDeltaOf213) {
  const InterfaceLaws l(laws(0.3, 1e-4, 4e-4));
  EXPECT_FALSE(l.friction_varies());
  EXPECT_FALSE(l.conductance_varies());
  EXPECT_EQ(l.friction(1.0), 0.3);
  EXPECT_NEAR(l.beta_c(500.0), 8e-5, 1e-20);  // γ^sγ^m/(γ^s + γ^m)
  EXPECT_NEAR(l.delta_c(500.0), 0.2, 1e-15);  // γ^s/(γ^s + γ^m)
  EXPECT_TRUE(l.frictional());
  EXPECT_TRUE(l.conducting());
  const InterfaceLaws none(laws(0.0, 0.0, 0.0));
  EXPECT_FALSE(none.frictional());
  EXPECT_FALSE(none.conducting());
  EXPECT_EQ(none.delta_c(300.0), 0.5);  // both 0: the heat is split evenly
}

TEST(InterfaceLaws, TablesAreEvaluatedPerNode) {
  // 𝔉 falls from 0.5 at 300 K to 0.1 at 500 K; γ^s rises from 1 to 3, γ^m is 2.
  const InterfaceLaws l(laws(core::TemperatureTable({300.0, 500.0}, {0.5, 0.1}),
                             core::TemperatureTable({300.0, 500.0}, {1.0, 3.0}), 2.0));
  EXPECT_TRUE(l.friction_varies());
  EXPECT_TRUE(l.conductance_varies());
  const std::vector<double> theta = {250.0, 400.0, 450.0, 900.0};
  const auto n = l.at(theta);
  ASSERT_EQ(n.friction.size(), 4u);
  const double f[] = {0.5, 0.3, 0.2, 0.1}, gs[] = {1.0, 2.0, 2.5, 3.0};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(n.friction[k], f[k], 1e-15) << k;
    EXPECT_NEAR(n.beta_c[k], gs[k] * 2 / (gs[k] + 2), 1e-15) << k;
    EXPECT_NEAR(n.delta_c[k], gs[k] / (gs[k] + 2), 1e-15) << k;
  }
  EXPECT_TRUE(n.frictional);
  EXPECT_TRUE(n.conducting);
}

TEST(InterfaceLaws, ConductingWhereBothConductancesArePositiveOnlyBetweenTablePoints) {
  // γ^s vanishes at 300 K, γ^m at 400 K: β_C = 0 at every table point, > 0 between them.
  const InterfaceLaws crossing(laws(0.0, core::TemperatureTable({300.0, 400.0}, {0.0, 1.0}),
                                    core::TemperatureTable({300.0, 400.0}, {1.0, 0.0})));
  EXPECT_EQ(crossing.beta_c(300.0), 0.0);
  EXPECT_EQ(crossing.beta_c(400.0), 0.0);
  EXPECT_NEAR(crossing.beta_c(350.0), 0.25, 1e-15);
  EXPECT_TRUE(crossing.conducting());
  // γ^m is zero wherever γ^s is not: no conductance at any temperature.
  const InterfaceLaws apart(laws(0.0, core::TemperatureTable({300.0, 400.0}, {0.0, 1.0}),
                                 core::TemperatureTable({200.0, 300.0}, {1.0, 0.0})));
  EXPECT_FALSE(apart.conducting());
}

}  // namespace
}  // namespace tc::physics
