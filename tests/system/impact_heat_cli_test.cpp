// The thermoelastic heat of an impact (tests/cases/verification/impact-thermoelastic-2d.toml): a
// block pushed by a force onto a plate, dynamic with the default modified mass. The impact sets
// the block ringing: Newmark's velocities alternate from step to step and never damp. With
// [physics] thermoelastic_rate = "newmark" (the thesis' (5.6)) that ringing entered θ₀K_uθᵀu̇ as
// a heat source alternating in sign, the first layer of cells above the contact heating and
// cooling by turns: ±2.5 K here, ±150 K for a user's Gmsh punch at τ = 5 ms. The default rate,
// (u^{k+1} − u^k)/τ, follows the strain instead (docs/choices.md, "The thermoelastic term at the
// step's mean rate").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

const fs::path kCase =
    fs::path(TC_SOURCE_DIR) / "tests/cases/verification/impact-thermoelastic-2d.toml";

/// The largest |θ − θ₀| of the run's history, θ₀ = 293.15 K.
double largest_deviation(const std::string& extra, const std::string& dir) {
  const auto out = fresh_dir(dir);
  const auto r = thermocontact("run " + kCase.string() + " --output " + out.string() + extra);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto h = read_history(out / "history.csv");
  EXPECT_TRUE(h.whole);
  double d = 0;
  for (const char* c : {"max_temperature", "min_temperature"})
    for (const double v : column(h, c)) d = std::max(d, std::abs(v - 293.15));
  return d;
}

TEST(ImpactHeatCli, TheTemperatureFollowsTheStrainNotTheRinging) {
  // The adiabatic bound: |Δθ| ≤ θ₀β|tr ε|/(ρc_p), β = Eα/(1 − 2ν) = 6e6 Pa/K, θ₀β/(ρc_p) = 498 K.
  // The force, 1e5 N/m on 0.02 m, is 5 MPa; with the corners' concentration (a few times that)
  // |σ_xx + σ_yy| ≤ 5e7 Pa, plane strain tr ε = (1 + ν)(1 − 2ν)/E (σ_xx + σ_yy) ≤ 1.3e-4, so
  // |Δθ| ≤ 0.065 K, before conduction spreads it. 0.5 K leaves a margin of 8.
  const double mean_rate = largest_deviation("", "impact-heat-mean");
  EXPECT_LT(mean_rate, 0.5);
  // The thesis' rate, run for the record: the ringing's ±2.5 K, 5 times the bound and 40 times
  // the default's.
  const double newmark =
      largest_deviation(" --set physics.thermoelastic_rate=\\\"newmark\\\"", "impact-heat-newmark");
  EXPECT_GT(newmark, 1.0);
  std::printf("largest |θ − θ₀|: step mean rate %.4f K, Newmark's rate %.4f K\n", mean_rate,
              newmark);
}

}  // namespace
}  // namespace tc::test
