// Abuse of the command line (issue 20, docs/robustness.md): two runs into one output
// directory (#1), a disk that fills up (#2), results that overflow (#9), PETSc's
// floating-point traps (#16). Each test runs the binary as a user would and checks the exit
// code, the message and the files.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const fs::path sliding = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";
constexpr size_t sliding_rows = 41;  // steps 0 … 40

/// `thermocontact run CASE --output|--restart DIR` as a child process, its output to a file.
pid_t start_run(const fs::path& case_file, const char* mode, const fs::path& dir,
                const fs::path& log) {
  const std::string binary = TC_BINARY, c = case_file.string(), d = dir.string(), l = log.string();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(l.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execl(binary.c_str(), binary.c_str(), "run", c.c_str(), mode, d.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// Waits until history.csv in `dir` has `rows` rows (header aside); false if `pid` ended first.
bool wait_for_rows(pid_t pid, const fs::path& dir, size_t rows, int& status) {
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    if (tc::test::read_history(dir / "history.csv").rows.size() >= rows) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

int exit_code(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// ---- #1: one run per output directory ----------------------------------------------------

TEST(AbuseCli, ASecondRunIntoABusyOutputDirectoryIsRefused) {
  // The first run is frozen (SIGSTOP) once it has written two rows, so it certainly holds
  // the directory while the second run and a --restart into it are tried.
  const auto dir = tc::test::fresh_dir("abuse-busy");
  const auto out = dir / "out";
  const pid_t first = start_run(sliding, "--output", out, dir / "first.log");
  int status = 0;
  ASSERT_TRUE(wait_for_rows(first, out, 2, status)) << tc::test::read_file(dir / "first.log");
  ASSERT_EQ(kill(first, SIGSTOP), 0);
  const auto pid = std::to_string(first);
  EXPECT_EQ(tc::test::read_file(out / ".lock"), pid + "\n");
  const auto second = thermocontact("run " + sliding.string() + " --output " + out.string());
  const auto restart = thermocontact("run " + sliding.string() + " --restart " + out.string());
  kill(first, SIGCONT);
  ASSERT_EQ(waitpid(first, &status, 0), first);
  const std::string busy = "output directory " + out.string() + " is in use by pid " + pid;
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find(busy), std::string::npos) << second.output;
  EXPECT_EQ(restart.exit_code, 2) << restart.output;
  EXPECT_NE(restart.output.find(busy), std::string::npos) << restart.output;
  // The first run was not disturbed: every step in history.csv, once.
  EXPECT_EQ(exit_code(status), 0) << tc::test::read_file(dir / "first.log");
  const auto h = tc::test::read_history(out / "history.csv");
  EXPECT_TRUE(h.whole);
  ASSERT_EQ(h.rows.size(), sliding_rows);
  for (size_t k = 0; k < h.rows.size(); ++k) EXPECT_EQ(h.rows[k][0], static_cast<double>(k));
  EXPECT_NE(tc::test::read_file(out / "summary.json").find("\"status\": \"completed\""),
            std::string::npos);
  // Released at exit: the file names no one and the next run may write there.
  EXPECT_EQ(tc::test::read_file(out / ".lock"), "");
}

TEST(AbuseCli, TheLockOfAKilledRunDoesNotBlockItsRestart) {
  // SIGKILL leaves .lock with the dead run's pid; the kernel released its flock, so the
  // restart goes ahead.
  const auto dir = tc::test::fresh_dir("abuse-stale");
  const auto out = dir / "out";
  const pid_t first = start_run(sliding, "--output", out, dir / "first.log");
  int status = 0;
  ASSERT_TRUE(wait_for_rows(first, out, 3, status)) << tc::test::read_file(dir / "first.log");
  kill(first, SIGKILL);
  waitpid(first, &status, 0);
  EXPECT_EQ(tc::test::read_file(out / ".lock"), std::to_string(first) + "\n");
  const auto r = thermocontact("run " + sliding.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), sliding_rows);
}

// ---- #2: a full disk ------------------------------------------------------------------------

/// A plate of 20 × 20 cells: its .vtu files (67 kB at t = 0, 171 kB after) are larger than
/// fmt's 32 kB output buffer, which made the old writer throw out of a destructor (SIGABRT).
const char* const plate = R"(
dimension = 2
[time]
scheme = "dynamic"
step = 1e-5
end = 1e-4
[materials.steel]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1.2e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "plate"
material = "steel"
mesh = { box = { min = [0.0, 0.0], max = [0.1, 0.1], cells = [20, 20] } }
initial_temperature = 350.0
[[boundary]]
body = "plate"
where = "ymin"
displacement = [0.0, 0.0]
[[boundary]]
body = "plate"
where = "ymax"
traction = [0.0, -1.0e6]
)";

/// `run CASE --output DIR` with files limited to `kilobytes` (ulimit -f): a write beyond it
/// fails with EFBIG as a full disk fails with ENOSPC. SIGXFSZ is ignored in the shell, as a
/// batch system would, so the write fails instead of the signal killing the run. PMIx keeps
/// its data in memory (gds=hash) instead of files that the limit would forbid in MPI_Init.
tc::test::CommandResult run_with_file_limit(const fs::path& case_file, const fs::path& out,
                                            int kilobytes, const std::string& options = "") {
  return tc::test::run_command("PMIX_MCA_gds=hash bash -c \"trap '' XFSZ; ulimit -f " +
                               std::to_string(kilobytes) + "; exec " + TC_BINARY + " run " +
                               case_file.string() + " --output " + out.string() + options + "\"");
}

/// What a run stopped by a failed write must leave: exit 1 and the reason, summary.json
/// "stopped" with the steps whose rows are written, whole files, no temporary file.
void expect_stopped_by_the_limit(const tc::test::CommandResult& r, const fs::path& out,
                                 const std::string& file) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stopped: cannot write " + (out / file).string() + ": File too large"),
            std::string::npos)
      << r.output;
  const auto h = tc::test::read_history(out / "history.csv");
  EXPECT_TRUE(h.whole) << "a partial row in history.csv";
  ASSERT_FALSE(h.rows.empty());
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("File too large"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"steps_done\": " + std::to_string(h.rows.size() - 1) + ","),
            std::string::npos)
      << summary;
  EXPECT_NE(r.output.find("output of the " + std::to_string(h.rows.size() - 1) + " completed"),
            std::string::npos)
      << r.output;
  const auto pvd = tc::test::read_collection(out / "result.pvd");
  EXPECT_TRUE(pvd.whole);
  EXPECT_FALSE(pvd.files.empty());
  for (const auto& f : pvd.files) EXPECT_TRUE(tc::test::whole_vtu(out / f)) << f;
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

