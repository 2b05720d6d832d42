// Example 08 (the brake sandwich: a cast-iron disc segment slid between two pads, two contact
// pairs in one dual QP, Gmsh Tet4 meshes, frictional heating, conduction across both
// interfaces, films) run whole as committed, and its physics checked pair by pair against the
// laws its README quotes:
// - Coulomb per pair: in every sliding step (all steps after the pressing one) each pair's
//   resultant tangential force over its normal force, and its Σ_k w_k‖λ_τ,k‖ over it, equal its
//   own 𝔉 (inboard 0.40, outboard 0.35) to 1e-6;
// - the pairs add up to the summed columns (forces, heat);
// - each pair's frictional heat lies within 1.5 % below 𝔉 Σ_k N_k |Δx_k| (the hub's 0.75 mm per
//   step; at each of the 30 stroke reversals the pad's face lags its backing by the shear
//   deflection 2𝔉N/k_t: 0.7 % and 0.6 % measured) and is split δ_C = 0.2 to the pad, 0.8 to
//   the disc;
// - the heat ledger: with thermoelastic heating off and no prescribed temperature, flux or
//   radiation, thermal_energy = heat_generated − heat_film at every step, to 1e-6 of the heat;
// - the films carry heat away (it grows; 0.7 % of the heat in 3 s: the heat is still stored
//   near the interfaces), and the temperature rises by 2 to 30 K without falling more than
//   10 mK below the initial 293.15 K (tetrahedra: no M-matrix; −2.4 mK measured).
// Slow: 121 steps, 19 s on the idle 2-core VM; the default run of cli_test only validates this
// case (`# test: slow` in it).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

TEST(ExampleBrakeSandwich, EachPairSlidesAtItsCoulombLimitAndTheHeatLedgerCloses) {
  const auto out = fresh_dir("example08");
  const auto c = std::filesystem::path(TC_SOURCE_DIR) / "examples/08-brake-sandwich/case.toml";
  const auto r = thermocontact(fmt::format("run {} --output {}", c.string(), out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  ASSERT_EQ(h.rows.size(), 122u);  // t = 0 and 121 steps
  const auto generated = column(h, "heat_generated");
  const auto thermal = column(h, "thermal_energy");
  const auto film = column(h, "heat_film");
  const auto radiation = column(h, "heat_radiation");
  const auto normal = column(h, "contact_normal_force");
  const auto tmax = column(h, "max_temperature");
  const auto tmin = column(h, "min_temperature");
  const double total = generated.back();
  ASSERT_GT(total, 0.0);
  const double stroke_per_step = 0.75e-3, delta_c = 0.2;

  struct Pair {
    std::string name;
    double friction;
  };
  std::vector<double> sum_n(h.rows.size(), 0.0), sum_heat(h.rows.size(), 0.0);
  for (const Pair& p : {Pair{"inboard", 0.40}, Pair{"outboard", 0.35}}) {
    SCOPED_TRACE(p.name);
    const auto n = column(h, "contact_normal_force_" + p.name);
    const auto t = column(h, "contact_tangential_force_" + p.name);
    const auto tsum = column(h, "contact_tangential_force_sum_" + p.name);
    const auto heat = column(h, "heat_generated_" + p.name);
    const auto dissipation = column(h, "frictional_dissipation_" + p.name);
    const auto to_slave = column(h, "heat_to_slave_" + p.name);
    double coulomb_work = 0;
    for (size_t k = 2; k < h.rows.size(); ++k) {
      EXPECT_NEAR(t[k] / n[k], p.friction, 1e-6) << "step " << k;
      EXPECT_NEAR(tsum[k] / n[k], p.friction, 1e-6) << "step " << k;
      EXPECT_GT(heat[k], heat[k - 1]) << "step " << k;
      coulomb_work += p.friction * n[k] * stroke_per_step;
    }
    for (size_t k = 0; k < h.rows.size(); ++k) {
      EXPECT_NEAR(to_slave[k], delta_c * heat[k], 1e-9 * total) << "step " << k;
      sum_n[k] += n[k];
      sum_heat[k] += heat[k];
    }
    EXPECT_NEAR(dissipation.back(), heat.back(), 1e-5 * heat.back());
    EXPECT_LT(heat.back(), coulomb_work);
    EXPECT_GT(heat.back(), 0.985 * coulomb_work);
  }
  for (size_t k = 0; k < h.rows.size(); ++k) {
    EXPECT_NEAR(sum_n[k], normal[k], 1e-9 * normal.back()) << "step " << k;
    EXPECT_NEAR(sum_heat[k], generated[k], 1e-9 * total) << "step " << k;
    EXPECT_EQ(radiation[k], 0.0) << "step " << k;
    EXPECT_NEAR(thermal[k], generated[k] - film[k], 1e-6 * total) << "step " << k;
    EXPECT_GE(tmin[k], 293.15 - 1e-2) << "step " << k;
    if (k >= 2) {
      EXPECT_GT(film[k], film[k - 1]) << "step " << k;
    }
  }
  EXPECT_GT(film.back(), 0.003 * total);
  EXPECT_LT(film.back(), 0.05 * total);
  EXPECT_GT(tmax.back(), 293.15 + 2);
  EXPECT_LT(tmax.back(), 293.15 + 30);
}

}  // namespace
}  // namespace tc::test
