// Restart (case-format.md, "Restart"): a run stopped after step k and continued with
// `--restart OUTDIR` leaves the history.csv of an uninterrupted run, and a checkpoint that
// does not belong to the case is refused with exit code 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const fs::path sliding = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";
const fs::path pin = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/pin-on-plate.toml";

/// Every cell of two history.csv files equal to the bit (`wall_seconds` aside): the number of
/// differing cells, and the first of them in the failure message. The files hold each value
/// with 17 significant digits, so equal doubles here are equal bits.
void expect_same_bits(const tc::test::History& a, const tc::test::History& b,
                      const std::string& name) {
  ASSERT_EQ(a.columns, b.columns) << name;
  ASSERT_EQ(a.rows.size(), b.rows.size()) << name;
  int differing = 0;
  std::string first;
  for (size_t r = 0; r < a.rows.size(); ++r)
    for (size_t c = 0; c < a.columns.size(); ++c) {
      if (a.columns[c] == "wall_seconds" || a.rows[r][c] == b.rows[r][c]) continue;
      if (differing++ == 0)
        first = "step " + std::to_string(r) + ", " + a.columns[c] + ": " +
                std::to_string(a.rows[r][c]) + " against " + std::to_string(b.rows[r][c]);
    }
  EXPECT_EQ(differing, 0) << name << ": first at " << first;
}

std::string run_args(const fs::path& c, const fs::path& out) {
  return "run " + c.string() + " --output " + out.string();
}

/// Runs `c` uninterrupted and stopped after `k` then restarted; compares the histories.
void expect_restart_reproduces(const fs::path& c, int k, const std::string& name,
                               const std::string& petsc_options = "", bool bit_for_bit = false) {
  const auto full = tc::test::fresh_dir(name + "-full");
  const auto split = tc::test::fresh_dir(name + "-split");
  auto r = thermocontact(run_args(c, full) + petsc_options);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = thermocontact(run_args(c, split) + " --stop-after " + std::to_string(k) + petsc_options);
  ASSERT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(tc::test::read_file(split / "summary.json").find("\"status\": \"stopped\""),
            std::string::npos);
  const auto stopped = tc::test::read_history(split / "history.csv");
  ASSERT_EQ(stopped.rows.size(), static_cast<size_t>(k + 1));  // t = 0 and k steps
  ASSERT_TRUE(fs::exists(split / "checkpoint.bin"));

  r = thermocontact("run " + c.string() + " --restart " + split.string() + petsc_options);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("restarting from step " + std::to_string(k)), std::string::npos)
      << r.output;
  const auto a = tc::test::read_history(full / "history.csv");
  const auto b = tc::test::read_history(split / "history.csv");
  ASSERT_TRUE(a.whole && b.whole);
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (size_t i = 0; i < b.rows.size(); ++i) EXPECT_EQ(b.rows[i][0], static_cast<double>(i));
  // 1e-12: the bar of round-off. The restart restores the bits of every vector and sum the
  // later steps read, so the arithmetic is the same and the difference is in fact 0; the
  // wall-clock column is the one that differs by nature.
  EXPECT_LE(tc::test::max_relative_difference(a, b, {"wall_seconds"}), 1e-12) << name;
  if (bit_for_bit) expect_same_bits(a, b, name);
  // Every listed data set exists and is whole; those of the uninterrupted run are all there.
  const auto pa = tc::test::read_collection(full / "result.pvd");
  const auto pb = tc::test::read_collection(split / "result.pvd");
  ASSERT_TRUE(pb.whole);
  for (const auto& f : pb.files) EXPECT_TRUE(tc::test::whole_vtu(split / f)) << f;
  for (const auto& f : pa.files)
    EXPECT_NE(std::find(pb.files.begin(), pb.files.end(), f), pb.files.end()) << f;
  const auto summary = tc::test::read_file(split / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"completed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"steps_done\": " + std::to_string(a.rows.size() - 1)), std::string::npos)
      << summary;
}

TEST(Restart, ASlidingHeatedContactContinuesAsIfNeverStopped) {
  // Dynamic, contact-stabilised, friction, frictional heating and conductance (the case's
  // header): stopped at step 17 of 40, between two outputs (every = 3).
  expect_restart_reproduces(sliding, 17, "restart-sliding");
}

TEST(Restart, ThePinOnPlateContinuesBitForBit) {
  // Issue 41, #5: two Gmsh bodies, friction, frictional heating, conduction, films and
  // radiation, quasistatic. Stopped after step 3, the restart's first difference was at step 5
  // (strain_energy, 2e-11 relative; 54 cells): the interface heat solver's compliance, grown by
  // the plate nodes the pin reaches as it slides, was rebuilt in one block of columns instead
  // of the run's blocks. Now in the checkpoint (format 7) and replayed.
  expect_restart_reproduces(pin, 3, "restart-pin", "", true);
}

