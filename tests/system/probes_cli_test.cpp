// Probes and the contact CSV through the command line (case-format.md, `[[probe]]`,
// `output.contact_csv`):
// - a probe in a slab heated through one face reproduces the series solution of transient 1D
//   conduction, with backward Euler's factor per mode, within the spatial error stated;
// - probes.csv survives a stop and a restart bit for bit;
// - `check` reports a probe outside its body, and both or neither of point and where;
// - contact_<step>.csv lists every contact node with the .vtu's pressure.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

// A slab 0 < x < L (2D strip L × L/10, 50 × 1 cells), θ₀ at t = 0, a flux q into its face x = 0,
// every other face insulated, no thermal expansion: θ depends on x and t only,
//   θ = θ₀ + (qL/κ)[a t/L² + 1/3 − x/L + x²/(2L²) − (2/π²) Σ_n cos(nπx/L) e^{−λ_n t}/n²],
// λ_n = a(nπ/L)², a = κ/(ρc). Backward Euler integrates the part linear in t exactly, and
// linear elements hold the quadratic steady profile exactly at the nodes (1D, a constant
// source), so the time discretisation error is the modes': step k gives (1 + λ_nτ)^{−k}
// instead of e^{−λ_n kτ}, which the expected value below uses.
constexpr double kL = 0.05, kKappa = 50.0, kRhoC = 5.0e6, kQ = 1.0e5, kTheta0 = 300.0;
constexpr double kTau = 0.5;
constexpr int kSteps = 100;

double expected(double x, int k) {
  const double a = kKappa / kRhoC, t = k * kTau, scale = kQ * kL / kKappa;
  double modes = 0;
  for (int n = 1; n <= 2000; ++n) {
    const double lambda = a * std::pow(n * std::numbers::pi / kL, 2);
    modes += std::cos(n * std::numbers::pi * x / kL) * std::pow(1 + lambda * kTau, -k) / (n * n);
  }
  return kTheta0 + scale * (a * t / (kL * kL) + 1.0 / 3 - x / kL + x * x / (2 * kL * kL) -
                            2 / (std::numbers::pi * std::numbers::pi) * modes);
}

fs::path write_slab(const fs::path& dir, const std::string& extra = "") {
  const auto file = dir / "slab.toml";
  std::ofstream(file) << fmt::format(R"(dimension = 2
[time]
scheme = "quasistatic"
step = {}
end = {}
[physics]
reference_temperature = {}
thermal_expansion = false
thermoelastic_heating = false
[materials.m]
density = 1000.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 0.0
specific_heat = {}
thermal_conductivity = {}
[[bodies]]
name = "slab"
material = "m"
mesh = {{ box = {{ min = [0.0, 0.0], max = [{}, {}], cells = [50, 1] }} }}
[[boundary]]
body = "slab"
where = "xmin"
displacement = [0.0, 0.0]
heat_flux = {}
[output]
every = 1000
[[probe]]
name = "mid_cell"
body = "slab"
point = [0.0155, 0.002]
[[probe]]
name = "node"
body = "slab"
point = [0.03, 0.0]
[[probe]]
name = "face"
body = "slab"
where = "xmax"
{})",
                                     kTau, kTau * kSteps, kTheta0, kRhoC / 1000.0, kKappa, kL,
                                     kL / 10, kQ, extra);
  return file;
}

