// Coulomb sliding with frictional heating on second-order contact surfaces, through Simulation:
// the slider of support/problems.hpp's slider_on_base (pressed 10 µm, then dragged at v for
// 10 steps, insulated, α = 0) with both bodies of Hex20 (Quad8 faces: the transformed dual
// basis) or Hex27 (Quad9), and Hex8 for the same closed forms at first order. Closed forms:
//  - gross sliding: every active node on its Coulomb disc, Σw‖λ_τ‖ = 𝔉 Σwλ_n (T/N = 𝔉);
//  - heat_generated = 𝔉 N v t over the sliding steps (thermal_contact_test.cpp), δ_C of it to
//    the slave, and the thermal energy's rise equal to it (insulated bodies);
//  - the mechanical ledger: strain energy + dissipation − external work = ½ 𝔉N vτ, the half
//    step of friction work the trapezoidal external work misses at the start of the slide
//    (quasistatic_work_test.cpp), i.e. 1/20 of the dissipation of the 10 steps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/body_energy.hpp"
#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kTheta0 = 293.15;
constexpr double kV = 0.01, kTau = 0.1, kFriction = 0.3;
constexpr int kSlideSteps = 10;

class QuadraticSliding : public ::testing::TestWithParam<mesh::CellType> {};

TEST_P(QuadraticSliding, CoulombHeatAndEnergyLedgerMatchTheClosedForms) {
  const mesh::CellType element = GetParam();
  auto mat = steel();
  mat.thermal_expansion = 0;
  auto p = slider_on_base(mat, kTau, kV, kSlideSteps, kTheta0, kTheta0 + 5, kFriction);
  p.bodies[0].mesh = mesh::make_box(3, {0, 0, 1}, {1, 1, 1.5}, {4, 4, 2}, element);
  p.bodies[1].mesh = mesh::make_box(3, {-0.25, -0.25, 0}, {1.25, 1.25, 1}, {5, 5, 3}, element);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  const double e0 = sim.history("thermal_energy");
  const double e_s0 = body_energy(sim, 0, kTheta0), e_m0 = body_energy(sim, 1, kTheta0);
  sim.advance();  // the press
  double expected = 0, worst_ratio = 0;
  for (int s = 0; s < kSlideSteps; ++s) {
    sim.advance();
    const double normal = sim.history("contact_normal_force");
    ASSERT_GT(normal, 0) << "step " << sim.step();
    expected += kTau * kFriction * normal * kV;
    // Every active node slides; T/N = 𝔉 to 1e-6: the fixed point stops at a relative change
    // of 1e-8 of λ and the QP at 1e-10 (thermal_contact_test.cpp's slider, first order).
    EXPECT_EQ(sim.history("slip_nodes"), sim.history("active_nodes")) << "step " << sim.step();
    const double ratio = sim.history("contact_tangential_force_sum") / normal;
    worst_ratio = std::max(worst_ratio, std::abs(ratio / kFriction - 1));
    EXPECT_NEAR(ratio, kFriction, 1e-6 * kFriction) << "step " << sim.step();
  }
  // Every slave node of the slider's bottom, vertex and mid-edge, is a contact node in contact.
  EXPECT_EQ(sim.history("active_nodes"),
            static_cast<double>(p.bodies[0].mesh.boundary_nodes("zmin").size()));
  const double generated = sim.history("heat_generated");
  ASSERT_GT(generated, 0);
  // 𝔉Nvt: the slider slides at v once the first sliding step has built the elastic shear
  // (𝔉ph/G ≈ 1e-6 m against vτ = 1e-3 m per step): 0.5 % (the bound) is generous.
  EXPECT_NEAR(generated, expected, 0.005 * expected);
  // Heat = the mechanical dissipation, the same sum at the last heat iterate (coupling 1e-8).
  EXPECT_NEAR(generated, sim.history("frictional_dissipation"), 1e-7 * generated);
  EXPECT_NEAR(sim.history("heat_to_slave") / generated, sim.interface_laws().delta_c(kTheta0),
              1e-12);
  EXPECT_NEAR(sim.history("heat_to_slave") + sim.history("heat_to_master"), generated,
              1e-12 * generated);
  // Insulated: 1ᵀM_θ conserved, 1ᵀK_θ = 0, 1ᵀL_θγ = 0: the rise is the heat to the solves'
  // round-off (θ ~ 300 K, ~1e-13 relative of ρc_pVθ ~ 1e9 J).
  EXPECT_NEAR(sim.history("thermal_energy") - e0, generated, 1e-6 * generated);
  const double conducted = sim.history("heat_conducted");
  EXPECT_NEAR(body_energy(sim, 0, kTheta0) - e_s0, sim.history("heat_to_slave") - conducted,
              1e-6 * generated);
  EXPECT_NEAR(body_energy(sim, 1, kTheta0) - e_m0, sim.history("heat_to_master") + conducted,
              1e-6 * generated);
  EXPECT_GT(conducted, 0.0);  // the slider starts 5 K hotter
  // The mechanical ledger's closed-form gap: ½ of one step's friction work of 10 steps. What
  // it leaves out, as in quasistatic_work_test.cpp: the elastic transition of the first
  // sliding step and the drift of N (~0.1 %): 3 % of the gap.
  const double work = sim.history("external_work"), strain = sim.history("strain_energy");
  const double dissipation = sim.history("frictional_dissipation");
  const double gap = (strain + dissipation - work) / dissipation;
  EXPECT_NEAR(gap, 0.5 / kSlideSteps, 0.03 * 0.5 / kSlideSteps);
  std::printf(
      "[ measure  ] %s sliding: max |T/N/𝔉 − 1| = %.2e, heat_generated %.6e J, 𝔉Nvt "
      "%.6e J (relative %.2e), ledger gap %.5f of the dissipation (closed form %.5f), "
      "%ld coupling iterations, %g contact nodes\n",
      mesh::name(element), worst_ratio, generated, expected, (generated - expected) / expected, gap,
      0.5 / kSlideSteps, sim.total_coupling_iterations(), sim.history("active_nodes"));
}

INSTANTIATE_TEST_SUITE_P(Elements, QuadraticSliding,
                         ::testing::Values(mesh::CellType::Hex8, mesh::CellType::Hex20,
                                           mesh::CellType::Hex27),
                         [](const auto& info) { return std::string(mesh::name(info.param)); });

}  // namespace
}  // namespace tc::test