TEST(Restart, ThePinOnPlateWithTheComplianceByForwardSolvesContinuesBitForBit) {
  // The same with S = YᵀY by forward solves (Y kept, the interface heat solve by halves; the
  // old restart differed from step 4 on, 105 cells).
  expect_restart_reproduces(pin, 3, "restart-pin-forward", " -tc_forward_compliance", true);
}

/// Example 06 (the ch. 7 frictional heating) cut to 60 steps: CHOLMOD's factors of its
/// bodies are supernodal, and the sliding adds 21 master columns to the compliance at step 46.
fs::path short_example06(const std::string& name) {
  const auto dir = tc::test::fresh_dir(name);
  const auto text = tc::test::read_file(fs::path(TC_SOURCE_DIR) /
                                        "examples/06-thesis-frictional-heating/case.toml");
  EXPECT_NE(text.find("\nend = 1.0\n"), std::string::npos);
  std::ofstream(dir / "case.toml") << tc::test::replace_all(text, "\nend = 1.0\n", "\nend = 0.6\n");
  return dir / "case.toml";
}

TEST(Restart, TheComplianceByForwardSolvesReplaysToo) {
  // -tc_forward_compliance takes S = YᵀY (CholeskySolver::forward_compliance) at any size:
  // stopped at step 50, after the later-step columns of step 46, the restart replays the
  // checkpoint's record of the compliance on that path, Y included.
  expect_restart_reproduces(short_example06("forward-case"), 50, "restart-forward",
                            " -tc_forward_compliance");
}

TEST(Restart, TheComplianceByForwardSolvesGivesTheHistoryOfTheRestrictedSolves) {
  // The same S to round-off (core_cholmod_test: 1e-13), other sums: the QP then stops
  // elsewhere inside its tolerance, so the histories agree to about that (1.1e-9 measured),
  // not to the bit, and the iteration counts may differ. Each column is compared at its own
  // largest value, the forces and reactions at the normal force's (the lateral reactions,
  // mN against MN, are round-off of the equilibrium). 1e-6, the example's coupling
  // tolerance, still catches a wrong column of S (an entry off by its own size moves the
  // forces by percents). A difference of exactly 0 would mean the option was not taken.
  const auto c = short_example06("forward-compare");
  const auto a = tc::test::fresh_dir("forward-off"), b = tc::test::fresh_dir("forward-on");
  ASSERT_EQ(thermocontact(run_args(c, a)).exit_code, 0);
  ASSERT_EQ(thermocontact(run_args(c, b) + " -tc_forward_compliance").exit_code, 0);
  const auto ha = tc::test::read_history(a / "history.csv");
  const auto hb = tc::test::read_history(b / "history.csv");
  ASSERT_EQ(ha.columns, hb.columns);
  ASSERT_EQ(ha.rows.size(), hb.rows.size());
  const auto largest = [&](size_t c) {
    double m = 0;
    for (const auto& row : ha.rows) m = std::max(m, std::abs(row[c]));
    return m;
  };
  double force = 0;
  for (size_t c = 0; c < ha.columns.size(); ++c)
    if (ha.columns[c] == "contact_normal_force") force = largest(c);
  ASSERT_GT(force, 0.0);
  double worst = 0, any = 0;
  for (size_t c = 0; c < ha.columns.size(); ++c) {
    const auto& name = ha.columns[c];
    if (name == "wall_seconds" || name == "qp_iterations" || name == "operator_applications" ||
        name == "friction_iterations")
      continue;
    const bool is_force = name.rfind("reaction_", 0) == 0 || name.rfind("contact_", 0) == 0;
    const double scale = std::max(largest(c), is_force ? force : 0.0);
    for (size_t r = 0; r < ha.rows.size(); ++r) {
      const double d = std::abs(ha.rows[r][c] - hb.rows[r][c]);
      any = std::max(any, d);
      if (scale > 0) worst = std::max(worst, d / scale);
    }
  }
  EXPECT_GT(any, 0.0);
  EXPECT_LE(worst, 1e-6);
  std::printf("forward compliance against restricted solves: %.3g\n", worst);
}

TEST(Restart, RunsWithoutContactContinueToo) {
  // Newmark without contact (u̇, ü restored) and the quasistatic scheme (no g).
  expect_restart_reproduces(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/plane-strain-2d.toml", 4,
                            "restart-newmark");
  expect_restart_reproduces(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/quasistatic.toml", 1,
                            "restart-quasistatic");
}

TEST(Restart, FilmAndRadiationLedgerContinues) {
  // heat_film and heat_radiation are cumulative: restored from the checkpoint (format 5).
  expect_restart_reproduces(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/film-radiation.toml", 2,
                            "restart-film-radiation");
}

