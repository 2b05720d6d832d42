// Hertz in 2D, the rate study of contact_hertz_rates_test.cpp one level finer (h = a/4 … a/32)
// and with every cell refined with h (the far field's size 0.2R·h/h₀ too, so that the far
// field's discretisation error does not set a floor), Tri3 against Tri6 (hertz_rates_2d.hpp).
// Measured (docs/theory.md, "Hertz under refinement"): e_in falls at ~1.3 (Tri3) and ~1.7
// (Tri6) over the four levels; the second order reaches ~2.4e-4 at a/32, which is the floor of
// the set-up rather than of the discretisation (Quad8 stops at the same ~2.7e-4 from a/16 on):
// Hertz's half-spaces against the finite half-disc and block, and the arc against a flat
// contact surface, differ by O((a/R)²) = 4.6e-4.
// Asserted: the second-order e_in below the first-order one at every level and its slope the
// larger; the second order's finest e_in below 4e-4 (its floor, with the margin of the Quad8
// and Tri6 values); both slopes above 0.9 (measured 1.26 and 1.71).
#include <gtest/gtest.h>

#include "verification/hertz_rates_2d.hpp"

namespace tc::test::hertz2d {
namespace {

TEST(Hertz2dRatesFine, Tri6ConvergesFasterThanTri3DownToTheSetUpsFloor) {
  const std::vector<double> levels{kHalfWidth / 4, kHalfWidth / 8, kHalfWidth / 16,
                                   kHalfWidth / 32};
  const auto linear = study({"Tri3", 1, false, false}, levels, true);
  const auto quadratic = study({"Tri6", 2, false, false}, levels, true);
  const double r1 = hertz::fitted_rate(linear, true), r2 = hertz::fitted_rate(quadratic, true);
  std::printf("[ measure  ] e_in rate %.2f (Tri3) against %.2f (Tri6)\n", r1, r2);
  EXPECT_GT(r2, r1);
  EXPECT_GT(r1, 0.9);
  for (size_t i = 0; i < levels.size(); ++i)
    EXPECT_LT(quadratic[i].e.inner, linear[i].e.inner) << "level " << i;
  EXPECT_LT(quadratic.back().e.inner, 4e-4);
}

}  // namespace
}  // namespace tc::test::hertz2d
