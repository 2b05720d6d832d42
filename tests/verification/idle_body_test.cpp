// A body at rest at θ₀ with nothing on it stays exactly there: the heat step solves for
// θ − θ₀ with K_θ1 = 0 taken exactly (heat_to_deviation), so its right-hand side, its
// temperature change and then its thermal load are exact zeros, and A⁻¹0 = 0 is taken without
// a solve (CholeskySolver::solve). Before, the heat solve returned θ₀ to round-off and the
// body was solved every coupling iteration for the thermal load of that round-off.
//
// The case: the thesis example of ch. 7 on the coarse mesh of tests/cases/feti, both couplings
// on (thermal expansion, thermoelastic heating), so the slave is loaded and heated from step 1
// while the master waits for the touch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "tc/io/case/case_reader.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

double max_deviation(const core::Vector& theta, double theta0) {
  double d = 0;
  const auto v = theta.read();
  for (const double t : v.span()) d = std::max(d, std::abs(t - theta0));
  return d;
}

TEST(IdleBody, StaysExactlyAtRestAndAtTheReferenceTemperatureUntilTouched) {
  auto p =
      io::read_case(std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/thesis-coarse.toml");
  p.physics.thermoelastic_heating = true;
  p.solver.coupling_tolerance = 1e-6;  // the defaults of case-format.md
  p.solver.qp_tolerance = 1e-8;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  const int master = p.contacts.at(0).master_body;
  const int slave = p.contacts.at(0).slave_body;
  const double theta0 = p.physics.reference_temperature;
  int before = 0;
  bool touched = false;
  while (!touched && sim.step() < 20) {
    sim.advance();
    const auto lambda = sim.contact_multipliers();
    touched = std::any_of(lambda.begin(), lambda.end(), [](double l) { return l != 0.0; });
    if (touched) break;
    ++before;
    const auto& m = sim.state(master);
    // Exact: no tolerance. The old absolute solve left |θ − θ₀| ~ 1e-13 K and u ~ 1e-20 m.
    EXPECT_EQ(m.u.max_abs(), 0.0) << "step " << sim.step();
    EXPECT_EQ(m.v.max_abs(), 0.0) << "step " << sim.step();
    EXPECT_EQ(m.a.max_abs(), 0.0) << "step " << sim.step();
    EXPECT_EQ(max_deviation(m.theta, theta0), 0.0) << "step " << sim.step();
    // The slave is pushed at its top face and heats by the thermoelastic term meanwhile: the
    // same checks on it must fail, or the case would not test the skip.
    EXPECT_GT(sim.state(slave).u.max_abs(), 0.0);
    EXPECT_GT(max_deviation(sim.state(slave).theta, theta0), 0.0);
  }
  EXPECT_GE(before, 3) << "the approach should take a few steps";
  ASSERT_TRUE(touched) << "no touch in 20 steps";
  // Once touched the master is loaded and moves: the skip must not keep it at rest.
  sim.advance();
  EXPECT_GT(sim.state(master).u.max_abs(), 0.0);
  EXPECT_GT(max_deviation(sim.state(master).theta, theta0), 0.0);
}

}  // namespace
}  // namespace tc::test
