// Heat across an open gap (physics::GapConductance, gap_conductance.hpp) on the pressed blocks
// of thermal_contact_test (verification.md's 4C case): lower block [0.5,1.5]²×[−0.5,0.5]
// (3×3×3, slave, its top), upper block of height 1 (2×2×2, master), E = 4000, ν = 0, α = 0,
// ρ = c_p = 1, κ = 52; bottom at θ_low, top at θ_high; τ = 1e4 s (each backward-Euler step
// damps the transient below 1e-5, so a few steps are steady to round-off).
//  - At a fixed open gap g (the upper block lifted by g, nothing pressed): the series
//    resistance q = Δθ/(L₁/κ + 1/h(g) + L₂/κ) with h(g) = h_table(g) + k_gas/(g + g₀).
//  - Closing the gap: the upper block lowered step by step through closure into contact; the
//    conductance h(g⁺) + β_C p_n has no jump, so neither has the flux.
//  - Radiation across a fixed open gap (grey parallel faces, ε = 1/(1/ε_s + 1/ε_m − 1)), bottom
//    at 300 K, top at 900 K: the steady flux q solves κ(θ_s − θ_low)/L₁ = q = κ(θ_high − θ_m)/L₂
//    = σε(θ_m⁴ − θ_s⁴) + h(g)(θ_m − θ_s), two equations in the faces' θ_s, θ_m (Newton here).
#include "tc/physics/interface_heat/gap_conductance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kTheta0 = 293.15;
constexpr double kLow = kTheta0 + 20, kHigh = kTheta0 + 40, kKappa = 52;