TEST(Restart, SeveralContactPairsContinueWithTheirOwnLedgers) {
  // Three blocks, two pairs (one with 𝔉(θ)): each pair's warm start and cumulative columns
  // (dissipation, heat) restored from its own record (checkpoint format 6).
  expect_restart_reproduces(
      fs::path(TC_SOURCE_DIR) / "tests/cases/several-pairs/three-blocks-2d.toml", 2,
      "restart-several-pairs");
}

TEST(Restart, InterfaceLawsInTheTemperatureAddNoState) {
  // 𝔉(θ) and γ_C^s(θ) as tables: evaluated from θ at every coupling iterate, nothing of
  // them is in the checkpoint (format unchanged), and the restart still gives the same bits.
  const auto dir = tc::test::fresh_dir("restart-laws");
  auto text = tc::test::read_file(sliding);
  const std::string friction = "friction = 0.3", conductance = "conductance = { slave = 1.0e-3";
  ASSERT_NE(text.find(friction), std::string::npos);
  ASSERT_NE(text.find(conductance), std::string::npos);
  text.replace(text.find(friction), friction.size(),
               "friction = { temperature = [293.15, 330.0, 400.0], value = [0.4, 0.3, 0.15] }");
  text.replace(text.find(conductance), conductance.size(),
               "conductance = { slave = { temperature = [293.15, 400.0], value = [1.0e-3, "
               "3.0e-3] }");
  std::ofstream(dir / "laws.toml") << text;
  expect_restart_reproduces(dir / "laws.toml", 17, "restart-laws-run");
}

