// Jaeger's moving band (issue 38): a slider of width 2l heated by friction while it slides at V
// over a deep block that takes all the heat; the block's steady surface temperature under the
// band against the closed form (tests/verification/jaeger_closed_form.hpp, derived there and in
// docs/theory.md, "Jaeger's moving band"), at one Péclet number; jaeger_band_slow.cpp runs
// Pe = 0.5, 2 and 10 with mesh and time-step refinement.
//  - The closed forms against each other: the steady K₀ integral against the transient erf
//    integral at a late time (two formulas, two quadratures), the uniform band through the
//    piecewise-linear one, and Jaeger's large-Pe limit.
//  - The run (jaeger_band.hpp): θ_max and θ̄ against the steady closed form within 2 %, the
//    error smaller at half the step, the run's own frictional flux convolved with the Green's
//    function against its surface temperature within 2 %, the pressure uniform, and the heat
//    ledger (friction work = heat into the block = the block's energy).
#include "jaeger_band.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

namespace tc::test {
namespace {

using namespace jaeger;

TEST(JaegerClosedForm, SteadyAndTransientIntegralsAgree) {
  for (const double pe : {0.5, 2.0, 10.0}) {
    Band b;
    b.v = 2 * pe;
    // V²t/(4k_d) = 100: the missing tail ≈ E₁(100) ≈ 4e-46. What is left is the two quadratures.
    // error (graded Gauss panels, ~1e-9 each against the 1e-7 asked).
    const double t = 400 / (b.v * b.v);
    for (const double x : {-3.0, -1.0, -0.4, 0.0, 0.7, 1.0, 1.5}) {
      const double s = steady_uniform(b, 1, x);
      EXPECT_NEAR(transient_uniform(b, 1, x, t), s, 1e-7 * s) << "Pe " << pe << " X " << x;
      // The piecewise-linear band with a constant flux on 7 uneven pieces is the uniform band.
      const std::vector<double> xs{-1, -0.8, -0.5, -0.45, 0.1, 0.3, 0.9, 1};
      const std::vector<double> qs(xs.size(), 1.0);
      EXPECT_NEAR(steady_profile(b, xs, qs, x), s, 1e-9 * s) << "Pe " << pe << " X " << x;
    }
    // The mean's single integral against the mean of the surface temperature.
    const auto f = [&](double x) { return steady_uniform(b, 1, x); };
    const double mean = (graded(f, -1, 0, -1) + graded(f, 0, 1, 1)) / 2;
    EXPECT_NEAR(steady_uniform_mean(b, 1), mean, 1e-8 * mean) << "Pe " << pe;
  }
}

TEST(JaegerClosedForm, TendsToTheLargePecletLimit) {
  // θ_max → 2ql/(k√(πPe)) at the trailing edge and θ̄ → ⅔θ_max, with a relative correction
  // O(Pe^{-1/2})·small (lateral conduction): at Pe = 400, within 1 % (measured 0.3 %).
  Band b;
  b.v = 800;
  const double limit = 2 / std::sqrt(std::numbers::pi * b.pe());
  const double top = band_maximum([&](double x) { return steady_uniform(b, 1, x); }, 1);
  EXPECT_NEAR(top, limit, 1e-2 * limit);
  std::cout << "[ measure  ] Pe 400: θ_max k/(ql) " << top << ", θ̄ k/(ql) "
            << steady_uniform_mean(b, 1) << " against 2/√(πPe) = " << limit << " and ⅔ of it\n";
  EXPECT_NEAR(steady_uniform_mean(b, 1), 2.0 / 3 * limit, 1e-2 * limit);
}

TEST(JaegerBand, SteadySurfaceTemperatureAtPeclet2) {
  // h = l/10 along the surface (20 cells under the band), the first cell h/4 deep; V τ = h/8 and
  // h/16. The slow test's table (docs/theory.md) at Pe 2, h = l/10: θ̄ −0.77 % at V τ = h/8 and
  // −0.39 % at h/32, first order in τ (backward Euler smooths and delays the moving source),
  // −0.26 % extrapolated to τ → 0, of which the slide's truncation is −0.05 % and the mesh's
  // ~−0.1 % (h/2 moves θ̄ by 0.08 %); θ_max −0.40 % and −0.26 %. 2 % is the acceptance bound,
  // 2.5 times the error at V τ = h/8.
  Result r[2];
  for (int i = 0; i < 2; ++i) {
    r[i] = run({2.0, 0.1, i == 0 ? 8.0 : 16.0});
    print(r[i]);
    EXPECT_NEAR(r[i].fe_max, r[i].cf_max, 0.02 * r[i].cf_max);
    EXPECT_NEAR(r[i].fe_mean, r[i].cf_mean, 0.02 * r[i].cf_mean);
    // (a): the run's own flux through the steady Green's function; the same budget.
    EXPECT_LT(r[i].own_worst, 0.02);
    // (b): the pressure uniform to the block's compliance, ~1e-3 measured (5e-3 asked): far
    // inside the 2 %, so the uniform band's closed form is the run's.
    EXPECT_LT(r[i].spread, 5e-3);
    EXPECT_LT(std::abs(r[i].mean_pressure), 1e-3);
    // The ledger: the friction work τ T V of each step is the heat generated to the slip's
    // change (the slider's shear, built in the first slide step: 𝔉p H/G ~ 1e-4 l of the 6 l
    // slide), all of it into the block (δ_C = 0) and kept there (insulated: round-off).
    EXPECT_NEAR(r[i].friction_heat, 0, 1e-3);
    EXPECT_NEAR(r[i].to_block, 0, 1e-12);
    EXPECT_NEAR(r[i].block_energy, 0, 1e-8);  // θ ≈ 293 K against a rise of ~1 K
  }
  // Backward Euler's error halves with τ.
  EXPECT_LT(std::abs(r[1].fe_mean / r[1].cf_mean - 1), std::abs(r[0].fe_mean / r[0].cf_mean - 1));
}

}  // namespace
}  // namespace tc::test
