// Abuse of the command line (issue 20, docs/robustness.md): two runs into one output
// directory, a disk that fills up, results that overflow, PETSc's floating-point traps. Each
// test runs the binary as a user would and checks the exit code, the message and the files.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
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

}  // namespace