TEST(AbuseCli, AFullDiskWhileWritingFieldsStopsTheRunWithExitOne) {
  // 100 kB: the history, the summary, the checkpoint (39 kB) and the fields at t = 0 (67 kB)
  // fit, the fields of step 1 (171 kB) do not. The old writer aborted (exit 134), summary.json
  // "running".
  const auto dir = tc::test::fresh_dir("abuse-full-fields");
  std::ofstream(dir / "plate.toml") << plate;
  const auto out = dir / "out";
  const auto r = run_with_file_limit(dir / "plate.toml", out, 100);
  expect_stopped_by_the_limit(r, out, "plate_000001.vtu");
  EXPECT_FALSE(fs::exists(out / "plate_000001.vtu")) << "the partial file was left";
  EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), 2u);
  // The steps done are usable: the run continues from them once there is room.
  const auto again =
      thermocontact("run " + (dir / "plate.toml").string() + " --restart " + out.string());
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), 11u);
}

TEST(AbuseCli, AFullDiskWhileAppendingToTheHistoryLeavesNoPartialRow) {
  // 12 kB: every .vtu (≤ 9 kB zlib-compressed; 20.5 kB in ASCII since the stress and strain
  // tensors) and the checkpoint (9.5 kB) fit; history.csv (16.7 kB whole) reaches the limit
  // in the middle of a row, which must be cut off again.
  const auto dir = tc::test::fresh_dir("abuse-full-history");
  const auto out = dir / "out";
  const auto r = run_with_file_limit(sliding, out, 12, " --set output.compression='\\\"zlib\\\"'");
  expect_stopped_by_the_limit(r, out, "history.csv");
  EXPECT_LT(tc::test::read_history(out / "history.csv").rows.size(), sliding_rows);
}

