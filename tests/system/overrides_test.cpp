// `--set KEY=VALUE` on `run` and `check` (issue 41, "Sweeps"; case-format.md, "Overrides"): the
// value is put into the parsed case before validation, validated like the file, recorded in
// summary.json; an invalid key or value is refused with exit 2 naming the --set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const fs::path sliding = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";

/// Runs the sliding block (friction 0.3 in the file) with `set` and returns its history.
tc::test::History slide(const std::string& set, const std::string& name) {
  const auto out = tc::test::fresh_dir(name);
  const auto r = thermocontact("run " + sliding.string() + " --output " + out.string() + set);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return tc::test::read_history(out / "history.csv");
}

/// T_sum/N over the rows where every active node slips (there Σ‖λ_τ‖ = 𝔉 N by the friction
/// law), sorted.
std::vector<double> sliding_ratios(const tc::test::History& h) {
  const auto n = tc::test::column(h, "contact_normal_force");
  const auto t = tc::test::column(h, "contact_tangential_force_sum");
  const auto active = tc::test::column(h, "active_nodes");
  const auto slip = tc::test::column(h, "slip_nodes");
  std::vector<double> out;
  for (size_t i = 0; i < n.size(); ++i)
    if (active[i] > 0 && slip[i] == active[i] && n[i] > 0) out.push_back(t[i] / n[i]);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Overrides, TheFrictionOfASweepIsTheOneSet) {
  // 𝔉 = 0: no tangential force at all (the Tresca bound is 0, so is λ_τ: exactly); 𝔉 = 0.5 (the
  // file says 0.3): T/N = 0.5 where every active node slips. 1e-6: slip_nodes counts nodes
  // within 1e-6 of the circle, λ_n = γ to the case's coupling tolerance 1e-8; the file's 0.3
  // would be 0.2 off.
  const auto none = slide(" --set contact.friction=0", "set-friction-0");
  for (const double t : tc::test::column(none, "contact_tangential_force")) EXPECT_EQ(t, 0.0);
  for (const double d : tc::test::column(none, "frictional_dissipation")) EXPECT_EQ(d, 0.0);
  double pressed = 0;
  for (const double n : tc::test::column(none, "contact_normal_force"))
    pressed = std::max(pressed, n);
  EXPECT_GT(pressed, 0.0);

  // The median row: 3 of the 40 rows, where the block's contact drops to 4 nodes, have
  // T/N = 0.503–0.507 (the discrete friction law checked after each step is another item of
  // issue 41); the others are within 2e-9 of 0.5.
  const auto half = sliding_ratios(slide(" --set contact.friction=0.5", "set-friction-half"));
  ASSERT_GT(half.size(), 20u);
  EXPECT_NEAR(half[half.size() / 2], 0.5, 1e-6);
  EXPECT_NEAR(half.front(), 0.5, 1e-6);
}

TEST(Overrides, AreRecordedInTheSummaryAndRepeatable) {
  const auto out = tc::test::fresh_dir("set-summary");
  const auto r = thermocontact("run " + sliding.string() + " --output " + out.string() +
                               " --set contact.friction=0.2 --set time.end=1.0e-3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // time.end = 1e-3 with τ = 2e-4: 5 steps instead of the file's 40.
  EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), 6u);
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find(R"("overrides": ["contact.friction=0.2", "time.end=1.0e-3"])"),
            std::string::npos)
      << summary;
}

TEST(Overrides, ArraysOfTablesAreAddressedByIndex) {
  // bodies[1] (or bodies.1) is the second [[bodies]] table, as the messages name it; a bare word
  // is a string. An unknown material there is refused like in the file.
  auto r = thermocontact("check " + sliding.string() + " --set bodies.1.initial_temperature=300");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = thermocontact("check " + sliding.string() + " --set 'bodies[1].material=copper'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--set bodies[1].material=copper: bodies[1].material: found \"copper\""),
            std::string::npos)
      << r.output;
  r = thermocontact("check " + sliding.string() + " --set 'bodies[2].material=\"steel\"'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bodies has 2 entries, so no [2]"), std::string::npos) << r.output;
}

