// Issue 42, security and data loss (docs/robustness.md, "Output safety, issue 42"): files
// written through links planted in the output directory (D1), a lock defeated by deleting its
// file and a run reported done after its directory was deleted (D2), restarts that wrote a
// history with a gap or lost result.pvd (D3), a missing history.csv (D11), a full disk during
// a restart (D12), summary.json after mpirun is killed (issue 41, point 6), and the output
// items "also seen": `--output /`, control characters echoed, a 10 MB title.
//
// Every test runs the binary as a user would. TC_TEST_BINARY, when set, names another binary
// to run instead (to check that a test fails on an older one).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::read_file;
using tc::test::replace_all;

namespace {

std::string binary() {
  const char* other = std::getenv("TC_TEST_BINARY");
  return other != nullptr && *other != '\0' ? other : TC_BINARY;
}

tc::test::CommandResult run(const std::string& args) {
  // A time limit: a regression must fail the test, not hang it.
  return tc::test::run_command("timeout -k 10 120 " + binary() + " " + args);
}

const fs::path sliding = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";
constexpr size_t sliding_rows = 41;  // steps 0 … 40

/// One dynamic 2D body, 6 steps, fields every step: each file a run writes, in a fraction of
/// a second.
const std::string kCase = R"(dimension = 2
[time]
scheme = "dynamic"
step = 1e-4
end = 6e-4
[materials.m]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "b"
material = "m"
mesh = { box = { min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2] } }
initial_temperature = 300.0
[[boundary]]
body = "b"
where = "ymin"
displacement = [0.0, 0.0]
[[boundary]]
body = "b"
where = "ymax"
traction = [0.0, -1.0e6]
)";
constexpr int kSteps = 6;

fs::path write_case(const fs::path& dir, const std::string& text = kCase) {
  const auto file = dir / "case.toml";
  std::ofstream(file) << text;
  return file;
}

const std::string kPrecious = "precious\n";

/// A file outside the output directory that a planted link points to.
fs::path victim(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir / "victims");
  const auto file = dir / "victims" / name;
  std::ofstream(file) << kPrecious;
  return file;
}

// ---- D1: planted links -------------------------------------------------------------------

// Each name a run creates or truncates in its directory, with a symbolic link planted there
// to a file outside: the old binary wrote the summary into the victim (summary.json.tmp),
// truncated it to zero (.lock), and so on for each.
TEST(Issue42IoLinks, ANewRunWritesThroughNoLinkPlantedInItsDirectory) {
  const auto dir = tc::test::fresh_dir("i42-links-new");
  const auto c = write_case(dir);
  // (summary.stopped.json, written in place without a temporary, is a run's own output name:
  // planted in a new directory it makes that directory an earlier run's; the restart test
  // below plants it.)
  for (const std::string name :
       {".lock", "summary.json.tmp", "result.pvd.tmp", "history.csv.tmp"}) {
    const auto out = dir / ("out" + name);
    fs::create_directories(out);
    const auto target = victim(dir, name);
    fs::create_symlink(target, out / name);
    const auto r = run("run " + c.string() + " --output " + out.string());
    EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.output;
    EXPECT_EQ(read_file(target), kPrecious) << "written through the link " << name;
    EXPECT_FALSE(fs::is_symlink(out / name)) << name;
    EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), size_t{kSteps + 1}) << name;
  }
  // A hard link is a name of the victim too: it is replaced, not written into.
  const auto out = dir / "out-hard";
  fs::create_directories(out);
  const auto target = victim(dir, "hard");
  fs::create_hard_link(target, out / "summary.json.tmp");
  const auto r = run("run " + c.string() + " --output " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_file(target), kPrecious) << "written through a hard link";
}

// On --restart also checkpoint.bin.tmp and the .vtu of the steps not yet written.
TEST(Issue42IoLinks, ARestartWritesThroughNoLinkPlantedInItsDirectory) {
  const auto dir = tc::test::fresh_dir("i42-links-restart");
  const auto c = write_case(dir);
  const auto out = dir / "out";
  auto r = run("run " + c.string() + " --output " + out.string() + " --stop-after 2");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  const std::vector<std::string> names{"checkpoint.bin.tmp",
                                       "b_000004.vtu",
                                       "summary.json.tmp",
                                       "summary.stopped.json",
                                       "result.pvd.tmp",
                                       "history.csv.tmp",
                                       ".lock"};
  for (const auto& name : names) {
    fs::remove(out / name);
    fs::create_symlink(victim(dir, name), out / name);
  }
  r = run("run " + c.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const auto& name : names) {
    EXPECT_EQ(read_file(dir / "victims" / name), kPrecious) << "written through " << name;
    EXPECT_FALSE(fs::is_symlink(out / name)) << name;
  }
  EXPECT_TRUE(tc::test::whole_vtu(out / "b_000004.vtu"));
  EXPECT_EQ(tc::test::read_history(out / "history.csv").rows.size(), size_t{kSteps + 1});
}

