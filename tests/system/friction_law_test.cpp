// Issue 41, points 2–4: the onset of sliding of a lightly held pin (the QP used to stagnate),
// the contact laws checked after every step (summary.json "contact_laws"), and the step
// cut-back ([solver] max_cutbacks) with its restart.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const fs::path source = TC_SOURCE_DIR;

/// The case `name` under tests/cases with `edit` applied, written into a fresh directory
/// (the meshes of examples/ by absolute path).
fs::path case_copy(const fs::path& from, const std::string& dir,
                   const std::vector<std::pair<std::string, std::string>>& edits) {
  auto text = tc::test::read_file(from);
  text = tc::test::replace_all(text, "../../../examples", (source / "examples").string());
  for (const auto& [a, b] : edits) {
    EXPECT_NE(text.find(a), std::string::npos) << a;
    text = tc::test::replace_all(text, a, b);
  }
  const auto d = tc::test::fresh_dir(dir);
  std::ofstream(d / "case.toml") << text;
  return d / "case.toml";
}

/// The number after `"key": ` in a summary.json (the first occurrence after `after`).
double summary_number(const std::string& summary, const std::string& key,
                      const std::string& after = "") {
  const auto from = after.empty() ? 0 : summary.find("\"" + after + "\"");
  const auto at = summary.find("\"" + key + "\": ", from == std::string::npos ? 0 : from);
  EXPECT_NE(at, std::string::npos) << key << " in " << summary;
  if (at == std::string::npos) return std::nan("");
  return std::stod(summary.substr(at + key.size() + 4));
}

