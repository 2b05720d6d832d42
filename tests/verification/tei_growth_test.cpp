// Thermoelastic instability (issue 38): a deep steel layer under a rigid non-conducting flat
// sliding at V, seeded with the cos(mx) eigenmode's temperature; the growth (or decay) rate b
// of the mode measured in a transient run against the linear stability theory
// (tests/verification/tei_layer.hpp; docs/theory.md, "Thermoelastic instability of a layer
// under a rigid flat"), at V/V_cr = 0.5, 2, 4 and on both sides of V_cr. tei_growth_slow.cpp
// refines the mesh and τ, checks the linearity and runs the dynamic scheme.
//  - The closed form against its dimensional relations (the dispersion relation, V_cr, P/Θ).
//  - The run: b of the θ mode (seeded − unseeded run) against b_τ = −ln(1 − bτ)/τ, the
//    pressure mode's rate and P/Θ, the contact closed and slipping at every node and step.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "tei_layer.hpp"

namespace tc::test {
namespace {

using namespace tei;

TEST(TeiClosedForm, SolvesTheDispersionRelation) {
  const Constants c;
  const double m = c.m(), kappa = c.kappa();
  // The dimensional relation λ(λ + m) = 𝔉 V E α m/(k(1 − ν)) with λ = √(m² + b/κ), b from
  // rate(): the non-dimensional root and its scaling against the relation it came from.
  for (const double r : {0.5, 0.95, 1.0, 1.05, 2.0, 4.0}) {
    const double v = r * c.critical_speed();
    const double b = rate(r) * c.rate_unit();
    const double lambda = std::sqrt(m * m + b / kappa);
    const double rhs =
        c.friction * v * c.young * c.expansion * m / (c.conductivity * (1 - c.poisson));
    EXPECT_NEAR(lambda * (lambda + m), rhs, 1e-12 * rhs) << "r " << r;
    // The mode's pressure: the thermoelastic surface displacement 2α(1 + ν)Θ/(λ + m) over the
    // half-plane's compliance 2(1 − ν²)/(E m) for a cos(mx) pressure.
    const double u = 2 * c.expansion * (1 + c.poisson) / (lambda + m);
    const double p = u * c.young * m / (2 * (1 - c.poisson * c.poisson));
    EXPECT_NEAR(pressure_per_kelvin(c, r), p, 1e-12 * p) << "r " << r;
    // The heat balance k λ Θ = 𝔉 V P closes the loop.
    EXPECT_NEAR(c.conductivity * lambda, c.friction * v * p, 1e-12 * c.conductivity * lambda);
  }
  EXPECT_NEAR(rate(1.0), 0.0, 1e-15);  // V_cr is the neutral speed
  EXPECT_LT(rate(0.999), 0.0);
  EXPECT_GT(rate(1.001), 0.0);
  // Backward Euler's factor 1/(1 − bτ) per step, read back as a rate.
  EXPECT_NEAR(std::exp(discrete_rate(2.0, 0.1) * 0.1), 1 / (1 - 0.2), 1e-14);
  std::cout << "[ measure  ] V_cr " << c.critical_speed() << " m/s, κm² " << c.rate_unit()
            << " 1/s, b/κm² at r = 0.5, 2, 4: " << rate(0.5) << ", " << rate(2) << ", " << rate(4)
            << "\n";
}

/// The checks every run passes: the contact closed (λ_n ≥ ½p₀: the mode's 5 % grown by e^{1.5}
/// and the base state's own cos(mx) part stay far from opening it) and in full slip the same
/// way at every node (the slip per unit length V τ to 1e-3: the surface's own tangential
/// displacement is ~1e-4 of it), the mode clean over the fit (the pressure's rate and P/Θ).
void expect_linear_regime(const Result& r) {
  EXPECT_GT(r.min_pressure, 0.5) << "V/V_cr " << r.s.r;
  EXPECT_GT(r.min_slip, 0.999) << "V/V_cr " << r.s.r;
  EXPECT_LT(r.max_slip, 1.001) << "V/V_cr " << r.s.r;
  EXPECT_EQ(r.cut_backs, 0) << "V/V_cr " << r.s.r;  // every step whole: b_τ is of τ
}

TEST(TeiGrowth, RatesAtHalfTwiceAndFourTimesTheCriticalSpeed) {
  // h_x = λ_w/40, the top cell 0.05 mm (12 of the 33 cells in the thermal decay length
  // 1/(ℓm) = 1.3 mm at r = 4), V τ = h_x. Measured errors against b_τ: +0.25 %, −0.16 %,
  // −0.14 % at r = 0.5, 2, 4; tei_growth_slow: halving h_x and the top cell, or τ, moves b by
  // ≤ 0.17 % (the discretisation's share is at the fit's scatter; b_τ accounts for backward
  // Euler's factor). 1 % is 4 × the largest error; the acceptance asks 5 %.
  for (const double v : {0.5, 2.0, 4.0}) {
    const auto r = run({.r = v});
    print(r);
    EXPECT_NEAR(r.fe, r.theory_tau, 0.01 * std::abs(r.theory_tau)) << "V/V_cr " << v;
    // The pressure's cos(mx) part grows at the same rate, and its ratio to the temperature's
    // is the closed form's P/Θ = Eα/((1 − ν)(ℓ + 1)): the measured mode is the theory's
    // eigenmode, not only its rate (measured within 0.4 %).
    EXPECT_NEAR(r.fe_pressure, r.theory_tau, 0.01 * std::abs(r.theory_tau)) << "V/V_cr " << v;
    EXPECT_NEAR(r.pressure_ratio, 0, 0.01) << "V/V_cr " << v;
    expect_linear_regime(r);
  }
}

TEST(TeiGrowth, ChangesSignAtTheCriticalSpeed) {
  // At 0.95 and 1.05 V_cr the mode decays and grows; b(V) interpolated linearly between them
  // vanishes within 1 % of V_cr (measured 0.1 %; the acceptance asks 5 %). b is ±0.066 κm²
  // there, so this asks b to ~0.015 κm² absolute: the errors at 0.5–4 V_cr are ≤ 0.004 κm².
  const auto lo = run({.r = 0.95});
  const auto hi = run({.r = 1.05});
  print(lo);
  print(hi);
  EXPECT_LT(lo.fe, 0);
  EXPECT_GT(hi.fe, 0);
  const double zero = 0.95 + 0.1 * lo.fe / (lo.fe - hi.fe);
  std::cout << "[ measure  ] b = 0 at V/V_cr " << zero << "\n";
  EXPECT_NEAR(zero, 1.0, 0.01);
  expect_linear_regime(lo);
  expect_linear_regime(hi);
}

TEST(TeiGrowth, TheSolversDefaultQpsSolveTheNormalRowsOfASlide) {
  // The QP's stopping test holds the normal rows to their own ‖d_n‖ (qp::QpOptions::
  // row_groups). Against the whole ‖d‖ alone — the tangential rows' slip V τ D, here
  // ~500 × the normal rows' p₀/E-sized gaps at p₀ = 1 MPa — the default qp_tolerance and the
  // friction loop's forcing let the warm start pass for solved: λ_n stayed at its first slide
  // step's value and b came out wrong (docs/choices.md, "TEI run"). With the solver's
  // defaults, b within 2 % of b_τ (2 × the tight-QP test's tolerance: the default
  // tolerances leave a scatter of the per-step rate at this p₀).
  const auto r = run({.r = 2, .pressure = 1e6, .tight_qps = false});
  print(r);
  EXPECT_NEAR(r.fe, r.theory_tau, 0.02 * std::abs(r.theory_tau));
  expect_linear_regime(r);
}

TEST(TeiGrowth, SeveralCellsOfSlideAStepKeepTheRate) {
  // A slide of 4 cells a step (V τ = 4 h_x, bτ = 0.02 at 2 V_cr): before the gap was
  // linearised about the predicted configuration (docs/theory.md, "Sliding: the gap's
  // linearisation") a grid-scale oscillation of λ_n grew 2–10 × a step from the corners and
  // put b +51 % off (docs/choices.md, "TEI run", defect 2); measured now −0.19 %. Within 1 %
  // of b_τ, as at V τ = h_x.
  const auto r = run({.r = 2, .cells_per_step = 4});
  print(r);
  EXPECT_NEAR(r.fe, r.theory_tau, 0.01 * std::abs(r.theory_tau));
  expect_linear_regime(r);
}

}  // namespace
}  // namespace tc::test