// ---- D2: the lock and the directory of a run ----------------------------------------------

/// `thermocontact run CASE --output DIR` as a child process, its output to `log`.
pid_t start_run(const fs::path& case_file, const fs::path& out, const fs::path& log) {
  const std::string b = binary(), c = case_file.string(), d = out.string(), l = log.string();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(l.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execl(b.c_str(), b.c_str(), "run", c.c_str(), "--output", d.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// Starts the sliding case (41 rows, a few seconds) into `out` and freezes it (SIGSTOP) once
/// it has written two rows: it then surely holds its directory, and whatever is done to the
/// directory happens between two of its writes.
pid_t start_and_freeze(const fs::path& out, const fs::path& log) {
  const pid_t pid = start_run(sliding, out, log);
  for (;;) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    if (tc::test::read_history(out / "history.csv").rows.size() >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  kill(pid, SIGSTOP);
  return pid;
}

int resume_and_wait(pid_t pid) {
  kill(pid, SIGCONT);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `rm DIR/.lock` and a second run with --force: the old binary admitted it; it removed the
// first run's files, and the first said `done` over a history holding the second's rows.
TEST(Issue42IoLock, DeletingTheLockFileDoesNotAdmitASecondRun) {
  const auto dir = tc::test::fresh_dir("i42-lock-file");
  const auto out = dir / "out";
  const pid_t first = start_and_freeze(out, dir / "first.log");
  ASSERT_GT(first, 0) << read_file(dir / "first.log");
  fs::remove(out / ".lock");
  const auto second = run("run " + sliding.string() + " --output " + out.string() + " --force");
  const int code = resume_and_wait(first);
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find("output directory " + out.string() + " is in use"),
            std::string::npos)
      << second.output;
  EXPECT_EQ(code, 0) << read_file(dir / "first.log");
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_EQ(h.rows.size(), sliding_rows);
  for (size_t k = 0; k < h.rows.size(); ++k) EXPECT_EQ(h.rows[k][0], static_cast<double>(k));
}

// `rm -rf DIR` during a run, and DIR made again (by hand, or by a second run): the old
// binary appended its rows to the deleted history.csv, wrote its other files into the new
// DIR, and ended with `done`, exit 0, and no history.csv there.
TEST(Issue42IoLock, ARunWhoseDirectoryIsDeletedAndMadeAgainDoesNotEndAsDone) {
  const auto dir = tc::test::fresh_dir("i42-rm-mkdir");
  const auto out = dir / "out";
  const pid_t first = start_and_freeze(out, dir / "first.log");
  ASSERT_GT(first, 0) << read_file(dir / "first.log");
  fs::remove_all(out);
  fs::create_directories(out);
  const int code = resume_and_wait(first);
  const auto log = read_file(dir / "first.log");
  EXPECT_EQ(code, 1) << log;
  EXPECT_EQ(log.find("done:"), std::string::npos) << log;
  EXPECT_NE(log.find("was deleted or replaced during the run"), std::string::npos) << log;
  // Nothing of the first run's went into the new directory (it may be another run's).
  EXPECT_TRUE(fs::is_empty(out)) << fs::directory_iterator(out)->path();
}

// `rm -rf DIR` alone: exit 1 and why (the old binary said "cannot create DIR/…tmp: No such
// file or directory", or `done` when the timing let it recreate files).
TEST(Issue42IoLock, ARunWhoseDirectoryIsDeletedEndsWithExitOneSayingSo) {
  const auto dir = tc::test::fresh_dir("i42-rm");
  const auto out = dir / "out";
  const pid_t first = start_and_freeze(out, dir / "first.log");
  ASSERT_GT(first, 0) << read_file(dir / "first.log");
  fs::remove_all(out);
  const int code = resume_and_wait(first);
  const auto log = read_file(dir / "first.log");
  EXPECT_EQ(code, 1) << log;
  EXPECT_NE(log.find("was deleted or replaced during the run"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
}

// ---- D3, D11: what a restart continues -------------------------------------------------------

/// A run of kCase into `out` stopped after step `k` (rows 0 … k, checkpoint of step k).
void stopped_run(const fs::path& c, const fs::path& out, int k) {
  const auto r =
      run("run " + c.string() + " --output " + out.string() + " --stop-after " + std::to_string(k));
  ASSERT_EQ(r.exit_code, 1) << r.output;
}

/// The first `rows` lines of `file` after its header, written back.
void keep_rows(const fs::path& file, size_t rows) {
  std::istringstream in(read_file(file));
  std::string text, line;
  for (size_t i = 0; i <= rows && std::getline(in, line); ++i) text += line + '\n';
  std::ofstream(file) << text;
}

TEST(Issue42IoRestart, AHistoryEndingBeforeTheCheckpointIsRefused) {
  // The issue's case: a completed run whose history is cut to steps 0 … 1: the old binary
  // wrote steps 0, 1, then 6 (`done`, exit 0).
  const auto dir = tc::test::fresh_dir("i42-gap");
  const auto c = write_case(dir);
  const auto out = dir / "out";
  auto r = run("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  keep_rows(out / "history.csv", 2);
  const auto before = read_file(out / "history.csv");
  r = run("run " + c.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("history.csv ends at step 1, before the checkpoint's step 6"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(read_file(out / "history.csv"), before) << "a refused restart changed the history";

  // A newer checkpoint copied into a run stopped after step 2.
  const auto older = dir / "older";
  stopped_run(c, older, 2);
  fs::copy_file(out / "checkpoint.bin", older / "checkpoint.bin",
                fs::copy_options::overwrite_existing);
  r = run("run " + c.string() + " --restart " + older.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("ends at step 2, before the checkpoint's step 6"), std::string::npos)
      << r.output;

  // A row missing in the middle.
  const auto holed = dir / "holed";
  stopped_run(c, holed, 4);
  auto text = read_file(holed / "history.csv");
  const auto row2 = text.find("\n2,") + 1;
  text.erase(row2, text.find('\n', row2) + 1 - row2);
  std::ofstream(holed / "history.csv") << text;
  r = run("run " + c.string() + " --restart " + holed.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("jumps from step 1 to step 3"), std::string::npos) << r.output;

  // The limit of the refusal: rows 0 … k−1 are enough (row k is written again).
  const auto ok = dir / "no-gap";
  stopped_run(c, ok, 3);
  keep_rows(ok / "history.csv", 3);  // steps 0, 1, 2
  r = run("run " + c.string() + " --restart " + ok.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto h = tc::test::read_history(ok / "history.csv");
  ASSERT_EQ(h.rows.size(), size_t{kSteps + 1});
  for (size_t k = 0; k < h.rows.size(); ++k) EXPECT_EQ(h.rows[k][0], static_cast<double>(k));
}

TEST(Issue42IoRestart, AMissingHistoryIsSaidToBeMissingWithExitTwo) {
  // D11: the old binary said "its header is not this case's", exit 1.
  const auto dir = tc::test::fresh_dir("i42-missing");
  const auto c = write_case(dir);
  const auto out = dir / "out";
  stopped_run(c, out, 2);
  fs::remove(out / "history.csv");
  const auto r = run("run " + c.string() + " --restart " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((out / "history.csv").string() + " is missing"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out / "history.csv"));
}

TEST(Issue42IoRestart, ADeletedOrGarbledCollectionIsRebuiltFromTheFieldFiles) {
  // The old binary replaced it by a collection listing only the steps after the checkpoint.
  const auto dir = tc::test::fresh_dir("i42-pvd");
  const auto c = write_case(dir);
  const auto full = dir / "full";
  auto r = run("run " + c.string() + " --output " + full.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto expected = tc::test::read_collection(full / "result.pvd");
  ASSERT_EQ(expected.files.size(), size_t{kSteps + 1});
  for (const bool garble : {false, true}) {
    const auto out = dir / (garble ? "garbled" : "deleted");
    stopped_run(c, out, 3);
    if (garble) {  // cut in the middle of a data set's line, as a full disk or an editor would
      const auto text = read_file(out / "result.pvd");
      std::ofstream(out / "result.pvd") << text.substr(0, text.size() / 2);
    } else {
      fs::remove(out / "result.pvd");
    }
    r = run("run " + c.string() + " --restart " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("was missing or damaged: rebuilt from the 4 data set(s)"),
              std::string::npos)
        << r.output;
    const auto got = tc::test::read_collection(out / "result.pvd");
    EXPECT_TRUE(got.whole);
    EXPECT_EQ(got.files, expected.files) << (garble ? "garbled" : "deleted");
    EXPECT_EQ(got.times, expected.times);
  }
}

// ---- D12: a full disk during a restart -------------------------------------------------------

/// Whether this machine lets an unprivileged-looking process mount a tmpfs in its own user and
/// mount namespaces (unshare -rm): a real full disk without being root.
bool can_mount_tmpfs() {
  const auto r = tc::test::run_command(
      "unshare -rm sh -c 'd=$(mktemp -d) && mount -t tmpfs -o size=64k tmpfs $d && umount $d "
      "&& rmdir $d'");
  return r.exit_code == 0;
}

TEST(Issue42IoFullDisk, ARestartOnAFullDiskLeavesASummaryThatSaysWhatHappened) {
  // A real full disk (ENOSPC): a small tmpfs holding a stopped run, filled up but for a few
  // pages, then --restart. The old binary left summary.json "running" with the restored step
  // as steps_done, and a summary.stopped.json that blamed "a second stop signal".
  if (!can_mount_tmpfs()) GTEST_SKIP() << "no tmpfs in a user namespace here (unshare -rm)";
  const auto dir = tc::test::fresh_dir("i42-full");
  const auto c = write_case(dir, replace_all(kCase, "end = 6e-4", "end = 6e-2"));  // 600 steps
  const auto stopped = dir / "stopped";
  stopped_run(c, stopped, 2);
  const auto mnt = dir / "mnt", kept = dir / "kept";
  fs::create_directories(mnt);
  fs::create_directories(kept);
  // 16 kB left: the restart's first writes fit (history.csv and the summary are rewritten
  // through temporary files, each old copy freed by its rename); the .vtu of every step,
  // about 2.6 kB each, then fill the disk within a few steps.
  const std::string script =
      "mount -t tmpfs -o size=1m tmpfs " + mnt.string() + " && cp -a " + stopped.string() + " " +
      mnt.string() + "/r && (cat /dev/zero > " + mnt.string() + "/fill 2>/dev/null; true) && " +
      "truncate -s -16k " + mnt.string() + "/fill && PMIX_MCA_gds=hash " + binary() + " run " +
      c.string() + " --restart " + mnt.string() + "/r; echo \"exit=$?\"; cp -a " + mnt.string() +
      "/r/. " + kept.string() + "/";
  const auto r = tc::test::run_command("unshare -rm bash -c '" + script + "'");
  EXPECT_NE(r.output.find("exit=1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  const auto h = tc::test::read_history(kept / "history.csv");
  ASSERT_TRUE(h.whole);
  ASSERT_GT(h.rows.size(), 3u) << "the restart wrote no row: too little room left\n" << r.output;
  const auto summary = read_file(kept / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"steps_done\": " + std::to_string(h.rows.size() - 1) + ","),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("No space left on device"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("second stop signal"), std::string::npos) << summary;
}

// ---- issue 41, point 6: summary.json after mpirun is killed ---------------------------------

/// The sliding case on finer meshes (about 0.3 s a step on one rank) and 4000 steps: still in
/// a step whenever a signal comes, and still running at the end of any test.
fs::path slow_sliding(const fs::path& dir) {
  const auto c = dir / "slow.toml";
  std::ofstream(c) << replace_all(
      replace_all(replace_all(read_file(sliding), "end = 8.0e-3", "end = 8.0e-1"), "cells = [5, 2]",
                  "cells = [40, 16]"),
      "cells = [12, 3]", "cells = [96, 24]");
  return c;
}

/// Runs `argv` as a child process (its output to `log`), waits until `out`/history.csv holds
/// two rows, sends SIGTERM, then SIGKILL to its process group unless it ended within `grace`:
/// a kill soon after a stop signal, as mpirun sends its ranks when it gets SIGTERM (from
/// `timeout`, a batch system).
void term_then_kill(const std::vector<std::string>& argv, const fs::path& out, const fs::path& log,
                    std::chrono::milliseconds grace) {
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);  // its own process group: the kill reaches mpirun and its ranks
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  for (;;) {
    ASSERT_NE(waitpid(pid, &status, WNOHANG), pid) << "ended early, status " << status << "\n"
                                                   << read_file(log);
    if (tc::test::read_history(out / "history.csv").rows.size() >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      kill(-pid, SIGKILL);  // ranks left behind, if any
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  kill(-pid, SIGKILL);
  waitpid(pid, &status, 0);
}

/// summary.json says "stopped" after the last row written (or the one before, when the kill
/// came between a row and the summary's rename).
void expect_stopped_summary(const fs::path& out, const fs::path& log) {
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_GE(h.rows.size(), 2u);
  const auto summary = read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos)
      << summary << read_file(log);
  const auto done = std::to_string(h.rows.size() - 1), before = std::to_string(h.rows.size() - 2);
  EXPECT_TRUE(summary.find("\"steps_done\": " + done + ",") != std::string::npos ||
              summary.find("\"steps_done\": " + before + ",") != std::string::npos)
      << summary << "rows " << h.rows.size();
}

TEST(Issue42IoSignals, SummarySaysStoppedWhenAKillFollowsTheStopSignal) {
  // One rank, SIGTERM then SIGKILL 30 ms later, inside a step of about 0.3 s: the old
  // binary's summary.json said "running".
  const auto dir = tc::test::fresh_dir("i42-term-kill");
  const auto out = dir / "out";
  term_then_kill({binary(), "run", slow_sliding(dir).string(), "--output", out.string()}, out,
                 dir / "log", std::chrono::milliseconds(30));
  expect_stopped_summary(out, dir / "log");
}

TEST(Issue42IoSignals, SummarySaysStoppedAfterMpirunIsStopped) {
  // `timeout` sends SIGTERM to mpirun, which passes it to the ranks and kills them soon after
  // (the old binary's summary.json said "running"). Two ranks; mpirun ends by itself, the
  // group is killed after 30 s only should it hang.
  const auto dir = tc::test::fresh_dir("i42-mpirun");
  const auto out = dir / "out";
  // A clean environment: this process is an MPI singleton, whose OMPI_/PMIX_ variables the
  // launcher would take for a job it belongs to (feti_mpi_cli_test). Root allowed, as in CI.
  term_then_kill({"env", "-i", "PATH=/usr/bin:/bin", "HOME=/tmp", "OPENBLAS_NUM_THREADS=1",
                  "OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                  "OMPI_MCA_rmaps_base_oversubscribe=1", TC_MPIEXEC, "-n", "2", binary(), "run",
                  slow_sliding(dir).string(), "--output", out.string()},
                 out, dir / "log", std::chrono::seconds(30));
  expect_stopped_summary(out, dir / "log");
}

// ---- also seen ---------------------------------------------------------------------------------

TEST(Issue42IoOutput, TheRootAndTheSystemsDirectoriesAreRefusedAsOutput) {
  // As root, `--output /` wrote .lock, history.csv and the fields into /. /srv first: a
  // binary without the check writes there only (checked under a private tmpfs on /srv).
  const auto dir = tc::test::fresh_dir("i42-root");
  const auto c = write_case(dir);
  for (const std::string out : {"/srv", "/", "/usr/", "/proc/self"}) {
    const auto r = run("run " + c.string() + " --output " + out);
    ASSERT_EQ(r.exit_code, 2) << out << "\n" << r.output;
    EXPECT_NE(r.output.find("expected a directory of the run's own"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(fs::path(out) / "history.csv")) << out;
  }
}

TEST(Issue42IoOutput, ControlCharactersInTheOutputPathAreEscapedWhenPrinted) {
  // A newline and an escape sequence (red text) in the directory's name reached the terminal.
  const auto dir = tc::test::fresh_dir("i42-escape");
  const auto c = write_case(dir);
  const auto out = dir / "a\nb\x1b[31mred";
  const auto r = run("run " + c.string() + " --output '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "history.csv"));
  EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a\\x0Ab\\x1B[31mred"), std::string::npos) << r.output;
}

TEST(Issue42IoOutput, ATitleBeyond4096CharactersIsRefusedNamingTheKey) {
  // A 10 MB title was copied into summary.json after every step (0.25 s a step).
  const auto dir = tc::test::fresh_dir("i42-title");
  const auto c = write_case(dir, "title = \"" + std::string(4097, 't') + "\"\n" + kCase);
  const auto r = run("check " + c.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(": title: found a title of 4097 characters, expected at most 4096"),
            std::string::npos)
      << r.output.substr(0, 2000);
  const auto ok = write_case(dir, "title = \"" + std::string(4096, 't') + "\"\n" + kCase);
  EXPECT_EQ(run("check " + ok.string()).exit_code, 0);
}

}  // namespace