size_t col_of(const tc::test::History& h, const std::string& name) {
  for (size_t c = 0; c < h.columns.size(); ++c)
    if (h.columns[c] == name) return c;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

const fs::path pin = source / "tests/cases/friction-law/pin-dead-load.toml";
const fs::path sliding = source / "tests/cases/restart/sliding-2d.toml";

TEST(FrictionLaw, ADeadLoadedPinStartsToSlide) {
  // Before issue 41: "the contact QP (6.9) did not converge: not converged in 2000 iterations"
  // at step 3, the first sliding step, and the run stopped. The pin's top is held in x and y
  // only, so its tilt about the top is held by its inertia and the contact alone: F has
  // near-rigid directions whose compliance grows as τ²/(4m), and MPGP stagnates at τ = 1 ms
  // at the step the pin lands on its edge (3 active nodes). Halving τ conditions F: the step
  // is cut back (to τ/16) and the run reaches its end.
  const auto c = case_copy(pin, "fl-pin", {});
  const auto out = c.parent_path() / "out";
  const auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_EQ(h.rows.size(), 4u);
  const auto summary = tc::test::read_file(out / "summary.json");
  // The laws held within the bounds the solvers guarantee (ratio ≤ 1), and were checked at a
  // node (a node index ≥ 0 names where the worst was).
  EXPECT_LE(summary_number(summary, "ratio", "penetration"), 1.0) << summary;
  EXPECT_LE(summary_number(summary, "ratio", "cone"), 1.0) << summary;
  EXPECT_GE(summary_number(summary, "node", "penetration"), 0.0) << summary;
  // The pin slides at step 3: friction force and heat appear.
  EXPECT_GT(h.rows[3][col_of(h, "contact_tangential_force")], 0.0);
  EXPECT_GT(h.rows[3][col_of(h, "heat_generated")], 0.0);
  // Every node within its cone ‖λ_τ‖ ≤ 𝔉λ_n with λ_n ≥ 0 bounds the resultant: T ≤ 𝔉N
  // (with the former release floor λ_n ≥ −λ_n^k, step 2 wrote T/N = 38.9 here: N = 2.5 N,
  // the sum of pushes and pulls). 1e-6 relative: the fixed point's coupling tolerance, the
  // cone's bound (docs/choices.md).
  const auto n = col_of(h, "contact_normal_force"), t = col_of(h, "contact_tangential_force");
  for (size_t i = 1; i < h.rows.size(); ++i)
    EXPECT_LE(h.rows[i][t], 0.4 * h.rows[i][n] * (1 + 1e-6)) << "row " << i;
}

TEST(FrictionLaw, ALooseQpToleranceKeepsTheLawsWithinItsBound) {
  // qp_tolerance = 1e-2: the bound on the penetration grows with it (ε_QP/σ_n), the friction
  // cone stays exact (the QP's projection): the summary reports both, no row is silent.
  const auto c =
      case_copy(pin, "fl-loose",
                {{"[output]", "[solver]\nqp_tolerance = 1e-2\nqp_forcing_cap = 1e-2\n\n[output]"}});
  const auto out = c.parent_path() / "out";
  const auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_LE(summary_number(summary, "ratio", "penetration"), 1.0) << summary;
  EXPECT_LE(summary_number(summary, "ratio", "cone"), 1.0) << summary;
  EXPECT_GT(summary_number(summary, "value", "penetration"), 0.0) << summary;
}

/// The thesis' rate in the thermoelastic term and the coupling loop to 7e-9, with which
/// sliding-2d needs 7 coupling iterations at step 6 and at most 6 elsewhere (the default, the
/// step's mean rate, needs 4–5 everywhere): with 6 allowed, step 6 fails at τ and is cut back;
/// before issue 41 the run stopped there. 39 steps: after the cut, step 40 would need 7 too.
const std::string kNewmarkRate = "thermoelastic_heating = true\nthermoelastic_rate = \"newmark\"";
constexpr size_t kCutStep = 6;
fs::path needs_a_cut_back(const std::string& dir) {
  return case_copy(sliding, dir,
                   {{"max_coupling_iterations = 50", "max_coupling_iterations = 6"},
                    {"coupling_tolerance = 1e-8", "coupling_tolerance = 7e-9"},
                    {"end = 8.0e-3", "end = 7.8e-3"},
                    {"thermoelastic_heating = true", kNewmarkRate}});
}

TEST(FrictionLaw, AStepThatFailsIsCutBackThereOnly) {
  const auto c = needs_a_cut_back("fl-cut");
  const auto out = c.parent_path() / "out";
  auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_EQ(summary_number(summary, "cut_back_steps"), 1.0) << summary;
  EXPECT_DOUBLE_EQ(summary_number(summary, "smallest_step"), 1e-4) << summary;
  // The uninterrupted run with 50 iterations allowed: the same arithmetic up to the step before.
  const auto full = tc::test::fresh_dir("fl-cut-full");
  r = thermocontact("run " + sliding.string() + " --output " + full.string() +
                    " --set physics.thermoelastic_rate=\\\"newmark\\\" --set "
                    "solver.coupling_tolerance=7e-9 --set time.end=7.8e-3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto a = tc::test::read_history(out / "history.csv");
  const auto b = tc::test::read_history(full / "history.csv");
  ASSERT_EQ(a.rows.size(), 40u);
  ASSERT_EQ(b.rows.size(), 40u);
  const auto wall = col_of(a, "wall_seconds");
  for (size_t i = 0; i < kCutStep; ++i)
    for (size_t col = 0; col < a.columns.size(); ++col)
      if (col != wall) {
        EXPECT_EQ(a.rows[i][col], b.rows[i][col]) << a.columns[col] << " row " << i;
      }
  // One row per step of τ, at the times of τ; the cut step's counts are those of its two halves
  // (each within the 6 allowed).
  const auto time = col_of(a, "time"), coupling = col_of(a, "coupling_iterations");
  for (size_t i = 0; i < a.rows.size(); ++i)
    EXPECT_EQ(a.rows[i][time], static_cast<double>(i) * 2e-4);
  EXPECT_GE(a.rows[kCutStep][coupling], 2.0);
  EXPECT_LE(a.rows[kCutStep][coupling], 12.0);
  // After it the run returns to τ: no more cut-backs (cut_back_steps = 1) and ≤ 6 per step.
  for (size_t i = kCutStep + 1; i < a.rows.size(); ++i) EXPECT_LE(a.rows[i][coupling], 6.0);
  // The cumulative heat is an integral over the run that converges with τ: one step taken as
  // two halves moves it by O(τ) of the dynamic contact's oscillation, measured 0.2 %.
  const auto heat = col_of(a, "heat_generated");
  EXPECT_NEAR(a.rows[39][heat], b.rows[39][heat], 1e-2 * b.rows[39][heat]);
}

TEST(FrictionLaw, ARestartAcrossACutBackIsBitForBit) {
  const auto c = needs_a_cut_back("fl-restart");
  const auto full = c.parent_path() / "full";
  auto r = thermocontact("run " + c.string() + " --output " + full.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto a = tc::test::read_history(full / "history.csv");
  for (const int k : {5, 9}) {  // a checkpoint before the cut-back step, and one after it
    const auto split = c.parent_path() / ("split" + std::to_string(k));
    r = thermocontact("run " + c.string() + " --output " + split.string() + " --stop-after " +
                      std::to_string(k));
    ASSERT_EQ(r.exit_code, 1) << r.output;
    r = thermocontact("run " + c.string() + " --restart " + split.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto b = tc::test::read_history(split / "history.csv");
    ASSERT_EQ(a.rows.size(), b.rows.size());
    // 0: the restart restores the bits of the step's start, and a cut-back starts from them.
    EXPECT_EQ(tc::test::max_relative_difference(a, b, {"wall_seconds"}), 0.0) << k;
  }
}

/// T/N of every row with N > 0 over 𝔉: at most 1 + `slack`, or the first row beyond.
void expect_cone_in_every_row(const fs::path& out, double friction, double slack) {
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  ASSERT_GT(h.rows.size(), 1u);
  const auto n = col_of(h, "contact_normal_force"), t = col_of(h, "contact_tangential_force");
  bool sliding = false;
  for (size_t i = 1; i < h.rows.size(); ++i) {
    if (!(h.rows[i][n] > 0)) continue;
    EXPECT_LE(h.rows[i][t], friction * h.rows[i][n] * (1 + slack)) << out << " row " << i;
    sliding = sliding || h.rows[i][t] > 0.99 * friction * h.rows[i][n];
  }
  EXPECT_TRUE(sliding) << out;  // the case does reach the cone
}

TEST(FrictionLaw, LooseTolerancesNeverWriteARowAboveTheCone) {
  // qp_tolerance = coupling_tolerance = 1e-2 on sliding cases with λ_n ≥ 0 at every node
  // (every scheme since the release floor went; the dynamic runs here use plain Newmark): the
  // fixed point then leaves nodes with ‖λ_τ‖ up to 𝔉·1e-2‖λ‖ above 𝔉λ_n, and history.csv
  // had T/N = 0.3034 (load-control-2d), 0.3015 (sliding-2d, quasistatic), 0.3027 (sliding-2d,
  // dynamic) with 𝔉 = 0.3 and 0.4003 (pin-dead-load, 𝔉 = 0.4). The tangential multipliers
  // are scaled into the cone of max(λ_n, 0) before the row: T = ‖Σ w λ_τ‖ ≤ Σ w ‖λ_τ‖ ≤
  // 𝔉 Σ w λ_n = 𝔉N, to the round-off of the sums (1e-12 of them; measured ≤ 6e-17 over 𝔉).
  const std::string loose = " --set solver.qp_tolerance=1e-2 --set solver.coupling_tolerance=1e-2";
  const std::string quasistatic = " --set time.scheme=quasistatic";
  const std::string plain = " --set time.contact_scheme=plain";
  const struct {
    fs::path c;
    std::string set, name;
    double friction;
  } runs[] = {{source / "tests/cases/restart/load-control-2d.toml", quasistatic, "lc", 0.3},
              {sliding, quasistatic, "sq", 0.3},
              {sliding, plain, "sd", 0.3},
              {pin, plain, "pd", 0.4}};
  for (const auto& run : runs) {
    const auto& c = run.c;
    const auto out = tc::test::fresh_dir("fl-loose-" + run.name);
    const auto r =
        thermocontact("run " + c.string() + " --output " + out.string() + loose + run.set);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_cone_in_every_row(out, run.friction, 1e-12);
    const auto summary = tc::test::read_file(out / "summary.json");
    EXPECT_LE(summary_number(summary, "ratio", "cone"), 1.0) << summary;
    if (run.name != "lc") continue;
    // u moved with the scaled multipliers: the upper block's equilibrium still passes its
    // top's force and its support's drag to the contact's resultant, to the solves' round-off
    // (1e-9 of the 1e6 N/m load, as in load_control_cli_test; measured 6e-12).
    const auto h = tc::test::read_history(out / "history.csv");
    const auto fy = col_of(h, "contact_force_y"), load = col_of(h, "force_upper_ymax_y");
    const auto fx = col_of(h, "contact_force_x"), drag = col_of(h, "reaction_upper_ymax_x");
    for (size_t i = 1; i < h.rows.size(); ++i) {
      EXPECT_NEAR(h.rows[i][fy], h.rows[i][load], 1e-9 * 1e6) << "row " << i;
      EXPECT_NEAR(h.rows[i][fx], h.rows[i][drag], 1e-9 * 1e6) << "row " << i;
    }
  }
}

TEST(FrictionLaw, TheFetiBodysPenetrationIsWithinItsBound) {
  // tests/cases/valid/two-blocks-3d: the slave is cut into 2 FETI subdomains, whose solves
  // leave u off the glued, supported body by their misfit ‖B u − c‖ (≤ feti_tolerance ‖P d‖):
  // the penetration was 4.4–9.2 × the QP's bound (2e-10 m at step 19), a penetration the QP
  // never saw (qp_tolerance 1e-10 left it at 1.99e-10 m; feti_tolerance 1e-12 took it to
  // 0.23 of the bound). With 10 × the misfit in the bound it holds, and no step is cut back.
  const auto out = tc::test::fresh_dir("fl-feti-gap");
  const auto r = thermocontact("run " + (source / "tests/cases/valid/two-blocks-3d.toml").string() +
                               " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_LE(summary_number(summary, "ratio", "penetration"), 1.0) << summary;
  EXPECT_GT(summary_number(summary, "value", "penetration"), 0.0) << summary;
  EXPECT_EQ(summary_number(summary, "cut_back_steps"), 0.0) << summary;
}

}  // namespace