// ---- #9: results that overflow -------------------------------------------------------------

/// Runs tests/cases/valid/plane-strain-2d.toml with `from` replaced by `to` and checks that
/// the run stops at step 1 naming a history column that is not finite, with exit 1, and
/// leaves only finite rows (step 0's) in history.csv. The state stays finite (~1e282–1e298):
/// only the energies and the work derived from it overflow, which passed as "completed".
void expect_refused_history_row(const std::string& name, const std::string& from,
                                const std::string& to, const std::string& appended = "") {
  const auto dir = tc::test::fresh_dir(name);
  const auto text =
      tc::test::read_file(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/plane-strain-2d.toml");
  ASSERT_NE(text.find(from), std::string::npos);
  std::ofstream(dir / "case.toml") << tc::test::replace_all(text, from, to) << appended;
  const auto out = dir / "out";
  const auto r = thermocontact("run " + (dir / "case.toml").string() + " --output " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const std::regex named(
      R"(stopped: history: [a-z_]+ is not finite \((NaN|\+Inf|-Inf)\) \(step 1, t = 0\.001 s\))");
  EXPECT_TRUE(std::regex_search(r.output, named)) << r.output;
  EXPECT_NE(r.output.find("output of the 0 completed step(s)"), std::string::npos) << r.output;
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"steps_done\": 0,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("is not finite"), std::string::npos) << summary;
  const auto h = tc::test::read_history(out / "history.csv");
  EXPECT_TRUE(h.whole);
  ASSERT_EQ(h.rows.size(), 1u);
  for (const double v : h.rows[0]) EXPECT_TRUE(std::isfinite(v));
}

TEST(AbuseCli, AnOverflowingTractionStopsTheRunNamingTheColumn) {
  expect_refused_history_row(
      "abuse-traction",
      R"(traction = [{ t = [0.0, 0.004, 0.01], value = [0.0, 2.0e6, 2.0e6] }, "free"])",
      R"(traction = [1e300, "free"])",
      // Without it the thermoelastic heating of the 1e300 N load takes θ below 0 K, which
      // stops the run one check earlier (issue 42 D10; tests/system/issue42_input_test.cpp).
      "[physics]\nthermoelastic_heating = false\n");
}

TEST(AbuseCli, AnOverflowingHeatSourceStopsTheRunNamingTheColumn) {
  expect_refused_history_row("abuse-heat-source",
                             "heat_source = { t = [0.0, 0.005], value = [0.0, 1.0e6] }",
                             "heat_source = { t = [0.0, 0.005], value = [0.0, 1.0e308] }");
}

// ---- #16: PETSc's floating-point traps ----------------------------------------------------

TEST(AbuseCli, TheContactPatchRunsUnderFloatingPointTraps) {
  // -fp_trap makes an invalid operation, a division by zero or an overflow abort the run.
  // FeasibleSet::split_gradient formed ∞ − ∞ (the activity tolerance of an infinite bound,
  // discarded, but trapped): exit 72, "floating point error", at the first contact QP.
  const auto out = tc::test::fresh_dir("abuse-fp-trap");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + out.string() + " -fp_trap");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("floating point"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("was not used"), std::string::npos) << r.output;  // PETSc read it
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"completed\""), std::string::npos) << summary;
}

}  // namespace