TEST(Overrides, AnUnknownKeyOrABadValueIsRefusedNamingTheSet) {
  for (const auto* cmd : {"check ", "run "}) {
    const auto out = tc::test::fresh_dir("set-refused");
    const std::string tail = std::string(cmd) == "run " ? " --output " + out.string() : "";
    // a misspelt key: unknown, with the keys it could be
    auto r = thermocontact(cmd + sliding.string() + tail + " --set contact.frction=0.5");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--set contact.frction=0.5: contact.frction: found an unknown key"),
              std::string::npos)
        << r.output;
    // a value out of range, and one of the wrong type
    r = thermocontact(cmd + sliding.string() + tail + " --set contact.friction=-1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--set contact.friction=-1: contact.friction: found -1"),
              std::string::npos)
        << r.output;
    r = thermocontact(cmd + sliding.string() + tail + " --set time.step=fast");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--set time.step=fast: time.step: found \"fast\""), std::string::npos)
        << r.output;
    // a table that does not exist: its key is unknown
    r = thermocontact(cmd + sliding.string() + tail + " --set solverr.qp_tolerance=1e-9");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--set solverr.qp_tolerance=1e-9: solverr: found an unknown key"),
              std::string::npos)
        << r.output;
    // no '=', and a path through a number
    r = thermocontact(cmd + sliding.string() + tail + " --set contact.friction");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--set contact.friction: (key): found no '='"), std::string::npos)
        << r.output;
    r = thermocontact(cmd + sliding.string() + tail + " --set contact.friction.x=1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("contact.friction is a number, not a table"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out / "history.csv"));
  }
}

}  // namespace

namespace {

TEST(CaseWarnings, UnitHabitsAreWarnedAboutButRun) {
  // Issue 41, #6: young_modulus = 2.1e5 (MPa) and ambient = 20 (°C) passed without a word. Now a
  // warning naming the key and the habit, from check and run alike; the exit code stays 0.
  const auto dir = tc::test::fresh_dir("habits");
  auto text = tc::test::read_file(sliding);
  text = tc::test::replace_all(text, "young_modulus = 2.0e11", "young_modulus = 2.1e5");
  text = tc::test::replace_all(text, "density = 7850.0", "density = 7.85");
  text = tc::test::replace_all(text, "end = 8.0e-3", "end = 4.0e-4");
  std::ofstream(dir / "case.toml") << text;
  const auto check = thermocontact("check " + (dir / "case.toml").string() +
                                   " --set bodies[1].initial_temperature=20");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  for (const auto* expected :
       {"case.toml:23: materials.steel.young_modulus: found 210000 Pa, below 1e+06 Pa",
        "did you give MPa?", "case.toml:22: materials.steel.density: found 7.85 kg/m³",
        "did you give g/cm³?",
        "warning: --set bodies[1].initial_temperature=20: bodies[1].initial_temperature: found "
        "20 K, below 150 K: did you give °C?"})
    EXPECT_NE(check.output.find(expected), std::string::npos) << expected << "\n" << check.output;
  const auto run =
      thermocontact("run " + (dir / "case.toml").string() + " --output " + (dir / "out").string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("did you give MPa?"), std::string::npos) << run.output;
  // SI values: no warning of a unit habit (the file as it is; its instant start of sliding is
  // warned about by the dynamic scheme's check, io/checks/data_checks.hpp).
  const auto clean = thermocontact("check " + sliding.string());
  const auto count = [&](const std::string& what) {
    size_t n = 0;
    for (auto p = clean.output.find(what); p != std::string::npos;
         p = clean.output.find(what, p + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(count("warning: "), count("jumps in velocity")) << clean.output;
}

TEST(CaseWarnings, AnEndThatIsNotAWholeNumberOfStepsRunsRoundEndOverStep) {
  // case-format.md: the run has round(end/step) steps. end = 1.15e-3 with τ = 2e-4 is 5.75 → 6
  // steps, t = 1.2e-3 s; 1.0e-3 + 1e-5 is 5.05 → 5 steps. It was refused ("not a whole number").
  for (const auto& [end, steps] : {std::pair{"1.15e-3", 6}, {"1.01e-3", 5}}) {
    const auto out = tc::test::fresh_dir("end-rounded");
    const auto r = thermocontact("run " + sliding.string() + " --output " + out.string() +
                                 " --set time.end=" + end);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("not a whole number of steps: the run has round(end/step) = " +
                            std::to_string(steps) + " steps"),
              std::string::npos)
        << r.output;
    const auto h = tc::test::read_history(out / "history.csv");
    ASSERT_EQ(h.rows.size(), static_cast<size_t>(steps + 1));
    EXPECT_NEAR(h.rows.back()[1], steps * 2.0e-4, 1e-15);
  }
  // end < step: at least one step is still required (an error, as before).
  const auto r = thermocontact("check " + sliding.string() + " --set time.end=0.9e-4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("time.end: found end = 9e-05 < step = 0.0002, expected end ≥ step"),
            std::string::npos)
      << r.output;
}

}  // namespace
