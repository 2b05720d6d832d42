// Load control from the command line (`[[boundary]] force`, docs/case-format.md): a case with
// a force runs and its history holds the load; a run stopped and restarted leaves the history
// of the uninterrupted run bit for bit (the face's w is taken from the checkpointed u at each
// step, and no other state of the balance outlives a step); cases load control cannot run are
// refused by `check` with exit 2 (tests/cases/invalid/force-*.toml name the messages).
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

const fs::path kCase = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/load-control-2d.toml";

TEST(LoadControlCli, TheForceIsHeldAndARestartIsBitForBit) {
  const auto full = fresh_dir("load-control-full");
  const auto split = fresh_dir("load-control-split");
  auto r = thermocontact("run " + kCase.string() + " --output " + full.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto a = read_history(full / "history.csv");
  ASSERT_TRUE(a.whole);
  const auto load = column(a, "force_upper_ymax_y");
  const auto n = column(a, "contact_normal_force");
  const auto w = column(a, "displacement_upper_ymax_y");
  // Row 0 is the state at t = 0 (the warm block's thermal force, nothing balanced yet); each
  // step holds the load, −1e6 N/m, to 10 qp_tolerance = 1e-7 of it; 1e-6 leaves a margin.
  for (size_t k = 1; k < a.rows.size(); ++k) {
    EXPECT_NEAR(load[k], -1e6, 1e-6 * 1e6) << "step " << k;
    // Held along y by the contact alone: the contact force is the load, up to the friction's
    // share along the rows' normals, tilted by the bodies' strain (σ/E ~ 1e-4) and the warm
    // block's expansion (α ΔT ~ 1e-3): 𝔉 · 1e-3 = 3e-4 bounds it.
    EXPECT_NEAR(n[k], 1e6, 3e-4 * 1e6) << "step " << k;
    EXPECT_LT(std::abs(w[k]), 1e-3) << "step " << k;
  }
  r = thermocontact("run " + kCase.string() + " --output " + split.string() + " --stop-after 4");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  r = thermocontact("run " + kCase.string() + " --restart " + split.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto b = read_history(split / "history.csv");
  ASSERT_TRUE(b.whole);
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  // Bit for bit, the wall clock aside.
  EXPECT_EQ(max_relative_difference(a, b, {"wall_seconds"}), 0.0);
}

TEST(LoadControlCli, TheContactForceOnTheSlaveIsTheLoadAlongIt) {
  // The upper block (the master) is held along y by its top's force and the contact alone, so
  // the contact's resultant on the lower block (the slave), −Σ_d (B_sᵀλ)_d over its y dofs,
  // is the load at every step, friction on; contact_normal_force is not (tilted normals).
  const auto out = fresh_dir("load-control-force");
  const auto r = thermocontact("run " + kCase.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  const auto load = column(h, "force_upper_ymax_y");
  const auto fy = column(h, "contact_force_y");
  const auto fx = column(h, "contact_force_x");
  const auto drag = column(h, "reaction_upper_ymax_x");
  ASSERT_EQ(fy.size(), h.rows.size());
  ASSERT_EQ(drag.size(), h.rows.size());
  EXPECT_TRUE(column(h, "contact_force_z").empty());  // 2D: x and y only
  for (size_t k = 1; k < h.rows.size(); ++k) {
    // The coupling holds the face's force to 10 qp_tolerance = 1e-7 of the load; 1e-6 leaves
    // a margin (as the test above).
    EXPECT_NEAR(fy[k], -1e6, 1e-6 * 1e6) << "step " << k;
    // The upper block's equilibrium passes the face's force to the contact exactly, and the
    // mortar's master integrals sum to the slave's weights where the master covers the
    // slave's active nodes: equal to the round-off of the solves (ε κ(K) ~ 1e-16 × 1e7;
    // measured 1.4e-12 of the load).
    EXPECT_NEAR(fy[k], load[k], 1e-9 * 1e6) << "step " << k;
    // Along x the support drags the upper block: its reaction balances the friction, which
    // the contact passes to the slave (measured 2e-11 of the load apart).
    EXPECT_NEAR(fx[k], drag[k], 1e-9 * 1e6) << "step " << k;
  }
  // The friction is on and carries 𝔉 = 0.3 of the load once the block slides.
  EXPECT_NEAR(std::abs(fx.back()), 0.3e6, 1e-3 * 0.3e6);
}

TEST(LoadControlCli, AForceOnAFetiBodyIsRefusedByCheck) {
  const auto r = thermocontact(
      "check " +
      (fs::path(TC_SOURCE_DIR) / "tests/cases/invalid/force-on-feti-body.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("boundary[1].force: found a force on body \"b\", which is cut into 2 "
                          "subdomains"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace tc::test