TEST(Restart, ACheckpointOfAnotherCaseIsRefusedWithExitTwo) {
  const auto dir = tc::test::fresh_dir("restart-refused");
  const auto out = dir / "out";
  auto r = thermocontact(run_args(sliding, out) + " --stop-after 3");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  const auto before = tc::test::read_file(out / "history.csv");

  // The same case with another time step: the checkpoint belongs to the first file only.
  auto text = tc::test::read_file(sliding);
  text.replace(text.find("step = 2.0e-4"), 13, "step = 1.0e-4");
  std::ofstream(dir / "other.toml") << text;
  r = thermocontact("run " + (dir / "other.toml").string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  // the key that differs is named, with both values
  EXPECT_NE(r.output.find("different case: time.step: 0.00020000000000000001 in the checkpoint's "
                          "run, 0.0001 now"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("checkpoint.bin"), std::string::npos) << r.output;

  // A damaged checkpoint: one byte changed in the middle.
  auto bytes = tc::test::read_file(out / "checkpoint.bin");
  bytes[bytes.size() / 2] ^= 0x5a;
  std::ofstream(dir / "damaged.bin", std::ios::binary) << bytes;
  fs::copy_file(out / "checkpoint.bin", dir / "good.bin");
  fs::copy_file(dir / "damaged.bin", out / "checkpoint.bin", fs::copy_options::overwrite_existing);
  r = thermocontact("run " + sliding.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("damaged"), std::string::npos) << r.output;

  // Cut short.
  fs::resize_file(out / "checkpoint.bin", bytes.size() / 3);
  r = thermocontact("run " + sliding.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;

  // No checkpoint at all.
  fs::remove(out / "checkpoint.bin");
  r = thermocontact("run " + sliding.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no checkpoint"), std::string::npos) << r.output;
  // None of the refusals touched the output of the stopped run.
  EXPECT_EQ(tc::test::read_file(out / "history.csv"), before);

  // --restart and --output together are a usage error.
  r = thermocontact("run " + sliding.string() + " --restart " + out.string() + " --output " +
                    (dir / "x").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST(Restart, ACheckpointOfAChangedMeshFileIsRefusedWithExitTwo) {
  // issue 20, #8: a node of the Gmsh file moved between the stop and the restart; the case file
  // itself unchanged. The restart went on, on the other mesh, with exit 0.
  const auto dir = tc::test::fresh_dir("restart-mesh");
  const auto valid = fs::path(TC_SOURCE_DIR) / "tests/cases/valid";
  fs::copy_file(valid / "gmsh-file.toml", dir / "case.toml");
  fs::copy_file(valid / "square.msh", dir / "square.msh");
  auto text = tc::test::read_file(dir / "case.toml");
  text.replace(text.find("end = 1.0"), 9, "end = 3.0");
  std::ofstream(dir / "case.toml") << text;
  const auto out = dir / "out";
  auto r = thermocontact(run_args(dir / "case.toml", out) + " --stop-after 2");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  auto mesh = tc::test::read_file(dir / "square.msh");
  const std::string corner = "\n1 1 0\n";  // node 3 at (1, 1)
  ASSERT_NE(mesh.find(corner), std::string::npos);
  mesh.replace(mesh.find(corner), corner.size(), "\n1.01 1 0\n");
  std::ofstream(dir / "square.msh") << mesh;
  r = thermocontact("run " + (dir / "case.toml").string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("mesh file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("checkpoint.bin"), std::string::npos) << r.output;
  // Put back, the restart goes on.
  std::ofstream(dir / "square.msh") << tc::test::read_file(valid / "square.msh");
  r = thermocontact("run " + (dir / "case.toml").string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Restart, ACompletedRunRestartsAsCompletedWithItsHistoryUnchanged) {
  const auto out = tc::test::fresh_dir("restart-completed");
  auto r =
      thermocontact(run_args(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/quasistatic.toml", out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto before = tc::test::read_history(out / "history.csv");
  r = thermocontact("run " +
                    (fs::path(TC_SOURCE_DIR) / "tests/cases/valid/quasistatic.toml").string() +
                    " --restart " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto after = tc::test::read_history(out / "history.csv");
  EXPECT_EQ(after.rows, before.rows);
}

}  // namespace

namespace {

/// The sliding case with `end` set to `end` (the file's is 8.0e-3: 40 steps of 2e-4 s).
fs::path sliding_until(const fs::path& dir, const std::string& end, const std::string& extra = "") {
  auto text = tc::test::read_file(sliding);
  const std::string from = "end = 8.0e-3";
  EXPECT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "end = " + end);
  std::ofstream(dir / "case.toml") << text << extra;
  return dir / "case.toml";
}

TEST(Restart, AnExtendedRestartEqualsTheLongerRunBitForBit) {
  // Issue 41, #5: a run of 20 steps, completed, then restarted with end twice as large (and
  // another output interval, and a comment): its 40 rows equal those of the 40-step run bit for
  // bit. The old restart refused the changed file ("different case file").
  const auto dir = tc::test::fresh_dir("restart-extend");
  const auto longer = sliding_until(dir, "8.0e-3");
  const auto full = dir / "full";
  ASSERT_EQ(thermocontact(run_args(longer, full)).exit_code, 0);
  fs::create_directories(dir / "short");
  const auto shorter = sliding_until(dir / "short", "4.0e-3");
  const auto out = dir / "out";
  auto r = thermocontact(run_args(shorter, out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(tc::test::read_history(out / "history.csv").rows.size(), 21u);
  fs::create_directories(dir / "extended");
  auto text = tc::test::read_file(longer);
  text = tc::test::replace_all(text, "every = 3", "every = 5   # fewer fields from here on");
  std::ofstream(dir / "extended" / "case.toml") << "# extended to 8 ms\n" << text;
  r = thermocontact("run " + (dir / "extended" / "case.toml").string() + " --restart " +
                    out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("restarting from step 20"), std::string::npos) << r.output;
  expect_same_bits(tc::test::read_history(full / "history.csv"),
                   tc::test::read_history(out / "history.csv"), "extended");
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"completed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"steps_done\": 40"), std::string::npos) << summary;
}

TEST(Restart, AChangedKeyIsRefusedByNameAndACommentIsNot) {
  const auto dir = tc::test::fresh_dir("restart-keys");
  const auto c = sliding_until(dir, "8.0e-3");
  const auto out = dir / "out";
  auto r = thermocontact(run_args(c, out) + " --set contact.friction=0.25 --stop-after 2");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  const auto text = tc::test::read_file(c);
  const auto before = tc::test::read_file(out / "history.csv");
  // A material constant changed: refused, the key and both values named.
  std::ofstream(dir / "case.toml")
      << tc::test::replace_all(text, "young_modulus = 2.0e11", "young_modulus = 2.1e11");
  r = thermocontact("run " + c.string() + " --restart " + out.string() +
                    " --set contact.friction=0.25");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("materials.steel.young_modulus: 200000000000 in the checkpoint's run, "
                          "210000000000 now"),
            std::string::npos)
      << r.output;
  // The --set of the stopped run left out (or changed): refused naming it.
  std::ofstream(dir / "case.toml") << text;
  r = thermocontact("run " + c.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(
                "contact.friction: 0.25 (--set) in the checkpoint's run, 0.29999999999999999 now"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(tc::test::read_file(out / "history.csv"), before);
  // Comments and layout are not the case: accepted with the same --set.
  std::ofstream(dir / "case.toml")
      << "# a comment added after the stop\n"
      << tc::test::replace_all(text, "friction = 0.3", "friction    =    0.3  # dry");
  r = thermocontact("run " + c.string() + " --restart " + out.string() +
                    " --set contact.friction=0.25");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // Shortened before its checkpoint: refused, naming time.end.
  r = thermocontact("run " + c.string() + " --restart " + out.string() +
                    " --set contact.friction=0.25 --set time.end=2.0e-4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("time.end"), std::string::npos) << r.output;
}

}  // namespace
