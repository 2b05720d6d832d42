// Temperature-dependent interface laws (2.13): 𝔉(θ) and γ_C(θ) as tables in the interface
// temperature θ_Γ = ½(θ_s + θ_m) at each slave contact node (physics::InterfaceLaws), end to
// end through Simulation with the mortar pair, each against a closed form:
//  - Steady sliding over a temperature gradient: in full slip ‖λ_τ,k‖ = 𝔉(θ_Γ,k) λ_n,k at
//    every contact node, with θ_Γ,k known in closed form (linear profile in the slider, the
//    base at θ₀), so the table is evaluated at five temperatures on both of its segments.
//  - A constant written as a number, a one-point table or a flat table: the same history,
//    bit for bit.
//  - Steady conduction through two pressed blocks with γ_C^s(θ) a table: the series
//    resistance q = Δθ/(L/κ + 1/h + L/κ), h = β_C(θ_Γ) p_n, θ_Γ the mean of the end
//    temperatures by symmetry.
#include "tc/physics/interface_heat/interface_laws.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kTheta0 = 293.15;

// ---------------------------------------------------------------------------------------------
// Sliding over a temperature gradient: the slider [0,1]²×[1,1.5] (4×4×2) is pressed (step 1)
// onto the base [−0.25,1.25]²×[0,1] (5×5×3, bottom held, wider: the slider stays covered) and
// dragged along x by its top. The slider's ends x = 0 and x = 1 are held at θ₀ + 10 and
// θ₀ + 50 K, the base stays at θ₀ (insulated, no heat crosses: conduction and frictional
// heating off, α = 0); c_p = 1e-6 J/(kg K) makes the slider's profile steady within a step
// (τκπ²/(ρc_pL²) ≈ 6e3). At a slave node with reference x = X:
//   θ_s = θ₀ + 10 + 40X, θ_m = θ₀  →  θ_Γ = θ₀ + 5 + 20X ∈ [θ₀ + 5, θ₀ + 25].
constexpr double kV = 0.01, kTau = 0.1;
constexpr int kSlideSteps = 6;

// 𝔉(θ): 0.4 at θ₀, 0.3 at θ₀ + 10, 0.2 at θ₀ + 30 (two slopes, both used).
core::TemperatureTable friction_law() {
  return core::TemperatureTable({kTheta0, kTheta0 + 10, kTheta0 + 30}, {0.4, 0.3, 0.2});
}

// The same law by hand, at the interface temperature of the node with reference x = X.
double expected_friction(double x) {
  const double d = 5 + 20 * x;  // θ_Γ − θ₀
  return d <= 10 ? 0.4 - 0.01 * d : 0.3 - 0.005 * (d - 10);
}

physics::Problem sliding_on_a_gradient(core::TemperatureTable friction, bool heat) {
  auto mat = steel();
  mat.thermal_expansion = 0;
  mat.specific_heat = heat ? mat.specific_heat : 1e-6;
  auto p = slider_on_base(mat, kTau, kV, kSlideSteps, kTheta0, kTheta0 + 30, 0.0);
  p.boundaries.push_back(temperature_bc(0, "xmin", kTheta0 + 10));
  p.boundaries.push_back(temperature_bc(0, "xmax", kTheta0 + 50));
  p.contacts.at(0).friction = std::move(friction);
  p.contacts.at(0).heat_conduction = heat;
  p.contacts.at(0).frictional_heating = heat;
  return p;
}

// Nested (default) and staggered friction loops: with the staggered one 𝔉_k changes between
// the single Tresca updates of successive heat–mechanics iterations, never inside one.
class SteadySliding : public ::testing::TestWithParam<physics::FrictionLoop> {};