/// The 4C blocks with the upper one lifted by `lift` and its top moved by `top` (a table).
physics::Problem blocks_across_a_gap(double lift, const core::TimeTable& top, int steps,
                                     const physics::GapConductance& law, double low = kLow,
                                     double high = kHigh) {
  auto p = pressed_conduction_blocks(kTheta0, kKappa, 0.0, steps);
  p.bodies[1].mesh.transform({{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {0, 0, lift});
  for (auto& bc : p.boundaries)
    if (bc.body == 1 && bc.where == "zmax") bc.displacement[2] = top;
  p.boundaries.push_back(temperature_bc(0, "zmin", low));
  p.boundaries.push_back(temperature_bc(1, "zmax", high));
  auto c = contact_pair(0, "zmax", 1, "zmin");
  c.conductance_slave = c.conductance_master = 10.0;  // β_C = 5 W/(m²K Pa) once pressed
  c.gap_conductance = law;
  p.contacts = {c};
  return p;
}

/// The mean over the contact nodes of the conducted flux out of the slave (W/m²).
double mean_flux(const physics::Simulation& sim) {
  const auto f = sim.contact_heat_flux();
  double s = 0;
  for (const double x : f) s += x;
  return f.empty() ? 0.0 : s / static_cast<double>(f.size());
}

/// The steady series state of the two blocks at a fixed open gap: the flux −q at each of the
/// 4×4 nodes of the slave's top and the linear profiles of both blocks (low at the lower
/// block's bottom z = −0.5, high at the upper block's top z = 1.5 + gap), to 1e-8.
void expect_series_state(const physics::Simulation& sim, const physics::Problem& p,
                         const std::vector<double>& flux, double q, double gap, double low,
                         double high) {
  ASSERT_EQ(flux.size(), 16u);
  for (const double f : flux) EXPECT_NEAR(f, -q, 1e-8 * q);
  for (int b = 0; b < 2; ++b) {
    const auto theta = sim.state(b).theta.to_std();
    const auto& m = p.bodies[b].mesh;
    for (int a = 0; a < m.n_nodes(); ++a) {
      const double z = m.point(a)[2];
      const double expected =
          b == 0 ? low + q * (z + 0.5) / kKappa : high - q * (1.5 + gap - z) / kKappa;
      EXPECT_NEAR(theta[a], expected, 1e-8 * (high - low)) << "body " << b << " node " << a;
    }
  }
}

TEST(GapConductance, TwoBlocksAtAFixedOpenGapReachTheSeriesResistance) {
  // h(g) = 30 (1 − g/0.01) + 0.05/(g + 1e-3) at g = 2 mm: 24 + 16.67 = 40.67 W/(m²K), close
  // to κ/L = 52, so that all three resistances count.
  physics::GapConductance law;
  law.table = core::TimeTable({0.0, 0.01}, {30.0, 0.0});
  law.gas_conductivity = 0.05;
  law.gas_offset = 1e-3;
  const double gap = 2e-3;
  const auto p = blocks_across_a_gap(gap, core::TimeTable(0.0), 3, law);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  double before = 0;
  for (int s = 0; s < 3; ++s) {
    before = sim.history("heat_gap_conducted");
    sim.advance();
  }
  EXPECT_LE(sim.history("contact_normal_force"), 1e-12);  // open: no pressure
  const double h = 30 * (1 - gap / 0.01) + 0.05 / (gap + 1e-3);
  ASSERT_NEAR(physics::gap_conductance(law, gap), h, 1e-12 * h);
  const double q = (kHigh - kLow) / (1.0 / kKappa + 1.0 / h + 1.0 / kKappa);
  // Linear elements hold the piecewise linear profile, the nodal gap of flat parallel faces is
  // exact (D diagonal, Σ_j M_kj = D_kk), h uniform: the solves' round-off is what is left, far
  // below the 1e-8 asked.
  const auto flux = sim.contact_heat_flux();
  expect_series_state(sim, p, flux, q, gap, kLow, kHigh);
  // The ledger: all of the conducted heat went through the gap (area 1, slave → master: −q).
  const double step_gap = (sim.history("heat_gap_conducted") - before) / p.time.step;
  EXPECT_NEAR(step_gap, -q, 1e-8 * q);
  EXPECT_NEAR(sim.history("heat_gap_conducted"), sim.history("heat_conducted"),
              1e-12 * std::abs(sim.history("heat_conducted")));
  std::cout << "[ measure  ] fixed open gap: flux " << -flux[0] << " W/m² against " << q
            << " (relative " << -flux[0] / q - 1 << ")\n";
}

TEST(GapConductance, ClosingTheGapChangesTheFluxWithoutAJump) {
  // Gas only, h(g) = k/(g + g₀) with k = 0.02, g₀ = 0.5 mm: 17.4 W/(m²K) at the start, 40 at
  // closure; the upper block lowered 0.1 mm a step from a gap of 1.05 mm: closed during step
  // 11, then pressed 0.1 mm more a step, p = E δ/2 (β_C p grows by 1 W/(m²K) a step).
  physics::GapConductance law;
  law.gas_conductivity = 0.02;
  law.gas_offset = 5e-4;
  constexpr int kSteps = 16;
  constexpr double kStart = 1.05e-3, kRate = 1e-4;
  const double tau = 1e4;
  const core::TimeTable lower({0, kSteps * tau}, {0, -kSteps * kRate});
  const auto p = blocks_across_a_gap(kStart, lower, kSteps, law);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  std::vector<double> q, normal;
  for (int s = 0; s < kSteps; ++s) {
    sim.advance();
    q.push_back(-mean_flux(sim));
    normal.push_back(sim.history("contact_normal_force"));
  }
  int closed = -1;  // the first step with pressure
  for (int s = 0; s < kSteps; ++s)
    if (normal[s] > 0 && closed < 0) closed = s;
  ASSERT_GT(closed, 1);
  ASSERT_LT(closed, kSteps - 2);
  // The change of the flux across closure against the changes on either side: the conductance
  // grows by ≤ 6 W/(m²K) a step before (dh/dg × 0.1 mm) and by β_C E 0.1 mm/2 = 1 after, and at
  // closure by h(0) − h(g_last) + β_C p_first, of the same order; a law that dropped the gap
  // term on contact would jump by −h(0) = −40 W/(m²K) (flux −25 % here).
  double largest_other = 0;
  for (int s = 1; s < kSteps; ++s)
    if (s != closed) largest_other = std::max(largest_other, std::abs(q[s] - q[s - 1]));
  const double at_closure = std::abs(q[closed] - q[closed - 1]);
  EXPECT_LE(at_closure, 1.5 * largest_other);
  EXPECT_GT(q[closed], q[closed - 1]);  // the conductance only grows as the blocks approach
  std::cout << "[ measure  ] closing the gap: flux per step";
  for (const double x : q) std::cout << " " << x;
  std::cout << "; closed in step " << closed + 1 << ", change there " << at_closure
            << " W/m², largest elsewhere " << largest_other << "\n";
}

TEST(GapConductance, RadiationIsTheSecantOfTheFourthPower) {
  // h_rad[θ] = σε(θ_s⁴ − θ_m⁴) is an identity ((a² + b²)(a + b)(a − b) = a⁴ − b⁴): only
  // round-off of a few operations on numbers of 1e11 separates the two sides.
  for (const auto& [ts, tm] : {std::pair{300.0, 900.0}, {1200.0, 400.0}, {500.0, 500.0 + 1e-6}}) {
    const double q = physics::gap_radiation(0.5, ts, tm) * (ts - tm);
    const double exact = physics::kStefanBoltzmann * 0.5 * (std::pow(ts, 4) - std::pow(tm, 4));
    EXPECT_NEAR(q, exact, 1e-12 * physics::kStefanBoltzmann * std::pow(std::max(ts, tm), 4));
  }
  physics::GapConductance law;
  law.emissivity_slave = 0.8;
  law.emissivity_master = 0.5;
  EXPECT_NEAR(law.effective_emissivity(), 1 / (1 / 0.8 + 1 / 0.5 - 1), 1e-15);
  law.emissivity_master = 0;
  EXPECT_EQ(law.effective_emissivity(), 0.0);
}

TEST(GapConductance, RadiationAndGasAcrossAFixedOpenGapReachTheNonlinearSeriesState) {
  // ε_s = ε_m = 0.8 (ε = 2/3) with gas k = 0.02, g₀ = 1 mm at g = 2 mm (h_gas = 6.7 W/(m²K));
  // at ~450 K / ~750 K h_rad ≈ 35 W/(m²K), both comparable to κ/L = 52: each term counts.
  physics::GapConductance law;
  law.gas_conductivity = 0.02;
  law.gas_offset = 1e-3;
  law.emissivity_slave = law.emissivity_master = 0.8;
  const double gap = 2e-3, low = 300, high = 900;
  auto p = blocks_across_a_gap(gap, core::TimeTable(0.0), 1, law, low, high);
  // One step long enough to be steady (τ = 1e12 s against the blocks' L²c/κ ≈ 0.02 s), from
  // 293 K everywhere: only the fixed point iterating θ with h_rad(θ) until θ settles reaches
  // the state (stopped by the rules of a θ-independent conductance, the flux was 2.7 % high).
  // It contracts (|d(h_rad[θ])/dθ| is below the series' conductance); to 1e-12 so that what it
  // leaves is far below the 1e-8 asked.
  p.time.step = p.time.end = 1e12;
  p.solver.coupling_tolerance = 1e-12;
  p.solver.max_coupling_iterations = 200;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  const double before = sim.history("heat_gap_conducted");
  sim.advance();
  EXPECT_LE(sim.history("contact_normal_force"), 1e-12);  // open: no pressure
  // The closed form: F(θ_s, θ_m) = 0 by Newton (quadratic convergence to round-off).
  const double eps = law.effective_emissivity(), sigma = physics::kStefanBoltzmann;
  const double hg = law.gas_conductivity / (gap + law.gas_offset);
  double ts = low + (high - low) / 3, tm = high - (high - low) / 3;
  for (int it = 0; it < 50; ++it) {
    const double across = sigma * eps * (std::pow(tm, 4) - std::pow(ts, 4)) + hg * (tm - ts);
    const double f1 = kKappa * (ts - low) - across, f2 = kKappa * (high - tm) - across;
    const double da_ts = -4 * sigma * eps * std::pow(ts, 3) - hg;
    const double da_tm = 4 * sigma * eps * std::pow(tm, 3) + hg;
    // J = [[κ − da_ts, −da_tm], [−da_ts, −κ − da_tm]]
    const double j11 = kKappa - da_ts, j12 = -da_tm, j21 = -da_ts, j22 = -kKappa - da_tm;
    const double det = j11 * j22 - j12 * j21;
    ts -= (f1 * j22 - f2 * j12) / det;
    tm -= (j11 * f2 - j21 * f1) / det;
  }
  const double q = kKappa * (ts - low);
  // As in the series test: linear elements hold the linear profiles, the nodal gap is exact,
  // θ_s and θ_m uniform over the faces; left are the solves' round-off and the fixed point's
  // 1e-12, far below the 1e-8 asked.
  const auto flux = sim.contact_heat_flux();
  expect_series_state(sim, p, flux, q, gap, low, high);
  const double step_gap = (sim.history("heat_gap_conducted") - before) / p.time.step;
  EXPECT_NEAR(step_gap, -q, 1e-8 * q);
  std::cout << "[ measure  ] radiation + gas across a fixed gap: faces " << ts << " K / " << tm
            << " K, flux " << -flux[0] << " W/m² against " << q << " (relative " << -flux[0] / q - 1
            << "); h_rad = " << physics::gap_radiation(eps, ts, tm) << " W/(m²K), h_gas = " << hg
            << "\n";
}

}  // namespace
}  // namespace tc::test
