// Example 09 (a pin-on-disc tribometer under load control: a 200 N resultant force on the pin's
// top through a rigid coupling, Gmsh Tet4 meshes, 𝔉 = 0.4, frictional heating, conduction
// across the contact, films) run whole as committed, and checked against what its README
// states:
// - the load: the pin's top carries the 200 N at every step (force_pin_top_z = −200 N, ramped
//   in over the first 4 ms) to 1e-6, and since the pin is held along z by the contact alone,
//   the contact force's resultant along z is that load; the normal force Σ w_k λ_n,k (along
//   the normals of the rows, in the configuration of t^k) differs from it by the friction's
//   share along z, 𝔉 × the tilt of the rows' normals: the pin's face bends under 𝔉N and the
//   track bulges round the hot spot, by up to α(θ_max − θ₀) ≈ 1.15e-5 × 400 K ≈ 4.6e-3 rad
//   (measured: 3.0e-5 of the load, README); contact_force_z, the resultant of the contact on
//   the pin in space (−Σ B_sᵀλ over its z dofs), is the load to 1e-6;
// - the heat: heat_generated = 𝔉 N × the 0.2 m of slide within 0.5 % (the slip differs from the
//   holder's travel by the pin's elastic lag, µm), split ½ / ½ (δ_C = ½), and the heat ledger
//   thermal_energy = heat_generated − heat_film at every step, to 1e-6 of the heat generated;
// - the top's z displacement is one unknown: the column equals the node values (in the .vtu not
//   read here; the verification test load_control_test checks it node by node).
// Slow: 204 steps, 7.6 s of CPU (minutes of wall time on the VM when it is shared); cli_test only
// validates the case.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

TEST(ExamplePinOnDisc, HoldsTheLoadAndHeatsByCoulomb) {
  const auto out = fresh_dir("example09");
  const auto c = std::filesystem::path(TC_SOURCE_DIR) / "examples/09-pin-on-disc/case.toml";
  const auto r = thermocontact(fmt::format("run {} --output {}", c.string(), out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  ASSERT_EQ(h.rows.size(), 205u);  // t = 0 and 204 steps
  const auto n = column(h, "contact_normal_force");
  const auto load = column(h, "force_pin_top_z");
  const auto w = column(h, "displacement_pin_top_z");
  const auto generated = column(h, "heat_generated");
  const auto to_slave = column(h, "heat_to_slave");
  const auto to_master = column(h, "heat_to_master");
  const auto thermal = column(h, "thermal_energy");
  const auto film = column(h, "heat_film");
  const auto tmax = column(h, "max_temperature");
  const auto fz = column(h, "contact_force_z");
  ASSERT_EQ(fz.size(), h.rows.size());
  const auto time = column(h, "time");
  const double friction = 0.4, full = 200.0, slide = 0.2;
  for (size_t k = 1; k < h.rows.size(); ++k) {
    const double force = full * std::min(time[k] / 0.004, 1.0);  // ramped over the first 4 ms
    // The coupling balances the load to 10 × qp_tolerance (1e-7) of it: 1e-6 with a margin.
    EXPECT_NEAR(load[k], -force, 1e-6 * force) << "step " << k;
    // The normals of the rows tilt (bending under 𝔉N, the thermal bulge of the track): the
    // friction then carries up to 𝔉·tilt of the load along z, tilt ≤ α(θ_max − θ₀).
    // And from the second step of the ramp the rows are built on the indented faces, dished
    // by up to the contact's strain p/E = (200 N / π(3 mm)²) / 110 GPa = 6.4e-5 (measured:
    // 7e-6 of the load at step 4, before any sliding).
    const double tilt = 1.15e-5 * (tmax[k] - 293.15) + 6.4e-5;
    EXPECT_NEAR(n[k], force, friction * tilt * force + 1e-6 * force) << "step " << k;
    // The resultant of the contact on the pin, normal and tangential parts in space, is what
    // holds it along z: the load, to the coupling's 1e-7 with the margin above.
    EXPECT_NEAR(fz[k], force, 1e-6 * force) << "step " << k;
    // The top moves by the indentation and the thermal expansion: micrometres.
    EXPECT_LT(std::abs(w[k]), 1e-5) << "step " << k;
  }
  const double total = generated.back();
  EXPECT_NEAR(total, friction * full * slide, 0.005 * friction * full * slide);
  for (size_t k = 0; k < h.rows.size(); ++k) {
    EXPECT_NEAR(thermal[k], generated[k] - film[k], 1e-6 * total) << "step " << k;
    EXPECT_NEAR(to_slave[k], to_master[k], 1e-9 * total) << "step " << k;
  }
}

}  // namespace
}  // namespace tc::test