TEST_P(SteadySliding, FollowsTheFrictionTableAtTheInterfaceTemperature) {
  auto p = sliding_on_a_gradient(friction_law(), false);
  p.solver.friction_loop = GetParam();
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  for (int s = 0; s <= kSlideSteps; ++s) sim.advance();
  const auto lambda = sim.contact_multipliers();
  const auto& rows = sim.dual_solver()->rows();
  const auto& nodes = sim.mortar()->contact_nodes();
  const auto& slave = p.bodies[0].mesh;
  ASSERT_EQ(rows.n_nodes(), 25);  // the 5×5 nodes of the slider's bottom
  ASSERT_EQ(nodes.size(), 25u);
  // In full slip the Coulomb bound holds with equality, ‖λ_τ,k‖ = 𝔉_k λ_n,k: to the fixed
  // point's tolerance, |λ_n,k − γ_k| ≤ 1e-8‖λ‖ ≈ 5e-8 λ_n,k (25 nodes of comparable λ_n), and
  // the QP's 1e-10; θ_Γ is exact to round-off (linear profiles, which linear elements and the
  // dual mortar basis reproduce). 1e-6 relative is the acceptance bound and far above these.
  double worst = 0, force_sum = 0;
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    const double ln = lambda[3 * k];
    const double lt = std::hypot(lambda[3 * k + 1], lambda[3 * k + 2]);
    const double x = slave.point(nodes[k])[0];
    const double f = expected_friction(x);
    ASSERT_GT(ln, 0) << "node " << k;
    EXPECT_NEAR(lt / ln, f, 1e-6 * f) << "node " << k << " at x = " << x;
    // The law as the code evaluated it: θ_Γ to the round-off of the heat solves (~1e-12 of θ,
    // 3e-10 K), times the table's slope of 0.01/K.
    EXPECT_NEAR(sim.nodal_laws().friction[k], f, 1e-10) << "node " << k;
    worst = std::max(worst, std::abs(lt / ln - f) / f);
    force_sum += rows.weights[k] * f * ln;
  }
  std::cout << "[ measure  ] max |‖λ_τ‖/λ_n − 𝔉(θ_Γ)|/𝔉 over the 25 nodes: " << worst << "\n";
  // The history counts every node as slipping, each against its own 𝔉_k, and the sum of the
  // nodal friction forces is Σ_k w_k 𝔉_k λ_n,k.
  const auto& cs = sim.contact_statistics();
  EXPECT_EQ(cs.active_nodes, 25);
  EXPECT_EQ(cs.slip_nodes, 25);
  EXPECT_NEAR(sim.history("contact_tangential_force_sum"), force_sum, 1e-6 * force_sum);
}

INSTANTIATE_TEST_SUITE_P(InterfaceLaws, SteadySliding,
                         ::testing::Values(physics::FrictionLoop::nested,
                                           physics::FrictionLoop::staggered),
                         [](const auto& info) {
                           return info.param == physics::FrictionLoop::nested ? "Nested"
                                                                              : "Staggered";
                         });

// A constant 𝔉 and γ_C written as a number, a one-point table and a flat table: the same run,
// history bit for bit (wall_seconds aside), with frictional heating and conduction on.
TEST(InterfaceLaws, AConstantAsANumberOrAOnePointOrAFlatTableGivesTheSameHistory) {
  using Table = core::TemperatureTable;
  struct Form {
    Table friction, gamma_slave;
  };
  const std::vector<Form> forms = {
      {0.3, 1e-4},
      {Table({350.0}, {0.3}), Table({290.0}, {1e-4})},
      {Table({300.0, 310.0, 400.0}, {0.3, 0.3, 0.3}), Table({320.0, 330.0}, {1e-4, 1e-4})}};
  std::vector<std::vector<std::vector<double>>> histories;
  std::vector<std::string> columns;
  for (const auto& f : forms) {
    auto p = sliding_on_a_gradient(f.friction, true);
    p.time.end = 4 * kTau;
    p.contacts.at(0).conductance_slave = f.gamma_slave;
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    std::vector<std::vector<double>> rows;
    for (int s = 0; s < 4; ++s) {
      sim.advance();
      rows.push_back(sim.history_row());
    }
    columns = sim.history_columns();
    histories.push_back(std::move(rows));
  }
  ASSERT_GT(
      histories[0]
          .back()[std::find(columns.begin(), columns.end(), "heat_generated") - columns.begin()],
      0.0);
  for (size_t form = 1; form < forms.size(); ++form)
    for (size_t s = 0; s < histories[0].size(); ++s)
      for (size_t i = 0; i < columns.size(); ++i) {
        if (columns[i] == "wall_seconds") continue;
        EXPECT_EQ(histories[form][s][i], histories[0][s][i])
            << "form " << form << ", step " << s + 1 << ", " << columns[i];
      }
}