TEST(ProbesCli, AProbeFollowsTheSeriesSolutionOfTransientConduction) {
  const auto dir = tc::test::fresh_dir("probes-slab");
  const auto out = dir / "out";
  const auto r = thermocontact("run " + write_slab(dir).string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto probes = tc::test::read_history(out / "probes.csv");
  ASSERT_EQ(probes.rows.size(), static_cast<size_t>(kSteps + 1));
  const std::vector<std::string> columns{"step",
                                         "time",
                                         "mid_cell_temperature",
                                         "mid_cell_displacement_x",
                                         "mid_cell_displacement_y",
                                         "mid_cell_velocity_x",
                                         "mid_cell_velocity_y",
                                         "node_temperature"};
  for (size_t c = 0; c < columns.size(); ++c) EXPECT_EQ(probes.columns[c], columns[c]);
  // The error left is spatial: the modes' eigenvalues (relative error (πh/L)²n²/12 for linear
  // elements, h = L/50) and the interpolation of a mid-cell point (θ''h²/8 = q h²/(8κL) =
  // 0.001 K). The first mode's share is (2/π²)(qL/κ) × λ₁t e^{−λ₁t} (πh/L)²/12 ≤ 0.003 K;
  // the higher modes' shares fall as 1/n² but their relative errors grow as n² while they
  // decay: 0.02 K of 100 K (qL/κ) bounds the sum from the second step on (at step 1 the
  // unresolved modes above n ≈ 50 still hold ~0.1 K: not compared).
  double worst = 0;
  for (int k = 2; k <= kSteps; ++k) {
    const auto& row = probes.rows[static_cast<size_t>(k)];
    EXPECT_EQ(row[0], k);
    const double mid = expected(0.0155, k), node = expected(0.03, k), face = expected(kL, k);
    EXPECT_NEAR(row[2], mid, 0.02) << "step " << k;
    EXPECT_NEAR(row[7], node, 0.02) << "step " << k;
    EXPECT_NEAR(row[12], face, 0.02) << "step " << k;  // the mean of the face's two nodes
    worst = std::max(
        {worst, std::abs(row[2] - mid), std::abs(row[7] - node), std::abs(row[12] - face)});
    EXPECT_EQ(row[3], 0.0);  // no expansion: the slab does not move
  }
  // The comparison can fail: the mean heating over the run is 20 K (a t/L² · qL/κ, t = 50 s).
  EXPECT_GT(probes.rows.back()[2] - kTheta0, 15.0);
  RecordProperty("worst_error_K", std::to_string(worst));
}

TEST(ProbesCli, ProbesSurviveARestartBitForBit) {
  const auto dir = tc::test::fresh_dir("probes-restart");
  const auto c = write_slab(dir);
  const auto full = dir / "full", split = dir / "split";
  auto r = thermocontact("run " + c.string() + " --output " + full.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = thermocontact("run " + c.string() + " --output " + split.string() + " --stop-after 37");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(tc::test::read_history(split / "probes.csv").rows.size(), 38u);
  r = thermocontact("run " + c.string() + " --restart " + split.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Printed with 17 significant digits: equal text is equal bits.
  EXPECT_EQ(tc::test::read_file(split / "probes.csv"), tc::test::read_file(full / "probes.csv"));
}

TEST(ProbesCli, CheckReportsProbesItCannotPlace) {
  const auto dir = tc::test::fresh_dir("probes-check");
  const auto c = write_slab(dir, R"([[probe]]
name = "outside"
body = "slab"
point = [0.06, 0.001]
[[probe]]
name = "both"
body = "slab"
point = [0.01, 0.001]
where = "xmin"
[[probe]]
name = "node"
body = "slab"
where = "nowhere"
)");
  const auto r = thermocontact("check " + c.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* m : {"probe[3].point: found [0.06, 0.001], expected a point of body \"slab\"",
                        "probe[4]: found both point and where",
                        "probe[5].name: found \"node\" again", "probe[5].where"})
    EXPECT_NE(r.output.find(m), std::string::npos) << m << "\n" << r.output;
}

TEST(ProbesCli, ContactCsvListsTheContactNodes) {
  const auto dir = tc::test::fresh_dir("contact-csv");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + dir.string() +
                               " --set output.contact_csv=true --set output.every=20");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto csv = tc::test::read_history(dir / "contact_000040.csv");
  ASSERT_FALSE(csv.rows.empty());
  EXPECT_EQ(csv.columns.front(), "pair");
  EXPECT_EQ(csv.columns.back(), "master_temperature");
  EXPECT_TRUE(fs::exists(dir / "contact_000000.csv"));
  EXPECT_TRUE(fs::exists(dir / "contact_000020.csv"));
  // Where the contact presses, the node is on the master's surface (the gap is closed to the
  // QP's accuracy, far below the 1e-5 m of the upper block's push); the slave's temperature
  // lies within the step's extremes in history.csv (an independent reduction over all nodes);
  // and the conducted flux is β_C p (θ_s − θ_m) with the columns' own p, θ_s and θ_m,
  // β_C = γ_sγ_m/(γ_s + γ_m) = 1e-3·2e-3/3e-3, to the coupling tolerance (1e-8) of the
  // iterate the flux was taken from: 1e-6 relative.
  const auto history = tc::test::read_history(dir / "history.csv");
  const auto column = [&](const std::string& name) {
    const auto at = std::find(history.columns.begin(), history.columns.end(), name);
    EXPECT_NE(at, history.columns.end()) << name;
    return history.rows.back()[static_cast<size_t>(at - history.columns.begin())];
  };
  const double hottest = column("max_temperature"), coldest = column("min_temperature");
  const double beta = 1e-3 * 2e-3 / 3e-3;
  int pressed = 0;
  for (const auto& row : csv.rows) {
    if (row[6] <= 0) continue;
    ++pressed;
    EXPECT_LT(std::abs(row[5]), 1e-7);
    EXPECT_GE(row[14], coldest);
    EXPECT_LE(row[14], hottest);
    const double conducted = beta * row[6] * (row[14] - row[15]);
    EXPECT_NEAR(row[13], conducted, 1e-6 * std::abs(conducted) + 1e-9) << "node " << row[1];
  }
  EXPECT_GT(pressed, 0);
}

}  // namespace
