// NaN/Inf detection (docs/robustness.md): a non-finite value stops the run with a
// NumericalError naming the phase (assembly, initial state, heat step, mechanical step,
// contact rows, contact QP), the step and the coupling iteration; the CLI then exits with 1
// and summary.json says "stopped" with that reason. The NaN is put where each phase reads it
// first through Simulation::restore (the checkpoint API), or comes from the case itself.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "support/cli.hpp"
#include "tc/core/error.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/run/simulation.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

tc::physics::Problem read(const std::string& name) {
  return tc::io::read_case(fs::path(TC_SOURCE_DIR) / "tests/cases" / name);
}

/// The message of the NumericalError that `f` throws (fails the test if none).
template <class F>
std::string numerical_error(F&& f) {
  try {
    f();
  } catch (const tc::NumericalError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no NumericalError";
  return "";
}

void expect_contains(const std::string& text, std::initializer_list<const char*> parts) {
  for (const char* p : parts) EXPECT_NE(text.find(p), std::string::npos) << p << " in: " << text;
}

TEST(NaN, AHugeHeatSourceStopsTheRunInTheHeatStepWithExitOne) {
  // 1e307 W/m³ over τ = 1000 s on ρc = 1 J/(m³K): the temperature overflows in step 1.
  const auto dir = tc::test::fresh_dir("nan-heat-source");
  std::ofstream(dir / "case.toml") << R"(
dimension = 2
[time]
step = 1.0e3
end = 1.0e4
[physics]
thermal_expansion = false
thermoelastic_heating = false
[materials.m]
density = 1.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1e-5
specific_heat = 1.0
thermal_conductivity = 1.0e-3
[[bodies]]
name = "b"
material = "m"
mesh = { box = { min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2] } }
heat_source = 1.0e307
[[boundary]]
body = "b"
where = "ymin"
displacement = [0.0, 0.0]
)";
  const auto r =
      thermocontact("run " + (dir / "case.toml").string() + " --output " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const auto summary = tc::test::read_file(dir / "out/summary.json");
  expect_contains(summary, {"\"status\": \"stopped\"", "heat step", "temperature is not finite",
                            "step 1, iteration 1"});
  EXPECT_NE(r.output.find("heat step"), std::string::npos) << r.output;
}

TEST(NaN, InTheAssemblyItIsRefusedBeforeTheFirstStep) {
  auto p = read("valid/plane-strain-2d.toml");
  p.bodies[0].material.thermal_conductivity = nan;  // K_θ
  expect_contains(numerical_error([&] { tc::physics::Simulation sim(p); }),
                  {"assembly", "K_θ", "not finite"});
}

/// The error of the second step of `p` after a NaN was put into θ^1.
std::string nan_in_theta_after_step_1(const tc::physics::Problem& p) {
  tc::physics::Simulation sim(p);
  sim.advance();
  auto c = sim.checkpoint();
  c.bodies[0].theta[3] = nan;
  sim.restore(c);
  return numerical_error([&] { sim.advance(); });
}

TEST(NaN, InTheTemperatureItIsFoundByTheHeatStep) {
  auto p = read("valid/plane-strain-2d.toml");
  p.solver.coupling_order = tc::physics::CouplingOrder::heat_first;
  expect_contains(nan_in_theta_after_step_1(p),
                  {"heat step", "temperature", "step 2, iteration 1"});
}

TEST(NaN, InTheTemperatureWithMechanicsFirstItIsFoundByTheMechanicalStep) {
  // The case has thermoelastic heating: mechanics first by default, and θ^k enters its
  // right-hand side through K_uθ before any heat step.
  const auto p = read("valid/plane-strain-2d.toml");
  ASSERT_FALSE(
      tc::physics::heat_before_mechanics(p.solver.coupling_order, p.physics.thermoelastic_heating));
  expect_contains(nan_in_theta_after_step_1(p),
                  {"mechanical step", "displacement", "step 2, iteration 1"});
}

TEST(NaN, InTheAccelerationItIsFoundByTheMechanicalStep) {
  // Without thermal coupling the mechanical step runs first; Newmark's right-hand side reads ü.
  auto p = read("valid/plane-strain-2d.toml");
  p.physics.thermal_expansion = p.physics.thermoelastic_heating = false;
  tc::physics::Simulation sim(p);
  auto c = sim.checkpoint();
  c.bodies[0].a[5] = INFINITY;
  sim.restore(c);
  expect_contains(numerical_error([&] { sim.advance(); }),
                  {"mechanical step", "displacement", "step 1, iteration 1"});
}

TEST(NaN, InTheDisplacementOfAContactBodyItIsFoundByTheContactPhase) {
  const auto p = read("restart/sliding-2d.toml");
  tc::physics::Simulation sim(p);
  sim.enable_mortar_contact();
  sim.advance();
  sim.advance();
  auto c = sim.checkpoint();
  for (auto& x : c.bodies[p.contacts.at(0).slave_body].u) x = nan;
  sim.restore(c);
  expect_contains(numerical_error([&] { sim.advance(); }),
                  {"contact: the configuration", "not finite", "step 3"});
}

TEST(NaN, InTheMultipliersItIsFoundByTheContactQp) {
  // The contact patch (no heat through the contact): the warm start λ is the only NaN.
  auto p = read("valid/contact-patch-2d.toml");
  p.time.end = 2 * p.time.step;
  tc::physics::Simulation sim(p);
  sim.enable_mortar_contact();
  sim.advance();
  auto c = sim.checkpoint();
  ASSERT_FALSE(c.lambda.empty());
  for (auto& x : c.lambda) x = nan;
  sim.restore(c);
  expect_contains(numerical_error([&] { sim.advance(); }),
                  {"contact QP (6.9)", "step 2, iteration 1"});
}

}  // namespace