// ---------------------------------------------------------------------------------------------
// Conduction through two pressed blocks (as thermal_contact_test's series resistance): the
// lower block [0.5,1.5]²×[−0.5,0.5] (slave, its bottom at θ₀ + 20) and the upper
// [0.5,1.5]²×[0.5,1.5] (master, its top at θ₀ + 40), both 1 m thick with the same κ, pressed
// by p_n = E δ/(2L) = 30 Pa. The slave's γ_C^s is a table, 4 at θ₀ + 20 and 16 at θ₀ + 40,
// the master's γ_C^m = 10. By symmetry of the two equal bars the interface temperatures sit
// symmetrically about the mean, θ_Γ = ½(θ_s + θ_m) = θ₀ + 30 whatever h is: γ_C^s(θ_Γ) = 10,
// β_C = 5, h = β_C p_n = 150 W/(m²K), q = 20/(2/κ + 1/h). The slave's own temperature θ_s =
// θ₀ + 28.52 would give γ_C^s = 9.11, h = 143.0 and q 1.2 % lower: the test tells them apart.
constexpr double kLow = kTheta0 + 20, kHigh = kTheta0 + 40, kKappa = 52, kPush = 0.015;

TEST(InterfaceLaws, SteadyConductionUsesTheConductanceTableAtTheInterfaceTemperature) {
  // τ = 1e4 s: the transient decays by < 1e-5 per step, steady to round-off in 5.
  auto p = pressed_conduction_blocks(kTheta0, kKappa, kPush, 5);
  p.boundaries.push_back(temperature_bc(0, "zmin", kLow));
  p.boundaries.push_back(temperature_bc(1, "zmax", kHigh));
  auto c = contact_pair(0, "zmax", 1, "zmin");
  c.conductance_slave = core::TemperatureTable({kLow, kHigh}, {4.0, 16.0});
  c.conductance_master = 10.0;
  p.contacts = {c};
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  double conducted_before = 0;
  for (int s = 0; s < 5; ++s) {
    conducted_before = sim.history("heat_conducted");
    sim.advance();
  }
  const double pressure = 4000 * kPush / 2.0;  // 30
  const double h = 5.0 * pressure;             // β_C(θ₀ + 30) = 10·10/(10 + 10)
  const double q = (kHigh - kLow) / (2.0 / kKappa + 1.0 / h);
  // Linear profiles and a uniform pressure are reproduced exactly (as in the constant case,
  // thermal_contact_test): left are the coupling tolerance (1e-12) on θ, which moves θ_Γ and
  // so h by its slope, and round-off. 1e-8 relative is far above both, and far below the
  // 1.2 % that a wrong interface temperature would make.
  const double tol = 1e-8;
  const auto& laws = sim.nodal_laws();
  ASSERT_EQ(laws.beta_c.size(), 16u);
  for (const double b : laws.beta_c) EXPECT_NEAR(b, 5.0, tol * 5);
  const auto& flux = sim.contact_heat_flux();
  ASSERT_EQ(flux.size(), 16u);
  double worst = 0;
  for (const double f : flux) {
    EXPECT_NEAR(f, -q, tol * q);
    worst = std::max(worst, std::abs(f + q) / q);
  }
  std::cout << "[ measure  ] max |q_k − q|/q over the 16 nodes: " << worst << "\n";
  EXPECT_NEAR((sim.history("heat_conducted") - conducted_before) / p.time.step, -q, tol * q);
  const double th_slave = kLow + q / kKappa;
  const auto theta = sim.state(0).theta.to_std();
  for (const int a : p.bodies[0].mesh.boundary_nodes("zmax"))
    EXPECT_NEAR(theta[a], th_slave, tol * (kHigh - kLow)) << "slave node " << a;
}

}  // namespace
}  // namespace tc::test
