// Example 07 (the reciprocating pin-on-plate tribometer, Gmsh Tet4 meshes, frictional heating,
// conduction across the contact, films and radiation) run whole as committed, and its physics
// checked against the laws its README quotes:
// - Coulomb: in every sliding step (all steps after the pressing one) the resultant tangential
//   force over the normal one, and Σ_k w_k‖λ_τ,k‖ over it, equal 𝔉 = 0.3 to 1e-6;
// - the frictional heat equals the friction work of the steps (to the coupling tolerance), is
//   split ½ / ½ (δ_C = ½), and lies within 2 % below 𝔉 Σ_k N_k |Δx_k| (the holder's 0.5 mm per
//   step; the pin's base lags its holder by the elastic deflection 2𝔉N/k_t at each of the 30
//   stroke reversals: 1.3 % measured);
// - the heat ledger: with thermoelastic heating off and no prescribed temperature or flux,
//   thermal_energy = heat_generated − heat_film − heat_radiation at every step, to 1e-6 of the
//   heat generated;
// - heat leaves through the films and by radiation (both grow), the temperature rises by 5 to
//   30 K (the README's estimate: ≈ 10 K on the contact face), and never falls more than 1 mK
//   below the initial 293.15 K (tetrahedra: the P1 stiffness is not an M-matrix).
// Slow: the 121 steps take 11 s of CPU (20 s on the loaded 2-core VM); the default run of
// cli_test only validates this case (`# test: slow` in it).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

TEST(ExamplePinOnPlate, SlidesAtCoulombAndClosesItsHeatLedger) {
  const auto out = fresh_dir("example07");
  const auto c = std::filesystem::path(TC_SOURCE_DIR) / "examples/07-pin-on-plate/case.toml";
  const auto r = thermocontact(fmt::format("run {} --output {}", c.string(), out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  ASSERT_EQ(h.rows.size(), 122u);  // t = 0 and 121 steps
  const auto n = column(h, "contact_normal_force");
  const auto t = column(h, "contact_tangential_force");
  const auto tsum = column(h, "contact_tangential_force_sum");
  const auto generated = column(h, "heat_generated");
  const auto dissipation = column(h, "frictional_dissipation");
  const auto to_slave = column(h, "heat_to_slave");
  const auto to_master = column(h, "heat_to_master");
  const auto thermal = column(h, "thermal_energy");
  const auto film = column(h, "heat_film");
  const auto radiation = column(h, "heat_radiation");
  const auto tmax = column(h, "max_temperature");
  const auto tmin = column(h, "min_temperature");
  const double friction = 0.3, stroke_per_step = 0.5e-3;
  const double total = generated.back();
  ASSERT_GT(total, 0.0);
  double coulomb_work = 0;
  for (size_t k = 2; k < h.rows.size(); ++k) {
    EXPECT_NEAR(t[k] / n[k], friction, 1e-6) << "step " << k;
    EXPECT_NEAR(tsum[k] / n[k], friction, 1e-6) << "step " << k;
    EXPECT_GT(generated[k], generated[k - 1]) << "step " << k;
    EXPECT_GT(film[k], film[k - 1]) << "step " << k;
    EXPECT_GT(radiation[k], radiation[k - 1]) << "step " << k;
    coulomb_work += friction * n[k] * stroke_per_step;
  }
  for (size_t k = 0; k < h.rows.size(); ++k) {
    EXPECT_NEAR(thermal[k], generated[k] - film[k] - radiation[k], 1e-6 * total) << "step " << k;
    EXPECT_NEAR(to_slave[k], to_master[k], 1e-9 * total) << "step " << k;
    EXPECT_GE(tmin[k], 293.15 - 1e-3) << "step " << k;
  }
  EXPECT_NEAR(dissipation.back(), total, 1e-5 * total);
  EXPECT_LT(total, coulomb_work);
  EXPECT_GT(total, 0.98 * coulomb_work);
  EXPECT_GT(film.back(), 0.01 * total);
  EXPECT_LT(film.back(), 0.2 * total);
  EXPECT_GT(tmax.back(), 293.15 + 5);
  EXPECT_LT(tmax.back(), 293.15 + 30);
}

}  // namespace
}  // namespace tc::test
