// Thermoelastic instability (issue 38): the growth rate of tei_growth_test under mesh and τ
// refinement at V/V_cr = 0.5, 2 and 4 (the table of docs/theory.md, "Thermoelastic
// instability of a layer under a rigid flat"), the linearity of the measured rate in the
// seed and in p₀, and the dynamic scheme at 2 V_cr. The run and the closed form:
// tei_layer.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tei_layer.hpp"

namespace tc::test {
namespace {

using namespace tei;

class TeiRefinement : public ::testing::TestWithParam<double> {};

TEST_P(TeiRefinement, ConvergesToTheLinearTheory) {
  const double v = GetParam();
  // (h_x, top cell, V τ/h_x): the default level; the mesh halved in x and in the top cell (at
  // the same V τ/h_x, so τ halves with it); τ halved on the default mesh.
  const Settings levels[] = {
      {.r = v}, {.r = v, .nx = 40, .first = 2.5e-5}, {.r = v, .cells_per_step = 0.5}};
  std::vector<Result> r;
  for (const auto& s : levels) {
    r.push_back(run(s));
    print(r.back());
  }
  for (size_t i = 0; i < r.size(); ++i) {
    // Every level within 1 % of b_τ (measured ≤ 0.25 %; the acceptance asks 5 %).
    EXPECT_NEAR(r[i].fe, r[i].theory_tau, 0.01 * std::abs(r[i].theory_tau)) << "level " << i;
    EXPECT_NEAR(r[i].fe_pressure, r[i].theory_tau, 0.01 * std::abs(r[i].theory_tau))
        << "level " << i;
    EXPECT_GT(r[i].min_pressure, 0.5) << "level " << i;
    EXPECT_GT(r[i].min_slip, 0.999) << "level " << i;  // over the steps not cut back
    EXPECT_LT(r[i].max_slip, 1.001) << "level " << i;
  }
  // The step's and the mesh's shares: b_τ carries backward Euler's factor, so halving τ
  // moves the measured b (read back as (1 − e^{−b_FE τ})/τ) by the fit's scatter only, and
  // halving h_x and the top cell moves it by as little: both within 0.3 % of b (measured
  // ≤ 0.17 % and ≤ 0.16 %; the fit's own scatter is ~0.1 %: with p₀ × 10, where the QP
  // resolves the mode ten times finer, b at 2 V_cr moves by 0.01 %). The discretisation
  // error at the default level is at that scatter's level, far inside the 1 % asked above.
  EXPECT_NEAR(r[2].inverted(), r[0].inverted(), 3e-3 * std::abs(r[0].theory));
  EXPECT_NEAR(r[1].inverted(), r[0].inverted(), 3e-3 * std::abs(r[0].theory));
}

INSTANTIATE_TEST_SUITE_P(Speeds, TeiRefinement, ::testing::Values(0.5, 2.0, 4.0),
                         [](const auto& info) {
                           return "r" + std::to_string(static_cast<int>(10 * info.param));
                         });

TEST(TeiLinearity, TheRateIsOfTheModeAlone) {
  // Linear regime: the seed halved, or p₀ ten times higher (the base state's own cos(mx) part
  // and its heating scale with p₀, the mode does not), give the same b within 0.5 % of it
  // (measured 0.18 % and 0.01 %): the subtraction of the unseeded run is exact for a linear
  // problem, and what is left is the fit's scatter, which doubles with the seed halved (the
  // QP resolves λ_n to a fixed fraction of p₀, so the mode's relative accuracy halves).
  const auto ref = run({.r = 2});
  const auto half = run({.r = 2, .seed_fraction = 0.025});
  const auto high = run({.r = 2, .pressure = 1e8});
  for (const auto* x : {&ref, &half, &high}) print(*x);
  EXPECT_NEAR(half.fe, ref.fe, 5e-3 * ref.theory);
  EXPECT_NEAR(high.fe, ref.fe, 5e-3 * ref.theory);
  // Without the subtraction the base state's own cos(mx) part (the friction's shear against
  // the rollers, 3.6 % of p₀) dominates the seeded run's rate: the subtraction is needed.
  EXPECT_GT(std::abs(ref.fe_seeded / ref.theory_tau - 1), 0.05);
}

TEST(TeiDynamic, InertiaLeavesTheRateAt2Vcr) {
  // The dynamic scheme (Newmark with contact) at 2 V_cr: V = 0.18 m/s against wave speeds of
  // km/s, so inertia changes nothing the theory sees (Afferrante & Ciavarella's dynamic TEI
  // needs V near the Rayleigh speed); the press's vibration is in both runs and cancels in the
  // difference. Within 0.5 % of the quasistatic rate (measured 0.01 %).
  const auto qs = run({.r = 2});
  const auto dyn = run({.r = 2, .scheme = physics::Scheme::dynamic});
  print(qs);
  print(dyn);
  EXPECT_NEAR(dyn.fe, qs.fe, 5e-3 * qs.fe);
  EXPECT_NEAR(dyn.fe, dyn.theory_tau, 0.01 * dyn.theory_tau);
}

}  // namespace
}  // namespace tc::test
